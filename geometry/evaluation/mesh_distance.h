// Queries against a triangle mesh surface: unsigned distance from points to the surface, the
// side (inside / outside) of points with respect to the solid a closed mesh bounds, and seeded,
// area-weighted random samples on the surface. Batched over many points, in parallel, with
// results in input order (independent of the thread count).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

/// Rows of equally spaced points (a grid's layer): row r holds starts[r] + i * step for i in
/// [0, count), in that order (world mm).
struct PointRows {
  std::vector<Vec3> starts;
  Vec3 step = Vec3::Zero();
  int count = 0;
  std::size_t size() const { return starts.size() * std::size_t(count < 0 ? 0 : count); }
  Vec3 at(std::size_t n) const { return starts[n / std::size_t(count)] + double(n % std::size_t(count)) * step; }
};

/// An immutable search structure (an AABB tree over the triangles) built once for a mesh;
/// queries are thread-safe. Copies share the structure.
class MeshDistance {
 public:
  /// @param mesh triangle mesh in mm; for inside() it must be closed and consistently oriented
  ///             (a non-closed mesh gives an unspecified side for some points). Must have at
  ///             least one triangle (std::invalid_argument otherwise).
  explicit MeshDistance(const TriangleMesh& mesh);
  ~MeshDistance();
  MeshDistance(const MeshDistance&) = default;
  MeshDistance& operator=(const MeshDistance&) = default;

  /// Euclidean distance (mm) from each point (world mm) to the nearest point of the surface.
  std::vector<double> distances(const std::vector<Vec3>& points) const;
  /// Nearest surface point (world mm) of each point.
  std::vector<Vec3> closestPoints(const std::vector<Vec3>& points) const;
  /// 1 where the point is inside the solid or on its boundary, 0 outside.
  std::vector<std::uint8_t> inside(const std::vector<Vec3>& points) const;
  /// inside() of every point of `rows`, row by row, the same answers at a fraction of the cost:
  /// one segment query per row finds the surface's crossings (the triangles it meets are found by
  /// exact predicates), and one side test answers for every point of a stretch between two
  /// crossings (no surface lies between them). Points within 1e-6 of a step of a crossing are
  /// tested one by one. Measured: the Dice grid of 228x216x161 points on a 430,000-triangle mesh,
  /// 1.9 s by inside() point by point, 0.66 s row by row.
  std::vector<std::uint8_t> insideRows(const PointRows& rows) const;

 private:
  struct Impl;
  std::shared_ptr<const Impl> impl_;
};

/// `count` points (world mm) on the surface, uniformly distributed by area: a triangle is drawn
/// with probability proportional to its area, then a uniform point in it. Deterministic for a
/// given mesh, count and seed. Empty when the mesh has no area.
std::vector<Vec3> sampleSurface(const TriangleMesh& mesh, std::size_t count, std::uint64_t seed);

/// Total surface area in mm².
double surfaceArea(const TriangleMesh& mesh);

}  // namespace xsect

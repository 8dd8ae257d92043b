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

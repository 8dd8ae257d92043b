// Accuracy measures of a reconstructed mesh against a truth shape, given either as a signed
// distance function (an analytic phantom) or as a reference mesh: one-sided and symmetric surface
// distances (Hausdorff and mean) from seeded surface samples, and Dice / IoU of the two solids on
// a voxel grid. Pure computations: no files; deterministic for any thread count.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <vector>

#include "geometry/evaluation/mesh_distance.h"
#include "geometry/core/types.h"

namespace xsect {

/// Signed distance (mm) of a world point (mm) to a surface, negative inside; must be thread-safe.
using SignedDistanceFn = std::function<double(const Vec3&)>;
/// For rows of world points (mm; a grid's layer, mesh_distance.h): 1 inside the solid, 0 outside,
/// in the rows' order; must be thread-safe.
using InsideFn = std::function<std::vector<std::uint8_t>(const PointRows&)>;

/// Distances from the points of one surface to the other surface (mm).
struct OneSidedDistance {
  double max_mm = 0.0;   ///< over all sample points and vertices
  double mean_mm = 0.0;  ///< over area-uniform samples only (vertices excluded)
  std::size_t points = 0;  ///< number of points the maximum was taken over
};

struct SurfaceDistances {
  OneSidedDistance mesh_to_truth, truth_to_mesh;
  double hausdorffMm() const { return std::max(mesh_to_truth.max_mm, truth_to_mesh.max_mm); }
  /// Symmetric mean: average of the two one-sided means.
  double meanMm() const { return 0.5 * (mesh_to_truth.mean_mm + truth_to_mesh.mean_mm); }
};

struct SamplingParams {
  std::size_t surface_samples = 100000;  ///< area-uniform samples on each mesh surface
  std::size_t zero_set_starts = 100000;  ///< starting points projected onto an implicit surface
  std::uint64_t seed = 1;                ///< seed of every random stream
  double zero_set_tolerance_mm = 1e-4;   ///< |sdf| below which a projected point is accepted
};

/// Points on the zero set of `sdf`: `starts` seeded uniform points in the box [lo, hi] (mm), each
/// moved by Newton steps x <- x - f(x) grad f(x) / |grad f(x)|^2 (central differences, step
/// 1e-3 mm; for an exact SDF this is x - f grad f), kept when |f| < tolerance_mm within 50 steps.
/// In the order of the starting points. The density is not area-uniform (it follows the volume
/// that projects onto each part of the surface).
std::vector<Vec3> zeroSetPoints(const SignedDistanceFn& sdf, const Vec3& lo, const Vec3& hi,
                                std::size_t starts, std::uint64_t seed, double tolerance_mm);

/// Mesh against an implicit truth. mesh -> truth: |sdf| at area-uniform mesh samples and at the
/// mesh vertices (exact when sdf is an exact distance, a lower bound otherwise). truth -> mesh:
/// distance to the mesh (via `meshQuery`, built on `mesh`) of zeroSetPoints in [lo, hi]; its
/// mean is taken over an approximately area-uniform subset (the first point in each cube of a
/// grid sized for about a fifth of the points, the mesh's area standing in for the truth's).
/// `distance`, when given, is an exact unsigned distance to the zero set used for mesh -> truth
/// (for truths whose sdf is only a lower bound).
SurfaceDistances distancesToImplicit(const TriangleMesh& mesh, const MeshDistance& meshQuery,
                                     const SignedDistanceFn& sdf, const Vec3& lo, const Vec3& hi,
                                     const SamplingParams& params,
                                     const SignedDistanceFn& distance = nullptr);

/// Mesh against a reference mesh: samples and vertices of each measured against the other.
SurfaceDistances distancesToMesh(const TriangleMesh& mesh, const MeshDistance& meshQuery,
                                 const TriangleMesh& reference,
                                 const MeshDistance& referenceQuery, const SamplingParams& params);

/// The voxel grid covering the box [lo, hi] (mm) plus one voxel on each side, with voxel edge
/// `voxel_mm` (0 = automatic: 1/100 of the box diagonal), enlarged when needed so that the grid
/// has at most `max_voxels` voxels.
GridSpec overlapGrid(const Vec3& lo, const Vec3& hi, double voxel_mm,
                     std::int64_t max_voxels = 8000000);

/// Voxel counts of two solids sampled at the voxel centres of a grid.
struct VolumeOverlap {
  std::int64_t a = 0, b = 0, both = 0;
  double dice() const { return a + b > 0 ? 2.0 * double(both) / double(a + b) : 1.0; }
  double iou() const { return a + b - both > 0 ? double(both) / double(a + b - both) : 1.0; }
};
VolumeOverlap volumeOverlap(const InsideFn& a, const InsideFn& b, const GridSpec& grid);

/// Axis-aligned bounds (mm) of a mesh's vertices.
void meshBounds(const TriangleMesh& mesh, Vec3* lo, Vec3* hi);

}  // namespace xsect

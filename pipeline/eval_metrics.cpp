// Surface distances and volume overlap of a mesh against a truth (eval_metrics.h).
// Parallel loops write one slot per point; every sum is then taken serially in point order, and
// voxel counts are integers, so results do not depend on the thread count.
#include "pipeline/eval_metrics.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "geometry/core/random_streams.h"

namespace xsect {
namespace {

template <class F>
void forEachIndex(std::size_t n, const F& f) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i) f(i);
                    });
}

/// Max over all values, mean over the first `meanCount` (the area-uniform samples).
OneSidedDistance summarise(const std::vector<double>& d, std::size_t meanCount) {
  OneSidedDistance s;
  s.points = d.size();
  double sum = 0.0;
  for (std::size_t i = 0; i < d.size(); ++i) {
    s.max_mm = std::max(s.max_mm, d[i]);
    if (i < meanCount) sum += d[i];
  }
  s.mean_mm = meanCount > 0 ? sum / double(meanCount) : 0.0;
  return s;
}

/// Area-uniform samples followed by the mesh vertices.
std::vector<Vec3> samplesAndVertices(const TriangleMesh& mesh, std::size_t count,
                                     std::uint64_t seed, std::size_t* sampleCount) {
  std::vector<Vec3> pts = sampleSurface(mesh, count, seed);
  *sampleCount = pts.size();
  pts.reserve(pts.size() + mesh.vertices.size());
  for (const auto& v : mesh.vertices) pts.push_back(v.cast<double>());
  return pts;
}

/// Indices of an approximately area-uniform subset of surface points: the first point (in input
/// order) of each occupied cube of edge cell_mm. Points projected from a volume crowd where much
/// volume projects (convex parts, the outside of a torus); one point per cell evens that out.
std::vector<std::size_t> thinToCells(const std::vector<Vec3>& pts, double cell_mm) {
  std::vector<std::pair<std::array<std::int64_t, 3>, std::size_t>> keyed(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    for (int c = 0; c < 3; ++c) keyed[i].first[c] = std::int64_t(std::floor(pts[i][c] / cell_mm));
    keyed[i].second = i;
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::size_t> chosen;
  for (std::size_t i = 0; i < keyed.size(); ++i)
    if (i == 0 || keyed[i].first != keyed[i - 1].first) chosen.push_back(keyed[i].second);
  std::sort(chosen.begin(), chosen.end());
  return chosen;
}

constexpr std::uint64_t kStreamZeroSet = 0x5A45524F534554ULL;  // "ZEROSET"

}  // namespace

std::vector<Vec3> zeroSetPoints(const SignedDistanceFn& sdf, const Vec3& lo, const Vec3& hi,
                                std::size_t starts, std::uint64_t seed, double tolerance_mm) {
  std::vector<Vec3> start(starts);
  std::mt19937_64 rng = makeStream(seed, kStreamZeroSet, 0);
  for (auto& p : start)
    for (int c = 0; c < 3; ++c) p[c] = uniform(rng, lo[c], hi[c]);

  constexpr double h = 1e-3;  // central-difference step, mm
  constexpr int kMaxSteps = 50;
  std::vector<std::optional<Vec3>> result(starts);
  forEachIndex(starts, [&](std::size_t i) {
    Vec3 x = start[i];
    for (int step = 0; step < kMaxSteps; ++step) {
      const double f = sdf(x);
      if (!std::isfinite(f)) return;
      if (std::abs(f) < tolerance_mm) {
        result[i] = x;
        return;
      }
      Vec3 g;
      for (int c = 0; c < 3; ++c) {
        Vec3 e = Vec3::Zero();
        e[c] = h;
        g[c] = (sdf(x + e) - sdf(x - e)) / (2 * h);
      }
      const double g2 = g.squaredNorm();
      if (!(g2 > 1e-12)) return;  // on the medial axis or a flat spot: no direction to move
      x -= (f / g2) * g;
    }
  });
  std::vector<Vec3> points;
  for (const auto& r : result)
    if (r) points.push_back(*r);
  return points;
}

SurfaceDistances distancesToImplicit(const TriangleMesh& mesh, const MeshDistance& meshQuery,
                                     const SignedDistanceFn& sdf, const Vec3& lo, const Vec3& hi,
                                     const SamplingParams& params,
                                     const SignedDistanceFn& distance) {
  SurfaceDistances out;
  std::size_t sampled = 0;
  const std::vector<Vec3> pts = samplesAndVertices(mesh, params.surface_samples, params.seed, &sampled);
  std::vector<double> d(pts.size());
  const SignedDistanceFn& toTruth = distance ? distance : sdf;
  forEachIndex(pts.size(), [&](std::size_t i) { d[i] = std::abs(toTruth(pts[i])); });
  out.mesh_to_truth = summarise(d, sampled);

  const std::vector<Vec3> truth =
      zeroSetPoints(sdf, lo, hi, params.zero_set_starts, params.seed, params.zero_set_tolerance_mm);
  const std::vector<double> dt = meshQuery.distances(truth);
  out.truth_to_mesh = summarise(dt, 0);
  // Mean over an area-uniform subset: cells sized for about a fifth of the points, using the
  // mesh's area as the estimate of the truth's.
  const double cell = std::sqrt(surfaceArea(mesh) / std::max<double>(1.0, truth.size() / 5.0));
  if (cell > 0 && !truth.empty()) {
    double sum = 0.0;
    const std::vector<std::size_t> chosen = thinToCells(truth, cell);
    for (std::size_t i : chosen) sum += dt[i];
    out.truth_to_mesh.mean_mm = sum / double(chosen.size());
  }
  return out;
}

SurfaceDistances distancesToMesh(const TriangleMesh& mesh, const MeshDistance& meshQuery,
                                 const TriangleMesh& reference,
                                 const MeshDistance& referenceQuery, const SamplingParams& params) {
  SurfaceDistances out;
  std::size_t sampled = 0;
  const std::vector<Vec3> a = samplesAndVertices(mesh, params.surface_samples, params.seed, &sampled);
  out.mesh_to_truth = summarise(referenceQuery.distances(a), sampled);
  const std::vector<Vec3> b =
      samplesAndVertices(reference, params.surface_samples, params.seed + 1, &sampled);
  out.truth_to_mesh = summarise(meshQuery.distances(b), sampled);
  return out;
}

GridSpec overlapGrid(const Vec3& lo, const Vec3& hi, double voxel_mm, std::int64_t max_voxels) {
  const Vec3 size = (hi - lo).cwiseMax(Vec3::Zero());
  double voxel = voxel_mm > 0 ? voxel_mm : size.norm() / 100.0;
  if (!(voxel > 0)) voxel = 1.0;  // a degenerate box: any voxel covers it
  auto dimsFor = [&](double v) {
    std::array<int, 3> dims;
    for (int c = 0; c < 3; ++c) dims[c] = int(std::ceil(size[c] / v)) + 3;  // + one voxel each side
    return dims;
  };
  auto count = [](const std::array<int, 3>& d) { return double(d[0]) * d[1] * d[2]; };
  while (count(dimsFor(voxel)) > double(max_voxels)) voxel *= 1.01;
  GridSpec g;
  g.voxel = voxel;
  g.dims = dimsFor(voxel);
  // Centre the grid on the box.
  const Vec3 extent = voxel * Vec3(g.dims[0] - 1, g.dims[1] - 1, g.dims[2] - 1);
  g.origin = 0.5 * (lo + hi) - 0.5 * extent;
  return g;
}

VolumeOverlap volumeOverlap(const InsideFn& a, const InsideFn& b, const GridSpec& grid) {
  VolumeOverlap v;
  // One z-layer at a time keeps memory bounded by a layer of points; its rows run along x.
  PointRows layer;
  layer.step = Vec3(grid.voxel, 0, 0);
  layer.count = grid.dims[0];
  layer.starts.resize(std::size_t(grid.dims[1]));
  for (int k = 0; k < grid.dims[2]; ++k) {
    for (int j = 0; j < grid.dims[1]; ++j) layer.starts[std::size_t(j)] = grid.centre(0, j, k);
    const std::vector<std::uint8_t> ina = a(layer), inb = b(layer);
    for (std::size_t n = 0; n < layer.size(); ++n) {
      v.a += ina[n];
      v.b += inb[n];
      v.both += ina[n] & inb[n];
    }
  }
  return v;
}

void meshBounds(const TriangleMesh& mesh, Vec3* lo, Vec3* hi) {
  *lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  *hi = -*lo;
  for (const auto& v : mesh.vertices) {
    *lo = lo->cwiseMin(v.cast<double>());
    *hi = hi->cwiseMax(v.cast<double>());
  }
}

}  // namespace xsect

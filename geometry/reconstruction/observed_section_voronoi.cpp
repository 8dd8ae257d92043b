// Method 2 on observed pieces: R' where the lift's ball is observed, method 1 on the pieces
// elsewhere (see observed_section_voronoi.h).
#include "geometry/reconstruction/observed_section_voronoi.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "geometry/core/block_grid.h"
#include "geometry/core/section_locator.h"
#include "geometry/reconstruction/nearest_plane_reconstruction.h"

namespace xsect {

namespace {

/// Method 1 on the pieces, kept by blocks (uniform blocks are tiles) until method 2's block asks.
struct PiecesSolid {
  BlockGrid<float> value, plane_distance;
  BlockGrid<int> nearest_plane;
  explicit PiecesSolid(const GridSpec& g) : value(g, 0.f), plane_distance(g, 0.f), nearest_plane(g, -1) {}
};

}  // namespace

bool ObservedLiftTest::keeps(const Vec3& x, double h, int lifted, const std::vector<int>& candidates) const {
  // The lift's foot, x's projection on its plane, lies in the plane's piece (then it is also the
  // nearest point of the piece to x).
  const Vec2 foot = planes_[std::size_t(lifted)].plane.toPlane(x);
  double na, nb;
  if (pieces_[std::size_t(lifted)].distance(foot.x(), foot.y(), &na, &nb) != 0) return false;
  // Every plane within h of x is observed over its disc of B(x, h).
  bool observed = true;
  for (const int p : candidates) {
    if (pieces_[std::size_t(p)].whole) continue;
    const Plane& P = planes_[std::size_t(p)].plane;
    const double s = std::abs(P.signedDistance(x));
    if (s > h * (1 + 1e-9)) continue;
    const Vec2 at = P.toPlane(x);
    if (!covers(pieces_[std::size_t(p)], at.x(), at.y(), std::sqrt(std::max(0.0, h * h - s * s)))) {
      observed = false;
      break;
    }
  }
  if (observed) return true;
  // Or no section point but the foot lies within h of x: no plane other than the lift's has a
  // section within its disc of B(x, h).
  for (const int p : candidates) {
    if (p == lifted || planes_[std::size_t(p)].sections.empty()) continue;
    const Plane& P = planes_[std::size_t(p)].plane;
    const double s = std::abs(P.signedDistance(x));
    if (s >= h) continue;
    const Vec2 at = P.toPlane(x);
    const double r = std::sqrt(h * h - s * s);
    const SectionLocator& L = locators_[std::size_t(p)];
    if (L.boxBound(at) >= r) continue;
    if (L.holding(at) >= 0 || L.nearestContour(at).d < r) return false;
  }
  return true;
}

void forEachObservedSectionVoronoiBlock(const std::vector<CuttingPlane>& planes,
                                        const std::vector<SectionDistanceField>& fields,
                                        const std::vector<ObservedPiece>& pieces, const GridSpec& grid,
                                        const SectionVoronoiParams& params,
                                        const std::function<void(std::int64_t, const SectionVoronoiBlock&)>& visit,
                                        const std::function<void(std::int64_t, std::int64_t)>& progress,
                                        ObservedSectionVoronoiStatistics* statistics) {
  if (pieces.size() != planes.size())
    throw std::invalid_argument("method 2 on observed pieces: one piece per plane is required");
  ObservedSectionVoronoiStatistics counts;
  if (std::all_of(pieces.begin(), pieces.end(), [](const ObservedPiece& p) { return p.whole; })) {
    forEachSectionVoronoiBlock(planes, fields, grid, params, visit, progress, &counts.voronoi);
    if (statistics) *statistics = counts;
    return;
  }
  PiecesSolid solid(grid);
  forEachNearestPlaneBlock(planes, fields, grid, [&](std::int64_t b, const NearestPlaneBlock& v) {
    solid.value.setBlock(b, v.value.data());
    solid.plane_distance.setBlock(b, v.plane_distance.data());
    solid.nearest_plane.setBlock(b, v.nearest_plane.data());
  }, true, [&](std::int64_t done, std::int64_t all) { if (progress) progress(done, 2 * all); }, &pieces);

  // Point location among each plane's sections, for the lifts' balls.
  std::vector<SectionLocator> locators(planes.size());
  tbb::parallel_for(std::size_t(0), planes.size(), [&](std::size_t p) {
    if (!planes[p].sections.empty()) locators[p] = SectionLocator(planes[p].sections);
  });
  const ObservedLiftTest test(planes, pieces, locators);
  std::atomic<std::int64_t> kept{0}, dropped{0}, added{0};
  const auto combine = [&](std::int64_t b, const SectionVoronoiBlock& m2) {
    SectionVoronoiBlock out;
    const auto origin = solid.value.blockOrigin(b);
    // The planes that may meet the ball of a voxel of the block whose lift must be checked: within
    // the largest such lift of the block's centre, plus the block's half diagonal.
    float hmax = -1;
    forEachVoxelOfBlock(grid, origin, [&](int i, int j, int k, int q) {
      if (m2.value[std::size_t(q)] < 0 && !(solid.value.at(i, j, k) < 0))
        hmax = std::max(hmax, m2.lift_height[std::size_t(q)]);
    });
    std::vector<int> near;  // planes that may meet the ball of a voxel of the block
    if (hmax >= 0) {
      const Vec3 lo = grid.centre(origin[0], origin[1], origin[2]);
      const Vec3 half = Vec3::Constant(0.5 * (BlockGrid<float>::kSide - 1) * grid.voxel);
      const Vec3 c = lo + half;
      for (std::size_t p = 0; p < planes.size(); ++p) {
        const Plane& P = planes[p].plane;
        if (std::abs(P.signedDistance(c)) - P.normal.cwiseAbs().dot(half) > double(hmax) * (1 + 1e-9)) continue;
        if (!pieces[p].whole || !planes[p].sections.empty()) near.push_back(int(p));
      }
    }
    std::int64_t k = 0, d = 0, a = 0;
    forEachVoxelOfBlock(grid, origin, [&](int i, int j, int kk, int q) {
      const std::size_t u = std::size_t(q);
      const float v1 = solid.value.at(i, j, kk);
      out.plane_distance[u] = solid.plane_distance.at(i, j, kk);
      out.nearest_plane[u] = solid.nearest_plane.at(i, j, kk);
      const bool in1 = v1 < 0, in2 = m2.value[u] < 0;
      bool lift = false;
      if (in2 && !in1) {
        // x ∈ R' \ R_Ω: kept when its foot is observed and, within B(x, h(x)), every plane is
        // observed or no section point but the foot lies (observed_section_voronoi.h).
        const Vec3 x = grid.centre(i, j, kk);
        const double h = m2.lift_height[u];
        const int A = m2.section_plane[u];
        lift = A >= 0 && test.keeps(x, h, A, near);
        (lift ? k : d) += 1;
      }
      a += in1 && !in2;
      if (lift) {
        out.value[u] = m2.value[u];
        out.section_plane[u] = m2.section_plane[u];
        out.lift_height[u] = m2.lift_height[u];
      } else {
        out.value[u] = v1;
        out.section_plane[u] = in1 ? out.nearest_plane[u] : -1;
        out.lift_height[u] = in1 ? out.plane_distance[u] : 0.f;
        // Method 2's outside evidence where no plane's sections reach x by projection (nearest
        // plane -1, section_voronoi_reconstruction.cpp) stands where x stays outside.
        if (m2.nearest_plane[u] < 0 && !in1) out.nearest_plane[u] = -1;
      }
    });
    // Voxels beyond the grid repeat the block's first (a block uniform within the grid stays a tile).
    repeatFirstBeyondGrid(grid, origin, out);
    kept += k;
    dropped += d;
    added += a;
    visit(b, out);
  };
  forEachSectionVoronoiBlock(planes, fields, grid, params, combine,
                             [&](std::int64_t done, std::int64_t all) { if (progress) progress(all + done, 2 * all); },
                             &counts.voronoi);
  counts.lift_voxels_kept = kept;
  counts.lift_voxels_dropped = dropped;
  counts.pieces_voxels_added = added;
  if (statistics) *statistics = counts;
}

}  // namespace xsect

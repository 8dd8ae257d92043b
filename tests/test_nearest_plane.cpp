// The block-culled method-1 evaluation equals the brute-force definition (thesis Def. 15-16):
// for every voxel, the nearest cutting plane over ALL planes and f_P at the projection.
#include <gtest/gtest.h>

#include <atomic>
#include <random>

#include "geometry/reconstruction/nearest_plane_reconstruction.h"
#include "section_fixtures.h"

using namespace xsect;

TEST(NearestPlane, BlockCullingEqualsBruteForce) {
  std::mt19937_64 rng(7);
  for (const int count : {1, 7, 60, 300}) {
    const auto planes = test::randomShellPlanes(count, rng, Vec3(0.3, -0.2, 0.1), 7.0, 6.0, 2.0);
    std::vector<SectionDistanceField> fields;
    for (const auto& p : planes) fields.push_back(sectionDistanceField(p.sections, 0.1, 0.6));
    GridSpec grid;
    grid.voxel = 0.23;
    grid.origin = Vec3(-8.1, -7.9, -8.05);
    grid.dims = {70, 69, 71};  // not multiples of the block sizes
    const NearestPlaneField f = nearestPlaneReconstruction(planes, fields, grid);
    std::int64_t mismatches = 0;
    for (int k = 0; k < grid.dims[2]; ++k)
      for (int j = 0; j < grid.dims[1]; ++j)
        for (int i = 0; i < grid.dims[0]; ++i) {
          const Vec3 x = grid.centre(i, j, k);
          double best = 1e300;
          int bp = -1;
          for (std::size_t p = 0; p < planes.size(); ++p) {
            const double d = std::abs(planes[p].plane.signedDistance(x));
            if (d < best) best = d, bp = int(p);
          }
          const std::size_t q = std::size_t(grid.index(i, j, k));
          const Vec2 a = planes[bp].plane.toPlane(x);
          const float want = fields[bp].sample(a.x(), a.y());
          // Ties between planes (equal distance to 1e-12) may resolve either way.
          const bool same = f.nearest_plane[q] == bp ||
                            std::abs(std::abs(planes[f.nearest_plane[q]].plane.signedDistance(x)) - best) < 1e-12;
          if (!same || std::abs(f.plane_distance[q] - best) > 1e-5 ||
              (f.nearest_plane[q] == bp && std::abs(f.value.values[q] - want) > 1e-5))
            ++mismatches;
        }
    EXPECT_EQ(mismatches, 0) << count << " planes";
  }
}

namespace {

/// The convex polygon `ring` cut by the half-plane {x : n . (x - p) >= 0} (Sutherland-Hodgman).
Ring clipped(const Ring& ring, const Vec2& p, const Vec2& n) {
  Ring out;
  for (std::size_t k = 0; k < ring.size(); ++k) {
    const Vec2 &a = ring[k], &b = ring[(k + 1) % ring.size()];
    const double da = n.dot(a - p), db = n.dot(b - p);
    if (da >= 0) out.push_back(a);
    if ((da >= 0) != (db >= 0)) out.push_back(a + (b - a) * (da / (da - db)));
  }
  return out;
}

}  // namespace

// Observed pieces (issue 20): the same with each plane cut down to an image rectangle, half of
// them also to a fan (a probe's sector, apex above the image): for every voxel the nearest piece
// over ALL planes, d = sqrt(s² + o²), and f_P at the piece's nearest point; and the whole-block
// decision (a block taken as outside without its voxels) never hides a voxel of R.
TEST(NearestPlane, ObservedPiecesCullingEqualsBruteForce) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> size(2.0, 8.0);
  for (const int count : {1, 9, 60}) {
    auto planes = test::randomShellPlanes(count, rng, Vec3(0.3, -0.2, 0.1), 7.0, 6.0, 2.0);
    for (std::size_t i = 0; i < planes.size(); ++i) {
      CuttingPlane& p = planes[i];
      p.pixel_mm = 0.1;
      p.extent = {Vec2(-size(rng), -size(rng)), Vec2(size(rng), size(rng))};
      if (i % 2) {
        const Vec2 apex(0.5 * (p.extent.min.x() + p.extent.max.x()), p.extent.min.y() - 3.0);
        const Ring rect{p.extent.min, Vec2(p.extent.max.x(), p.extent.min.y()), p.extent.max,
                        Vec2(p.extent.min.x(), p.extent.max.y())};
        const double a = 35 * M_PI / 180;  // the fan's half opening about +v
        p.field_of_view = {clipped(clipped(rect, apex, Vec2(std::cos(a), std::sin(a))), apex,
                                   Vec2(-std::cos(a), std::sin(a)))};
      }
    }
    const std::vector<ObservedPiece> pieces = observedPieces(planes, true);
    std::vector<SectionDistanceField> fields;
    for (const auto& p : planes) fields.push_back(sectionDistanceField(p.sections, 0.1, 0.6));
    GridSpec grid;
    grid.voxel = 0.23;
    grid.origin = Vec3(-8.1, -7.9, -8.05);
    grid.dims = {70, 69, 71};
    const NearestPlaneField f = nearestPlaneReconstruction(planes, fields, grid, {}, &pieces);
    std::int64_t mismatches = 0, inside = 0;
    std::vector<char> brute(std::size_t(grid.count()), 0);
    for (int k = 0; k < grid.dims[2]; ++k)
      for (int j = 0; j < grid.dims[1]; ++j)
        for (int i = 0; i < grid.dims[0]; ++i) {
          const Vec3 x = grid.centre(i, j, k);
          double best = 1e300, ba = 0, bb = 0;
          int bp = -1;
          for (std::size_t p = 0; p < planes.size(); ++p) {
            const Vec2 a = planes[p].plane.toPlane(x);
            double na, nb;
            const double d = std::hypot(planes[p].plane.signedDistance(x), pieces[p].distance(a.x(), a.y(), &na, &nb));
            if (d < best) best = d, bp = int(p), ba = na, bb = nb;
          }
          const std::size_t q = std::size_t(grid.index(i, j, k));
          if (bp < 0) {  // no piece at all
            mismatches += f.nearest_plane[q] != -1;
            continue;
          }
          const float want = fields[bp].sample(ba, bb);
          brute[q] = want < 0;
          inside += want < 0;
          const bool same = f.nearest_plane[q] == bp || std::abs(f.plane_distance[q] - best) < 1e-9;
          if (!same || std::abs(f.plane_distance[q] - best) > 1e-5 ||
              (f.nearest_plane[q] == bp && std::abs(f.value.values[q] - want) > 1e-5))
            ++mismatches;
        }
    EXPECT_EQ(mismatches, 0) << count << " planes";
    if (count > 1) EXPECT_GT(inside, 0) << "the test must see voxels of R";
    // The block evaluation with whole-block decisions: every voxel of R is evaluated and inside.
    std::atomic<std::int64_t> lost{0};
    const BlockGrid<float> blocks(grid, 0.f);  // the numbering of the blocks
    forEachNearestPlaneBlock(planes, fields, grid, [&](std::int64_t b, const NearestPlaneBlock& v) {
      forEachVoxelOfBlock(grid, blocks.blockOrigin(b), [&](int i, int j, int k, int o) {
        lost += brute[std::size_t(grid.index(i, j, k))] && !(v.value[std::size_t(o)] < 0);
      });
    }, true, {}, &pieces);
    EXPECT_EQ(lost.load(), 0) << count << " planes";
  }
}

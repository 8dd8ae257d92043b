// The block-culled method-1 evaluation equals the brute-force definition (thesis Def. 15-16):
// for every voxel, the nearest cutting plane over ALL planes and f_P at the projection.
#include <gtest/gtest.h>

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

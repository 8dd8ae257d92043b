// Components of voxel sets (geometry/core/digital_topology.h) found between runs along x (issue
// 17) against a plain flood fill voxel by voxel, on random sets of every density: the same
// components with the same numbers (by first voxel in scan order), the same bounded complement
// components, and the repair and well-composedness giving sets whose Betti numbers the mesh keeps.
#include <gtest/gtest.h>

#include <array>
#include <random>
#include <vector>

#include "geometry/core/digital_topology.h"

using namespace xsect;

namespace {

/// Flood fill from each unlabelled voxel of value v in scan order (26- or 6-connectivity).
std::vector<int> floodLabels(const std::vector<std::uint8_t>& in, std::uint8_t v, const GridSpec& g, bool full26,
                             std::vector<char>* border) {
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  std::vector<int> label(in.size(), -1);
  int next = 0;
  std::vector<std::int64_t> stack;
  for (std::int64_t s = 0; s < std::int64_t(in.size()); ++s) {
    if (in[std::size_t(s)] != v || label[std::size_t(s)] >= 0) continue;
    label[std::size_t(s)] = next;
    border->push_back(0);
    stack.assign(1, s);
    while (!stack.empty()) {
      const std::int64_t q = stack.back();
      stack.pop_back();
      const int i = int(q % nx), j = int((q / nx) % ny), k = int(q / (std::int64_t(nx) * ny));
      if (i == 0 || j == 0 || k == 0 || i == nx - 1 || j == ny - 1 || k == nz - 1) (*border)[std::size_t(next)] = 1;
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int m = std::abs(dx) + std::abs(dy) + std::abs(dz);
            if (m == 0 || (!full26 && m > 1)) continue;
            const int a = i + dx, b = j + dy, c = k + dz;
            if (a < 0 || b < 0 || c < 0 || a >= nx || b >= ny || c >= nz) continue;
            const std::int64_t r = g.index(a, b, c);
            if (in[std::size_t(r)] == v && label[std::size_t(r)] < 0) {
              label[std::size_t(r)] = next;
              stack.push_back(r);
            }
          }
    }
    ++next;
  }
  return label;
}

}  // namespace

TEST(DigitalTopology, RunComponentsAreTheFloodFillsOnRandomSets) {
  std::mt19937 rng(17);
  int sets = 0;
  for (const double density : {0.02, 0.1, 0.3, 0.5, 0.7, 0.9}) {
    for (int trial = 0; trial < 20; ++trial) {
      GridSpec g;
      g.voxel = 1;
      g.dims = {3 + int(rng() % 14), 1 + int(rng() % 12), 1 + int(rng() % 12)};
      std::bernoulli_distribution on(density);
      std::vector<std::uint8_t> in(std::size_t(g.count()));
      for (auto& v : in) v = on(rng);
      std::vector<char> border;
      const std::vector<int> expected = floodLabels(in, 1, g, true, &border);
      int count = 0;
      EXPECT_EQ(solidComponents(in, g, &count), expected) << "density " << density << " trial " << trial;
      int expectedCount = 0;
      for (const int l : expected) expectedCount = std::max(expectedCount, l + 1);
      EXPECT_EQ(count, expectedCount);
      // b0 and b2 of voxelBetti: the 26-components and the bounded 6-components of the complement.
      std::vector<char> outBorder;
      floodLabels(in, 0, g, false, &outBorder);
      int cavities = 0;
      for (const char b : outBorder) cavities += !b;
      const Betti betti = voxelBetti(in, g);
      EXPECT_EQ(betti[0], expectedCount);
      EXPECT_EQ(betti[2], cavities);
      ++sets;
    }
  }
  EXPECT_EQ(sets, 120);
}

/// The change of the Euler characteristic summed next to the change equals that of the whole
/// sets (chi = b0 - b1 + b2 of voxelBetti), for changes of every size on random sets.
TEST(DigitalTopology, EulerCharacteristicChangeIsTheWholeSetsDifference) {
  std::mt19937 rng(29);
  int changes = 0, nonzero = 0;
  for (const double density : {0.1, 0.3, 0.5, 0.7}) {
    for (int trial = 0; trial < 25; ++trial) {
      GridSpec g;
      g.dims = {4 + int(rng() % 10), 4 + int(rng() % 10), 4 + int(rng() % 10)};
      std::bernoulli_distribution on(density);
      std::vector<std::uint8_t> in(std::size_t(g.count()));
      for (auto& v : in) v = on(rng);
      const std::uint8_t value = std::uint8_t(rng() % 2);
      std::vector<std::int64_t> voxels;
      std::bernoulli_distribution pick(0.05 + 0.1 * (trial % 4));
      for (std::int64_t v = 0; v < g.count(); ++v)
        if (pick(rng)) voxels.push_back(v);
      std::vector<std::uint8_t> after = in;
      for (const std::int64_t v : voxels) after[std::size_t(v)] = value;
      const Betti b = voxelBetti(in, g), a = voxelBetti(after, g);
      const long long expected = (a[0] - a[1] + a[2]) - (b[0] - b[1] + b[2]);
      EXPECT_EQ(eulerCharacteristicChange(in, g, voxels, value), expected) << "density " << density << " trial " << trial;
      nonzero += expected != 0;
      ++changes;
    }
  }
  EXPECT_EQ(changes, 100);
  EXPECT_GT(nonzero, 50);  // the changes do change the topology: the test can fail
  EXPECT_EQ(eulerCharacteristicChange(std::vector<std::uint8_t>(8, 0), GridSpec{Vec3::Zero(), 1.0, {2, 2, 2}}, {}, 1), 0);
}

TEST(DigitalTopology, RepairKeepsTheAnchoredComponentsAndFillsUnanchoredCavities) {
  // Two blocks, one anchored; a hollow cube whose cavity carries no outside anchor.
  GridSpec g;
  g.voxel = 1;
  g.dims = {20, 9, 9};
  std::vector<std::uint8_t> in(std::size_t(g.count()), 0), inAnchor(in.size(), 0), outAnchor(in.size(), 0);
  for (int k = 2; k <= 6; ++k)
    for (int j = 2; j <= 6; ++j)
      for (int i = 2; i <= 6; ++i) in[std::size_t(g.index(i, j, k))] = !(i == 4 && j == 4 && k == 4);  // hollow
  for (int k = 3; k <= 4; ++k)
    for (int j = 3; j <= 4; ++j)
      for (int i = 12; i <= 13; ++i) in[std::size_t(g.index(i, j, k))] = 1;  // a speck
  inAnchor[std::size_t(g.index(2, 2, 2))] = 1;
  EXPECT_EQ(voxelBetti(in, g), (Betti{2, 0, 1}));
  const TopologyRepair r = repairSampledTopology(in, inAnchor, outAnchor, g);
  EXPECT_EQ(r.specks_removed, 1);
  EXPECT_EQ(r.cavities_filled, 1);
  EXPECT_EQ(voxelBetti(in, g), (Betti{1, 0, 0}));
  EXPECT_EQ(in[std::size_t(g.index(4, 4, 4))], 1);
  EXPECT_EQ(in[std::size_t(g.index(12, 3, 3))], 0);
}

// The well-composedness pass on blocks skips the cubes inside tiles of one value (issue 17); on
// dense bytes it scans every cube. Both must add the same voxels: sets with large uniform regions
// (tiles, inside and outside) and noisy boundaries, where additions reach into tiles.
TEST(DigitalTopology, WellComposedOnBlocksEqualsTheFullScanOnDenseBytes) {
  std::mt19937_64 rng(41);
  int added = 0;
  for (int trial = 0; trial < 12; ++trial) {
    GridSpec g;
    g.voxel = 1;
    g.dims = {27 + trial % 5, 30 - trial % 3, 25 + trial % 4};  // blocks cut by the grid's faces
    std::uniform_real_distribution<double> u(0, 1);
    const Vec3 c(u(rng) * g.dims[0], u(rng) * g.dims[1], u(rng) * g.dims[2]);
    const double radius = 6 + 6 * u(rng), noise = 0.5 + 1.5 * u(rng);
    std::vector<std::uint8_t> dense(std::size_t(g.count()), 0);
    BlockGrid<std::uint8_t> blocks(g, 0);
    for (int k = 0; k < g.dims[2]; ++k)
      for (int j = 0; j < g.dims[1]; ++j)
        for (int i = 0; i < g.dims[0]; ++i) {
          const double d = (Vec3(i, j, k) - c).norm() - radius;  // a ball, its boundary noisy
          const std::uint8_t v = d < -noise ? 1 : d > noise ? 0 : std::uint8_t(u(rng) < 0.5);
          dense[std::size_t(g.index(i, j, k))] = v;
          if (v) blocks.set(i, j, k, 1);
        }
    blocks.compact();  // uniform blocks as tiles, as the reconstruction stores them
    const int a = makeWellComposed(dense, g), b = makeWellComposed(blocks);
    EXPECT_EQ(a, b) << "trial " << trial;
    std::int64_t differ = 0;
    for (int k = 0; k < g.dims[2]; ++k)
      for (int j = 0; j < g.dims[1]; ++j)
        for (int i = 0; i < g.dims[0]; ++i) differ += dense[std::size_t(g.index(i, j, k))] != blocks.at(i, j, k);
    EXPECT_EQ(differ, 0) << "trial " << trial;
    added += a;
  }
  EXPECT_GT(added, 100);  // the noise made critical configurations to remove
}

TEST(DigitalTopology, ImposeSolidForcesTheSignToTheSet) {
  ScalarField f;
  f.grid.dims = {3, 1, 1};
  f.values = {-1.0f, 2.0f, 0.0f};
  const std::vector<std::uint8_t> in{0, 1, 1};
  EXPECT_EQ(imposeSolid(f, in, 0.1f), 3);
  EXPECT_EQ(f.values, (std::vector<float>{0.1f, -0.1f, -0.1f}));
}

// The exact distance transform (geometry/core/distance_transform.h) against brute force on random
// sets, and the ball closing and opening (ball_morphology.h) against their definitions: the
// closing holds the set and fills a slot narrower than the ball, the opening is held by the set
// and removes a neck thinner than the ball; the window-by-window closing and opening of a block grid
// (block_ball_morphology.h) voxel for voxel against the dense ones.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "geometry/core/ball_morphology.h"
#include "geometry/core/block_ball_morphology.h"
#include "geometry/core/digital_topology.h"
#include "geometry/core/distance_transform.h"

using namespace xsect;

namespace {

GridSpec grid(int nx, int ny, int nz) {
  GridSpec g;
  g.dims = {nx, ny, nz};
  return g;
}

TEST(DistanceTransform, EqualsTheNearestVoxelByBruteForceOnRandomSets) {
  for (int seed = 1; seed <= 20; ++seed) {
    std::mt19937 rng(static_cast<unsigned>(seed));
    const GridSpec g = grid(7 + seed % 5, 5 + seed % 7, 6 + seed % 3);
    const double density = 0.002 + 0.02 * (seed % 6);
    std::bernoulli_distribution in(density);
    std::vector<std::uint8_t> set(std::size_t(g.count()));
    for (auto& v : set) v = in(rng);
    const std::vector<float> d = squaredDistanceToSet(set, g);
    for (int k = 0; k < g.dims[2]; ++k)
      for (int j = 0; j < g.dims[1]; ++j)
        for (int i = 0; i < g.dims[0]; ++i) {
          double best = kNoVoxel;
          for (int c = 0; c < g.dims[2]; ++c)
            for (int b = 0; b < g.dims[1]; ++b)
              for (int a = 0; a < g.dims[0]; ++a)
                if (set[std::size_t(g.index(a, b, c))])
                  best = std::min(best, double((a - i) * (a - i) + (b - j) * (b - j) + (c - k) * (c - k)));
          ASSERT_EQ(double(d[std::size_t(g.index(i, j, k))]), best) << "seed " << seed << " at " << i << " " << j << " " << k;
        }
  }
}

TEST(DistanceTransform, RefusesASetOfAnotherSize) {
  EXPECT_THROW(squaredDistanceToSet(std::vector<std::uint8_t>(5, 0), grid(2, 2, 2)), std::invalid_argument);
}

/// Two slabs across a 25 x 15 x 15 grid, x <= 9 and x >= 10 + gap: a slot `gap` voxels wide.
std::vector<std::uint8_t> slot(const GridSpec& g, int gap) {
  std::vector<std::uint8_t> set(std::size_t(g.count()), 0);
  for (int k = 2; k < g.dims[2] - 2; ++k)
    for (int j = 2; j < g.dims[1] - 2; ++j)
      for (int i = 4; i < g.dims[0] - 4; ++i)
        if (i <= 9 || i >= 10 + gap) set[std::size_t(g.index(i, j, k))] = 1;
  return set;
}

TEST(BallMorphology, ClosingHoldsTheSetAndFillsOnlySlotsNarrowerThanTheBall) {
  const GridSpec g = grid(25, 15, 15);
  for (const int gap : {1, 2, 3, 4, 5})
    for (const double r : {1.0, 2.0}) {
      const std::vector<std::uint8_t> set = slot(g, gap);
      const std::vector<std::uint8_t> closed = ballClosing(set, g, r);
      for (std::size_t v = 0; v < set.size(); ++v) ASSERT_TRUE(!set[v] || closed[v]);
      // No ball of radius r (2r + 1 voxels across) fits in a slot of at most 2r voxels.
      EXPECT_EQ(bool(closed[std::size_t(g.index(10, 7, 7))]), gap <= 2 * r) << "gap " << gap << " radius " << r;
      EXPECT_FALSE(closed[std::size_t(g.index(1, 7, 7))]);  // beyond the slabs: not filled
    }
}

TEST(BallMorphology, OpeningIsHeldByTheSetAndRemovesNecksThinnerThanTheBall) {
  const GridSpec g = grid(31, 15, 15);
  // Two 9^3 blocks joined by a square neck of side `neck` voxels along x.
  for (const int neck : {1, 3})
    for (const double r : {1.0, 2.0}) {
      std::vector<std::uint8_t> set(std::size_t(g.count()), 0);
      for (int k = 3; k < 12; ++k)
        for (int j = 3; j < 12; ++j)
          for (int i = 2; i < 29; ++i) {
            const bool block = i < 11 || i >= 20;
            const bool inNeck = std::abs(j - 7) * 2 < neck && std::abs(k - 7) * 2 < neck;
            if (block || inNeck) set[std::size_t(g.index(i, j, k))] = 1;
          }
      const std::vector<std::uint8_t> opened = ballOpening(set, g, r);
      for (std::size_t v = 0; v < set.size(); ++v) ASSERT_TRUE(!opened[v] || set[v]);
      EXPECT_TRUE(opened[std::size_t(g.index(6, 7, 7))]);  // the blocks' centres stay
      EXPECT_EQ(bool(opened[std::size_t(g.index(15, 7, 7))]), neck > 2 * r) << "neck " << neck << " radius " << r;
    }
  EXPECT_THROW(ballOpening(std::vector<std::uint8_t>(8, 0), grid(2, 2, 2), 0.0), std::invalid_argument);
}

// With a reach, the distances within it are the exact ones and the others are no nearer.
TEST(DistanceTransform, WithAReachTheNearDistancesAreExactAndTheFarOnesNoNearer) {
  for (int seed = 1; seed <= 20; ++seed) {
    std::mt19937 rng(static_cast<unsigned>(seed));
    const GridSpec g = grid(11 + seed % 5, 9 + seed % 7, 8 + seed % 3);
    std::bernoulli_distribution in(0.01 + 0.01 * (seed % 4));
    std::vector<std::uint8_t> set(std::size_t(g.count()));
    for (auto& v : set) v = in(rng);
    const double reach = 1.0 + seed % 4;
    const std::vector<float> exact = squaredDistanceToSet(set, g), near = squaredDistanceToSet(set, g, reach);
    for (std::size_t v = 0; v < set.size(); ++v) {
      if (exact[v] <= reach * reach) EXPECT_EQ(near[v], exact[v]) << "seed " << seed << ", voxel " << v;
      else EXPECT_GT(near[v], reach * reach) << "seed " << seed << ", voxel " << v;
    }
  }
}

// The closing and opening by brute force from their definitions (the union of the balls of radius
// r held by the set or its complement): at r = 1 the ball is the cross (no transform is used), at
// r = 2 the transforms shared by BallMorphology; both against the definition on random sets.
TEST(BallMorphology, ClosingAndOpeningEqualTheirDefinitionsAtOneAndTwoVoxels) {
  for (int seed = 1; seed <= 12; ++seed) {
    std::mt19937 rng(static_cast<unsigned>(seed));
    const GridSpec g = grid(9, 8, 7);
    std::bernoulli_distribution in(0.3 + 0.04 * (seed % 5));
    std::vector<std::uint8_t> set(std::size_t(g.count()));
    for (auto& v : set) v = in(rng);
    const BallMorphology m(set, g);
    for (const double r : {1.0, 2.0}) {
      // dilate(A)[v]: a voxel of A within r of v (beyond the grid: not in A).
      const auto dilate = [&](const std::vector<std::uint8_t>& a) {
        std::vector<std::uint8_t> out(a.size(), 0);
        for (int k = 0; k < g.dims[2]; ++k)
          for (int j = 0; j < g.dims[1]; ++j)
            for (int i = 0; i < g.dims[0]; ++i)
              for (int c = 0; c < g.dims[2]; ++c)
                for (int b = 0; b < g.dims[1]; ++b)
                  for (int a0 = 0; a0 < g.dims[0]; ++a0)
                    if (a[std::size_t(g.index(a0, b, c))] && (i - a0) * (i - a0) + (j - b) * (j - b) + (k - c) * (k - c) <= r * r)
                      out[std::size_t(g.index(i, j, k))] = 1;
        return out;
      };
      const auto complement = [](std::vector<std::uint8_t> a) {
        for (auto& v : a) v = !v;
        return a;
      };
      std::vector<std::uint8_t> closing = complement(dilate(complement(dilate(set))));
      std::vector<std::uint8_t> opening = dilate(complement(dilate(complement(set))));
      for (std::size_t v = 0; v < set.size(); ++v) closing[v] |= set[v], opening[v] &= set[v];
      EXPECT_EQ(m.closing(r), closing) << "seed " << seed << ", r " << r;
      EXPECT_EQ(m.opening(r), opening) << "seed " << seed << ", r " << r;
      EXPECT_EQ(ballClosing(set, g, r), closing);
      const BallMorphology reaching(set, g, 2.0);  // transforms that reach only as far as asked
      EXPECT_EQ(reaching.closing(r), closing);
      EXPECT_EQ(reaching.opening(r), opening);
    }
  }
}

// Random sets with solid cubes (whole windows inside the set), empty regions (windows skipped) and
// speckle, on grids that are no multiple of the block: the windowed closing and opening equal the
// dense ones at every voxel, for the cross and for balls whose windows span several blocks; padding
// moves the set without changing it or its Betti numbers.
TEST(BlockBallMorphology, EqualsTheDenseClosingAndOpeningAtEveryVoxel) {
  for (int seed = 1; seed <= 6; ++seed) {
    std::mt19937 rng(static_cast<unsigned>(seed));
    const GridSpec g = grid(45 + seed, 38, 29 + 2 * seed);
    std::vector<std::uint8_t> set(std::size_t(g.count()), 0);
    std::bernoulli_distribution speck(0.25);
    std::uniform_int_distribution<int> at(0, 60);
    for (int cube = 0; cube < 3; ++cube) {  // solid cubes of 20 voxels, some cut by the grid's faces
      const int x = at(rng) % (g.dims[0] - 5), y = at(rng) % (g.dims[1] - 5), z = at(rng) % (g.dims[2] - 5);
      for (int k = z; k < std::min(g.dims[2], z + 20); ++k)
        for (int j = y; j < std::min(g.dims[1], y + 20); ++j)
          for (int i = x; i < std::min(g.dims[0], x + 20); ++i) set[std::size_t(g.index(i, j, k))] = 1;
    }
    for (int k = 0; k < g.dims[2]; ++k)  // speckle in the lower third along x, the rest left as is
      for (int j = 0; j < g.dims[1]; ++j)
        for (int i = 0; i < g.dims[0] / 3; ++i)
          if (speck(rng)) set[std::size_t(g.index(i, j, k))] ^= 1;
    const BlockGrid<std::uint8_t> blocks = blockValues(set, g);
    for (const double r : {1.0, 1.5, 2.0, 2.6, 4.3}) {
      EXPECT_EQ(denseValues(blockBallClosing(blocks, r)), ballClosing(set, g, r)) << "seed " << seed << ", r " << r;
      EXPECT_EQ(denseValues(blockBallOpening(blocks, r)), ballOpening(set, g, r)) << "seed " << seed << ", r " << r;
    }
    const BlockGrid<std::uint8_t> padded = paddedBlockGrid(blocks, 2);
    ASSERT_EQ(padded.grid().dims[0], g.dims[0] + 32);
    EXPECT_EQ(padded.count(1), blocks.count(1));
    for (int k = 0; k < g.dims[2]; k += 3)
      for (int j = 0; j < g.dims[1]; j += 2)
        for (int i = 0; i < g.dims[0]; ++i) ASSERT_EQ(padded.at(i + 16, j + 16, k + 16), set[std::size_t(g.index(i, j, k))]);
    EXPECT_EQ(voxelBetti(padded), voxelBetti(set, g));
  }
}

}  // namespace

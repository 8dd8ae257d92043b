// Several materials, one solid each (issue 49; geometry/reconstruction/well_composed_labels.h): on
// random balls cut into 2-4 labels by random wavy planes, the labels made
// well-composed at once are still a partition of the same union; no label holds a critical
// configuration; each label's mesh (the pipeline's labelField, mesh_stage.cpp) has its voxels'
// Betti numbers; and the labels' meshes do not overlap (their volumes add up to no more than the
// union's).
// Where the union itself is not well-composed (pure noise), it only grows, and ends well-composed.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "geometry/core/digital_topology.h"
#include "geometry/meshing/mesh_topology.h"
#include "geometry/meshing/volume_mesher.h"
#include "geometry/reconstruction/voxel_labels.h"
#include "geometry/reconstruction/well_composed_labels.h"

using namespace xsect;

namespace {

std::vector<std::uint8_t> voxelsOf(const std::vector<std::uint16_t>& labels, int label /* -1: union */) {
  std::vector<std::uint8_t> in(labels.size());
  for (std::size_t q = 0; q < in.size(); ++q) in[q] = label < 0 ? labels[q] != 0 : labels[q] == label;
  return in;
}

/// Voxels a set needs to become well-composed (0: it is).
int criticalRepairs(std::vector<std::uint8_t> in, const GridSpec& g) { return makeWellComposed(in, g); }

/// A ball with a noisy boundary, made well-composed, cut into `count` labels by random planes
/// through it (label = 1 + the number of planes the voxel is beyond), each plane made wavy (an
/// amplitude of 0.5 to 1.5 voxels over 3 to 5 voxels): oblique steps and thin folds where voxels of
/// a label meet at an edge or a vertex only.
std::vector<std::uint16_t> randomLabelledBall(std::mt19937_64& rng, const GridSpec& g, int count) {
  std::uniform_real_distribution<double> u(0, 1);
  const Vec3 c(g.dims[0] / 2.0, g.dims[1] / 2.0, g.dims[2] / 2.0);
  const double radius = 0.3 * std::min({g.dims[0], g.dims[1], g.dims[2]}), noise = 0.4 * u(rng);
  std::vector<std::uint8_t> in(std::size_t(g.count()), 0);
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        const double d = (Vec3(i, j, k) - c).norm() - radius;
        in[std::size_t(g.index(i, j, k))] = d < -noise ? 1 : d > noise ? 0 : std::uint8_t(u(rng) < 0.5);
      }
  makeWellComposed(in, g);
  const double wave = 0.3 + 0.6 * u(rng);
  std::vector<std::pair<Vec3, double>> cuts;  // normal, offset through the ball
  for (int p = 0; p + 1 < count; ++p) {
    Vec3 n(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
    n.normalize();
    cuts.push_back({n, n.dot(c) + (u(rng) - 0.5) * radius});
  }
  std::vector<std::uint16_t> labels(in.size(), 0);
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        const std::int64_t v = g.index(i, j, k);
        if (!in[std::size_t(v)]) continue;
        int L = 1;
        for (const auto& [n, off] : cuts) {
          const Vec3 x(i, j, k);
          const double s = n.dot(x) - off + wave * std::sin(x[0] * 0.7 + x[1] * 0.5) * std::sin(x[2] * 0.6 - x[0] * 0.4);
          L += int(s > 0);
        }
        labels[std::size_t(v)] = std::uint16_t(L);
      }
  return labels;
}

}  // namespace

TEST(WellComposedLabels, EveryLabelWellComposedTheUnionKeptAndTheMeshesDoNotOverlap) {
  std::mt19937_64 rng(49);
  int runs = 0, criticalBefore = 0;
  std::int64_t relabelled = 0;
  double worstShare = 1;
  int labelsSeen = 0, labelsKept = 0;
  for (int trial = 0; trial < 24; ++trial) {
    GridSpec g;
    g.voxel = 0.5;
    g.dims = {26 + trial % 5, 28 - trial % 3, 24 + trial % 4};
    const int count = 2 + trial % 3;
    std::vector<std::uint16_t> labels = randomLabelledBall(rng, g, count);
    const std::vector<std::uint8_t> unionBefore = voxelsOf(labels, -1);
    ASSERT_EQ(criticalRepairs(unionBefore, g), 0);
    std::vector<Betti> bettiBefore;
    for (int L = 1; L <= count; ++L) {
      criticalBefore += criticalRepairs(voxelsOf(labels, L), g) > 0;
      bettiBefore.push_back(voxelBetti(voxelsOf(labels, L), g));
    }
    const LabelComposition r = makeLabelsWellComposed(labels, g);
    relabelled += r.voxels_relabelled;
    EXPECT_EQ(r.voxels_added, 0) << "trial " << trial;
    EXPECT_EQ(voxelsOf(labels, -1), unionBefore) << "trial " << trial;  // a partition of the same union
    // The union's field: -1 inside, +1 outside (its surface half-way between voxel centres).
    ScalarField field;
    field.grid = g;
    field.values.resize(labels.size());
    for (std::size_t q = 0; q < labels.size(); ++q) field.values[q] = labels[q] != 0 ? -1.f : 1.f;
    const double unionVolume = meshTopology(meshZeroLevel(field)).volume_mm3;
    double labelVolumes = 0;
    for (int L = 1; L <= count; ++L) {
      std::vector<std::uint8_t> in = voxelsOf(labels, L);
      if (std::find(in.begin(), in.end(), 1) == in.end()) continue;
      EXPECT_EQ(criticalRepairs(in, g), 0) << "trial " << trial << " label " << L;
      ScalarField f = labelField(field, labels, std::uint16_t(L), 0.05f);
      imposeSolid(f, in, 0.05f);
      const MeshTopology t = meshTopology(meshZeroLevel(f));
      EXPECT_TRUE(t.watertight) << "trial " << trial << " label " << L;
      EXPECT_EQ(t.betti, voxelBetti(in, g)) << "trial " << trial << " label " << L;
      ++labelsSeen;
      labelsKept += voxelBetti(in, g) == bettiBefore[std::size_t(L - 1)];
      labelVolumes += t.volume_mm3;
    }
    // The labels' surfaces meet where the mirrored field crosses zero, once: no overlap. Where a
    // label meets another and the outside in one cell, each mesh cuts its own corner and a sliver
    // between them is in neither (marching cubes per label): the sum falls short by that.
    EXPECT_LE(labelVolumes, unionVolume * (1 + 1e-6)) << "trial " << trial;
    worstShare = std::min(worstShare, labelVolumes / unionVolume);
    ++runs;
  }
  EXPECT_EQ(runs, 24);
  EXPECT_GT(criticalBefore, 12);  // the noisy interfaces made labels with critical configurations
  EXPECT_GT(relabelled, 100);
  std::cerr << "labels' meshes: at least " << worstShare << " of the union's volume; labels whose Betti numbers "
            << "(closed cubes) the composition kept: " << labelsKept << " of " << labelsSeen << "\n";
}

// Pure noise with several labels: the union is not well-composed; it only grows, and every label
// and the union end well-composed.
TEST(WellComposedLabels, NoiseUnionOnlyGrowsAndEndsWellComposed) {
  std::mt19937_64 rng(50);
  std::uniform_real_distribution<double> u(0, 1);
  std::int64_t added = 0;
  for (int trial = 0; trial < 20; ++trial) {
    GridSpec g;
    g.voxel = 1;
    g.dims = {14 + trial % 3, 15, 13 + trial % 4};
    const double density = 0.1 + 0.04 * trial;
    const int count = 2 + trial % 4;
    std::vector<std::uint16_t> labels(std::size_t(g.count()), 0);
    for (auto& l : labels) l = u(rng) < density ? std::uint16_t(1 + int(u(rng) * count)) : std::uint16_t(0);
    const std::vector<std::uint8_t> before = voxelsOf(labels, -1);
    const LabelComposition r = makeLabelsWellComposed(labels, g);
    added += r.voxels_added;
    const std::vector<std::uint8_t> after = voxelsOf(labels, -1);
    for (std::size_t q = 0; q < after.size(); ++q) ASSERT_GE(after[q], before[q]) << "trial " << trial;
    EXPECT_EQ(criticalRepairs(after, g), 0) << "trial " << trial;
    for (int L = 1; L <= count; ++L) EXPECT_EQ(criticalRepairs(voxelsOf(labels, L), g), 0) << "trial " << trial << " label " << L;
  }
  EXPECT_GT(added, 100);
}

// isSimpleCube against the Betti numbers of the union of closed cubes: on random 3x3x3
// neighbourhoods of every density (padded into a 5x5x5 grid), the neighbourhood with and without
// its centre has the same Betti numbers exactly when the centre is simple. (Simple implies the
// same homotopy type; not simple changes the Euler characteristic or, where K is disconnected or
// the sphere, b0 or b2.)
TEST(WellComposedLabels, SimpleCubeIsWhereTheCentreKeepsTheBettiNumbers) {
  std::mt19937_64 rng(51);
  std::uniform_real_distribution<double> u(0, 1);
  GridSpec g;
  g.voxel = 1;
  g.dims = {5, 5, 5};
  int simple = 0, notSimple = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const double density = 0.05 + 0.9 * u(rng);
    std::array<bool, 27> set{};
    for (bool& b : set) b = u(rng) < density;
    std::vector<std::uint8_t> with(std::size_t(g.count()), 0);
    for (int q = 0; q < 27; ++q)
      with[std::size_t(g.index(1 + q % 3, 1 + q / 3 % 3, 1 + q / 9))] = set[std::size_t(q)];
    with[std::size_t(g.index(2, 2, 2))] = 1;
    std::vector<std::uint8_t> without = with;
    without[std::size_t(g.index(2, 2, 2))] = 0;
    const bool same = voxelBetti(with, g) == voxelBetti(without, g);
    const bool s = isSimpleCube(set);
    EXPECT_EQ(s, same) << "trial " << trial;
    (s ? simple : notSimple) += 1;
  }
  EXPECT_GT(simple, 500);
  EXPECT_GT(notSimple, 500);
}

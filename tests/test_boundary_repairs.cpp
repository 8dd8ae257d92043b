// The repairs of method 3's glued boundary (geometry/delaunay/boundary_repairs.h) on meshes built
// by hand, under random rigid motions: dropFlatShells drops what bounds no volume (a sliver
// tetrahedron, a small open flat sheet) and keeps a solid and an open sheet too large to be a
// rounding artefact (a defect open_edges must report, not a repair's to hide).
#include <gtest/gtest.h>

#include <random>

#include "geometry/delaunay/boundary_repairs.h"
#include "random_motion.h"

using namespace xsect;

namespace {

/// Appends the closed tetrahedron (a, b, c, d) (positively oriented: d above abc) as four outward faces.
void addTetrahedron(std::vector<Vec3>& positions, std::vector<std::array<int, 3>>& faces, const Vec3& a, const Vec3& b,
                    const Vec3& c, const Vec3& d) {
  const int i = int(positions.size());
  positions.insert(positions.end(), {a, b, c, d});
  faces.push_back({i, i + 2, i + 1});
  faces.push_back({i, i + 1, i + 3});
  faces.push_back({i + 1, i + 2, i + 3});
  faces.push_back({i + 2, i, i + 3});
}

/// Appends a square of side s in the plane z = 0 around `at`, as two triangles (open: four
/// boundary edges in one face each).
void addSquare(std::vector<Vec3>& positions, std::vector<std::array<int, 3>>& faces, const Vec3& at, double s) {
  const int i = int(positions.size());
  positions.insert(positions.end(), {at, at + Vec3(s, 0, 0), at + Vec3(s, s, 0), at + Vec3(0, s, 0)});
  faces.push_back({i, i + 1, i + 2});
  faces.push_back({i, i + 2, i + 3});
}

}  // namespace

TEST(BoundaryRepairs, FlatShellsAreDroppedAndLargeOpenSheetsKept) {
  std::mt19937 rng(20261204);
  const double spacing = 0.3;  // mm: thickness bound 3e-4 mm, open-area bound 0.09 mm²
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<Vec3> positions;
    std::vector<std::array<int, 3>> faces;
    // Kept: a solid tetrahedron (mean thickness about 0.2 mm).
    addTetrahedron(positions, faces, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1});
    const std::size_t solidFaces = faces.size();
    // Dropped: a sliver (four nearly coplanar points, 1e-7 mm out of plane).
    addTetrahedron(positions, faces, {5, 0, 0}, {6, 0, 0}, {5, 1, 0}, {5.4, 0.4, 1e-7});
    // Dropped: a small open sheet (1e-4 mm²).
    addSquare(positions, faces, {10, 0, 0}, 0.01);
    // Kept: an open sheet of 1 mm² (a defect, not a rounding artefact).
    const std::size_t bigSheet = faces.size() + 2;
    addSquare(positions, faces, {15, 0, 0}, 1.0);
    const Eigen::Matrix3d R = test::randomRotation(rng);
    const Vec3 t(std::uniform_real_distribution<double>(-50, 50)(rng), 3.0 * trial, -7.0);
    for (Vec3& p : positions) p = R * p + t;
    const std::vector<std::array<int, 3>> before = faces;
    EXPECT_EQ(dropFlatShells(faces, positions, 1e-3 * spacing, spacing * spacing), 2) << "trial " << trial;
    ASSERT_EQ(faces.size(), solidFaces + 2) << "trial " << trial;
    for (std::size_t f = 0; f < solidFaces; ++f) EXPECT_EQ(faces[f], before[f]);
    EXPECT_EQ(faces[solidFaces], before[bigSheet - 2]);
    EXPECT_EQ(faces[solidFaces + 1], before[bigSheet - 1]);
    // The big sheet's four boundary edges stay open: what open_edges counts.
    int open = 0;
    for (const auto& [key, n] : edgeUses(faces)) open += n % 2;
    EXPECT_EQ(open, 4);
  }
}

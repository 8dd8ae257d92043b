// Acceptance (issue 20): a .contour file written here (Ctr2Suf layout: per plane its equation,
// vertices and edges "i j left right") with two materials, one with a hole through it, on
// non-parallel planes, reconstructs each material with its own Betti numbers.
// Material 1: an annular cylinder (radii 4 and 10 mm, |z| <= 5 mm), a solid torus (1, 1, 0).
// Material 2: a box [16, 24] x [-4, 4] x [-5, 5] mm, a ball (1, 0, 0).
// Planes: z = -4.5 .. 4.5 mm every 1 mm, and the vertical planes y = 0.5 and y = -2.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "phantom_runs.h"

namespace xsect {
namespace {

/// Writes .contour planes: each polygon given in a plane frame (u, v) with u x v = n, counter-
/// clockwise for a solid's outer boundary and clockwise for a hole, its material on the left.
class ContourText {
 public:
  void plane(const Vec3& n, const Vec3& point, const Vec3& u, const Vec3& v,
             const std::vector<std::pair<int, std::vector<Vec2>>>& loops) {
    std::ostringstream p;
    p.precision(17);
    p << n.x() << " " << n.y() << " " << n.z() << " " << -n.dot(point) << "\n";
    std::size_t nv = 0;
    for (const auto& l : loops) nv += l.second.size();
    p << nv << " " << nv << "\n";
    std::ostringstream edges;
    std::size_t first = 0;
    for (const auto& [material, ring] : loops) {
      for (std::size_t k = 0; k < ring.size(); ++k) {
        const Vec3 x = point + ring[k].x() * u + ring[k].y() * v;
        p << x.x() << " " << x.y() << " " << x.z() << "\n";
        edges << first + k << " " << first + (k + 1) % ring.size() << " " << material << " 0\n";
      }
      first += ring.size();
    }
    text_ += p.str() + edges.str();
    ++planes_;
  }
  std::string str() const { return std::to_string(planes_) + "\n" + text_; }

 private:
  std::string text_;
  int planes_ = 0;
};

std::vector<Vec2> circle(double r, bool clockwise) {
  std::vector<Vec2> c;
  for (int k = 0; k < 128; ++k) {
    const double a = (clockwise ? -1 : 1) * 2 * M_PI * k / 128;
    c.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  return c;
}

std::vector<Vec2> rectangle(double a0, double a1, double b0, double b1) {
  return {{a0, b0}, {a1, b0}, {a1, b1}, {a0, b1}};
}

TEST(AcceptanceContour, TwoMaterialsOnNonParallelPlanesHaveTheirOwnBettiNumbers) {
  ContourText t;
  for (int k = 0; k < 10; ++k)
    t.plane(Vec3::UnitZ(), Vec3(0, 0, -4.5 + k), Vec3::UnitX(), Vec3::UnitY(),
            {{1, circle(10, false)}, {1, circle(4, true)}, {2, rectangle(16, 24, -4, 4)}});
  for (const double y : {0.5, -2.0}) {
    // Plane y = c, frame u = z, v = x (u x v = y): the annulus gives two rectangles, the box one.
    const double x0 = std::sqrt(16 - y * y), x1 = std::sqrt(100 - y * y);
    t.plane(Vec3::UnitY(), Vec3(0, y, 0), Vec3::UnitZ(), Vec3::UnitX(),
            {{1, rectangle(-5, 5, x0, x1)}, {1, rectangle(-5, 5, -x1, -x0)}, {2, rectangle(-5, 5, 16, 24)}});
  }
  const auto dir = test::freshDir("contour_materials");
  test::writeFile(dir / "two.contour", t.str());
  test::writeFile(dir / "config.yaml", "input: {contour: two.contour}\nreconstruction: {voxel_size_mm: 0.4}\n");
  const auto r = test::runXsect("run " + (dir / "config.yaml").string() + " --out " + (dir / "out").string() + " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json report = test::readJson(dir / "out/report.json");
  EXPECT_EQ(report["reconstruction"]["planes"], "whole");  // contour files: all of O ∩ P
  EXPECT_EQ(report["betti"], (std::vector<int>{2, 1, 0}));
  ASSERT_EQ(report["materials"].size(), 2u);
  EXPECT_EQ(report["materials"][0]["label"], 1);
  EXPECT_EQ(report["materials"][1]["label"], 2);
  for (const auto& m : report["materials"]) {
    SCOPED_TRACE(m.dump());
    if (m["label"] == 1) EXPECT_EQ(m["betti"], (std::vector<int>{1, 1, 0}));
    if (m["label"] == 2) EXPECT_EQ(m["betti"], (std::vector<int>{1, 0, 0}));
    EXPECT_TRUE(m["watertight"].get<bool>());
  }
  // Volumes: the annular cylinder 10 * pi * (100 - 16) = 2639 mm³, the box 640 mm³, within the
  // caps the method adds beyond the last planes (half a millimetre of each end at most) and a voxel.
  for (const auto& m : report["materials"]) {
    const double v = m["volume_mm3"].get<double>();
    if (m["label"] == 1) EXPECT_NEAR(v, 10 * M_PI * 84, 0.15 * 10 * M_PI * 84);
    if (m["label"] == 2) EXPECT_NEAR(v, 640, 0.15 * 640);
  }
}

}  // namespace
}  // namespace xsect

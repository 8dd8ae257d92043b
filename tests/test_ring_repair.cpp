// Issue 49, crossing contours repaired: figure eights, overlapping rings, rings touching at a
// vertex, holes crossing their outer ring, and random self-crossing polygons come out as simple
// rings bounding the region the stated rule gives (geometry/core/ring_repair.h: each ring's lobes
// by the even-odd rule, then positive winding with outer rings +1 and holes -1), checked point by
// point against that rule evaluated directly on the input; through `xsect run`, .csl and .contour
// files with such rings run with a warning, and input.repair_contours: false refuses them.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <random>

#include "cli.h"
#include "geometry/core/polygon.h"
#include "geometry/core/ring_repair.h"
#include "geometry/core/ring_validity.h"
#include "segmentation/segment_slice.h"

using namespace xsect;
namespace fs = std::filesystem;

namespace {

/// Crossings of the ray from p along +x with the ring's edges (half-open rule), signed by the
/// edge's direction: the winding number of the ring around p.
int winding(const Ring& r, const Vec2& p) {
  int w = 0;
  for (std::size_t i = 0, n = r.size(); i < n; ++i) {
    const Vec2 &a = r[i], &b = r[(i + 1) % n];
    if ((a.y() <= p.y()) != (b.y() <= p.y())) {
      const double x = a.x() + (p.y() - a.y()) / (b.y() - a.y()) * (b.x() - a.x());
      if (x > p.x()) w += b.y() > a.y() ? 1 : -1;
    }
  }
  return w;
}

/// The rule on the input rings directly: lobes by even-odd, outer +1, holes -1, inside if > 0.
bool ruleInside(const std::vector<Ring>& outers, const std::vector<Ring>& holes, const Vec2& p) {
  int w = 0;
  for (const Ring& r : outers) w += winding(r, p) % 2 != 0;
  for (const Ring& r : holes) w -= winding(r, p) % 2 != 0;
  return w > 0;
}

bool repairedInside(const RingRepair& r, const Vec2& p) {
  for (const Section& s : sectionsFromRings(r.outers, r.holes))
    if (sectionContains(s, p)) return true;
  return false;
}

double distanceToRings(const std::vector<Ring>& rings, const Vec2& p) {
  double d = 1e300;
  for (const Ring& r : rings) d = std::min(d, ringDistance(r, p));
  return d;
}

/// Every repaired ring is simple, outer rings counter-clockwise and holes clockwise, and the region
/// is the rule's at `samples` random points of the box (away from the rings by 1e-6).
void expectRuleRegion(const std::vector<Ring>& outers, const std::vector<Ring>& holes, std::mt19937& rng,
                      int samples = 400) {
  const RingRepair r = repairRings(outers, holes);
  for (const Ring& o : r.outers) {
    EXPECT_TRUE(ringIsSimple(o));
    EXPECT_GT(signedArea(o), 0);
  }
  for (const Ring& h : r.holes) {
    EXPECT_TRUE(ringIsSimple(h));
    EXPECT_LT(signedArea(h), 0);
  }
  std::vector<Ring> all = outers;
  all.insert(all.end(), holes.begin(), holes.end());
  Vec2 lo = Vec2::Constant(1e300), hi = -lo;
  for (const Ring& q : all)
    for (const Vec2& p : q) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  std::uniform_real_distribution<double> ux(lo.x(), hi.x()), uy(lo.y(), hi.y());
  int wrong = 0;
  double area = 0;
  for (int k = 0; k < samples; ++k) {
    const Vec2 p(ux(rng), uy(rng));
    if (distanceToRings(all, p) < 1e-6) continue;
    const bool want = ruleInside(outers, holes, p);
    wrong += want != repairedInside(r, p);
    area += want;
  }
  EXPECT_EQ(wrong, 0);
  // The area by the samples and the repair's own agree to the sampling's error.
  const double box = (hi - lo).prod();
  EXPECT_NEAR(r.area_after, box * area / samples, 4 * box / std::sqrt(double(samples)) + 1e-9);
}

Ring square(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }

/// The four vertex lines "x y z" of plane z of a prism whose middle plane (z = 1) holds a bow tie
/// (its lobes net no area) and the others a square.
std::string bowTiePlane(int z) {
  const double bowTie[4][2] = {{0, 0}, {2, 2}, {2, 0}, {0, 2}};
  const double square[4][2] = {{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  std::string lines;
  for (int v = 0; v < 4; ++v) {
    const auto& q = z == 1 ? bowTie[v] : square[v];
    lines += std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(z) + "\n";
  }
  return lines;
}

}  // namespace

TEST(RingRepair, SimpleDisjointRingsAreReturnedAsGiven) {
  const std::vector<Ring> outers = {square(0, 0, 10, 10), square(4, 4, 5, 5), square(20, 0, 21, 1)};
  const std::vector<Ring> holes = {[] { Ring h = square(2, 2, 8, 8); std::reverse(h.begin(), h.end()); return h; }()};
  const RingRepair r = repairRings(outers, holes);
  EXPECT_FALSE(r.changed);
  EXPECT_EQ(r.outers, outers);
  EXPECT_EQ(r.holes, holes);
}

TEST(RingRepair, AHoleTouchingItsOuterRingAtEveryVertexIsKept) {
  // A diamond hole on the midpoints of a square's sides: every hole vertex on the outer ring.
  Ring hole = {{1, 0}, {2, 1}, {1, 2}, {0, 1}};
  std::reverse(hole.begin(), hole.end());
  const RingRepair r = repairRings({{{0, 0}, {1, 0}, {2, 0}, {2, 1}, {2, 2}, {1, 2}, {0, 2}, {0, 1}}}, {hole});
  const std::vector<Section> s = sectionsFromRings(r.outers, r.holes);
  double area = 0;
  for (const Section& sec : s) {
    area += std::abs(signedArea(sec.outer));
    for (const Ring& h : sec.holes) area -= std::abs(signedArea(h));
  }
  EXPECT_NEAR(area, 2.0, 1e-12);  // 4 minus the diamond's 2
}

TEST(RingRepair, FigureEightOverlapsTouchingAndCrossingHoles) {
  std::mt19937 rng(7);
  // A figure eight (a bow tie): two lobes, each once; its signed area nets zero.
  const Ring eight = {{0, 0}, {2, 2}, {2, 0}, {0, 2}};
  RingRepair r = repairRings({eight}, {});
  EXPECT_TRUE(r.changed);
  EXPECT_EQ(r.outers.size(), 2u);
  EXPECT_NEAR(r.area_after, 2.0, 1e-12);  // two triangles of base 2, height 1
  // A ring around a square twice: winding 2, even-odd 0: nothing (its lobes by the even-odd rule).
  r = repairRings({{{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0.5}, {0.5, 0}, {1, 0.5}, {0.5, 1}}}, {});
  expectRuleRegion({{{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0.5}, {0.5, 0}, {1, 0.5}, {0.5, 1}}}, {}, rng);
  expectRuleRegion({eight}, {}, rng);
  // Two overlapping squares: their union, one ring.
  r = repairRings({square(0, 0, 2, 2), square(1, 1, 3, 3)}, {});
  EXPECT_EQ(r.outers.size(), 1u);
  EXPECT_NEAR(r.area_after, 7.0, 1e-12);
  // A ring touching itself at a vertex: two rings meeting there.
  const Ring bow = {{0, 0}, {2, 1}, {4, 0}, {4, 2}, {2, 1}, {0, 2}};
  r = repairRings({bow}, {});
  EXPECT_EQ(r.outers.size(), 2u);
  EXPECT_NEAR(r.area_after, 4.0, 1e-12);
  expectRuleRegion({bow}, {}, rng);
  // A hole reaching outside its outer ring removes only what lies inside: a notch.
  Ring hole = square(3, 1, 5, 2);
  std::reverse(hole.begin(), hole.end());
  r = repairRings({square(0, 0, 4, 4)}, {hole});
  EXPECT_EQ(r.outers.size(), 1u);
  EXPECT_EQ(r.holes.size(), 0u);
  EXPECT_NEAR(r.area_after, 15.0, 1e-12);
  expectRuleRegion({square(0, 0, 4, 4)}, {hole}, rng);
  // Two holes crossing each other inside an outer ring: their union removed, one hole.
  Ring h2 = square(2, 2, 5, 4);
  std::reverse(h2.begin(), h2.end());
  Ring h1 = square(1, 1, 3, 3);
  std::reverse(h1.begin(), h1.end());
  r = repairRings({square(0, 0, 6, 6)}, {h1, h2});
  EXPECT_EQ(r.holes.size(), 1u);
  EXPECT_NEAR(r.area_after, 36.0 - (4.0 + 6.0 - 1.0), 1e-12);
  // A hole crossing an outer ring and reaching past it: nothing of it outside the outer ring counts.
  Ring h3 = square(-1, 0.5, 0.5, 0.7);
  std::reverse(h3.begin(), h3.end());
  r = repairRings({square(0, 0, 1, 1)}, {h3});
  EXPECT_NEAR(r.area_after, 1.0 - 0.5 * 0.2, 1e-12);
  // Rings touching at a shared vertex only are already simple and disjoint: returned as given.
  EXPECT_FALSE(repairRings({square(0, 0, 1, 1), square(1, 1, 2, 2)}, {}).changed);
  EXPECT_FALSE(repairRings({{{-1, -1}, {0, 0}, {1, -1}}, {{-1, 1}, {0, 0}, {-1, 0.5}}}, {}).changed);
  // ... but two rings crossing at a shared vertex (one along y = x, the other along y = -x
  // through it) are not.
  EXPECT_TRUE(repairRings({{{-2, -2}, {0, 0}, {2, 2}, {-2, 3}}, {{2, -2}, {0, 0}, {-2, 2}, {-3, -3}}}, {}).changed);
  expectRuleRegion({{{-2, -2}, {0, 0}, {2, 2}, {-2, 3}}, {{2, -2}, {0, 0}, {-2, 2}, {-3, -3}}}, {}, rng);
}

TEST(RingRepair, RandomSelfCrossingPolygonsFollowTheRule) {
  // 150 random polygons of 5 to 40 vertices (most cross themselves), alone, paired with an
  // overlapping outer ring, or with a random hole.
  std::mt19937 rng(49);
  std::uniform_real_distribution<double> u(0, 10);
  std::uniform_int_distribution<int> count(5, 40);
  int crossing = 0;
  for (int k = 0; k < 150; ++k) {
    const auto randomRing = [&] {
      Ring r;
      const int n = count(rng);
      for (int i = 0; i < n; ++i) r.emplace_back(u(rng), u(rng));
      return r;
    };
    const Ring a = randomRing();
    crossing += !ringIsSimple(a);
    SCOPED_TRACE(k);
    if (k % 3 == 0) expectRuleRegion({a}, {}, rng, 200);
    if (k % 3 == 1) expectRuleRegion({a, randomRing()}, {}, rng, 200);
    if (k % 3 == 2) expectRuleRegion({a}, {randomRing()}, rng, 200);
  }
  EXPECT_GE(crossing, 100);
}

TEST(RingRepair, SimplifiedImageContoursThatCrossAreMadeSimple) {
  // Thin-walled rings (a disk with a hole 2 to 5 pixels from its edge): a Douglas-Peucker
  // tolerance wider than the wall moves the outer ring's chords across the hole's. Every section
  // comes out with simple rings.
  int repaired = 0;
  for (int k = 0; k < 30; ++k) {
    cv::Mat m = cv::Mat::zeros(120, 120, CV_8U);
    const int outer = 40 + k % 7, wall = 2 + k % 4;
    cv::circle(m, {60 + k % 3, 60}, outer, 255, -1);
    cv::circle(m, {60 + k % 3 + (k % 2), 60}, outer - wall, 0, -1);
    SegmentationParams p;
    p.simplify_mm = 0.2 * (4 + k % 5);
    const SegmentedSlice s = segmentSlice(m, cv::Mat(), Vec2(0.2, 0.2), p);
    repaired += s.contours_repaired;
    std::vector<Ring> rings;
    for (const Section& sec : s.sections) {
      rings.push_back(sec.outer);
      for (const Ring& h : sec.holes) rings.push_back(h);
    }
    for (const Ring& r : rings) EXPECT_TRUE(ringIsSimple(r)) << k;
  }
  EXPECT_GT(repaired, 0);
}

TEST(RingRepair, CslAndContourFilesWithCrossingRingsRunAndFalseRefuses) {
  const fs::path dir = test::freshDir("ring-repair");
  // Three planes z = 0, 1, 2; the middle plane's ring is a bow tie (its lobes net no area).
  std::string csl = "CSLC\n3 1\n\n";
  for (int z = 0; z < 3; ++z)
    csl += std::to_string(z + 1) + " 4 1 0 0 1 " + std::to_string(-z) + "\n\n" + bowTiePlane(z) + "\n4 1 0 1 2 3\n\n";
  test::writeFile(dir / "eight.csl", csl);
  test::writeFile(dir / "config.yaml", "input:\n  csl: eight.csl\nreconstruction:\n  voxel_size_mm: 0.1\n");
  auto r = test::runXsect("run " + (dir / "config.yaml").string() + " --out " + (dir / "out").string() + " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string report = test::slurp(dir / "out/report.json");
  EXPECT_NE(report.find("plane 2: crossing contours made simple (1 outer rings and 0 holes -> 2 and 0"),
            std::string::npos);
  r = test::runXsect("run " + (dir / "config.yaml").string() + " --out " + (dir / "out2").string() +
                     " --quiet --set input.repair_contours=false");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("plane 2 component 0"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("crosses itself"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out2"));
  // The same planes as a .contour file (material 1 on the left of each edge).
  std::string contour = "3\n";
  for (int z = 0; z < 3; ++z)
    contour += "0 0 1 " + std::to_string(-z) + "\n4 4\n" + bowTiePlane(z) + "0 1 1 0\n1 2 1 0\n2 3 1 0\n3 0 1 0\n";
  test::writeFile(dir / "eight.contour", contour);
  test::writeFile(dir / "contour.yaml", "input:\n  contour: eight.contour\nreconstruction:\n  voxel_size_mm: 0.1\n");
  r = test::runXsect("run " + (dir / "contour.yaml").string() + " --out " + (dir / "out3").string() + " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(test::slurp(dir / "out3/report.json").find("plane 2 material 1: crossing contours made simple"),
            std::string::npos);
  r = test::runXsect("run " + (dir / "contour.yaml").string() + " --out " + (dir / "out4").string() +
                     " --quiet --set input.repair_contours=false");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("crosses itself"), std::string::npos) << r.err;
  fs::remove_all(dir);
}

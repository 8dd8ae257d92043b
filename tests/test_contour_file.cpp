// Ctr2Suf .contour files (io/contour_file.h): a hand-written two-material file on three
// non-parallel planes (sections, holes, areas, orientation, the union across a shared edge), the
// edges' two spellings (i j left right = j i right left), contours touching at a vertex, and
// malformed files, each an InputError naming the file and the field.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "cli.h"
#include "geometry/core/polygon.h"
#include "io/contour_file.h"
#include "io/input_error.h"

namespace fs = std::filesystem;
using namespace xsect;

namespace {

/// One plane of a .contour file as text: equation, vertex lines, edge lines ("i j left right").
struct PlaneText {
  std::string equation;
  std::vector<std::string> vertices, edges;
};

// Material 1 an annulus (square 4 × 4 minus the square 2 × 2 in its middle) on every plane, material
// 2 a square beside it: on z = 0 sharing the annulus's edge x = 4 (listed once, left 1 right 2),
// elsewhere apart. Hole edges are written both ways (material 1 on the left of a clockwise hole,
// or material 0 on the left of a counter-clockwise one).
const PlaneText kZ0{"0 0 1 0",
                    {"0 0 0", "4 0 0", "4 4 0", "0 4 0",  // annulus outer
                     "1 1 0", "3 1 0", "3 3 0", "1 3 0",  // its hole
                     "6 0 0", "6 4 0"},                   // material 2: (4,0) (6,0) (6,4) (4,4)
                    {"0 1 1 0", "1 2 1 2", "2 3 1 0", "3 0 1 0",  // 1 2: the shared edge
                     "4 7 1 0", "7 6 1 0", "5 6 0 1", "4 5 0 1",  // hole
                     "1 8 2 0", "8 9 2 0", "9 2 2 0"}};
// x = 0, plane coordinates (y, z): annulus [0,4]² - [1,3]², material 2 [5,6] × [0,2] (area 2).
const PlaneText kX0{"1 0 0 0",
                    {"0 0 0", "0 4 0", "0 4 4", "0 0 4",
                     "0 1 1", "0 3 1", "0 3 3", "0 1 3",
                     "0 5 0", "0 6 0", "0 6 2", "0 5 2"},
                    {"0 1 1 0", "1 2 1 0", "2 3 1 0", "3 0 1 0",
                     "4 7 1 0", "7 6 1 0", "6 5 1 0", "5 4 1 0",
                     "8 9 2 0", "9 10 2 0", "10 11 2 0", "11 8 2 0"}};
// x + z = 10, vertices (s, y, 10 - s): (s, y) is right-handed about the normal (1, 0, 1) and scales
// areas by √2. Annulus s, y in [0,4]² - [1,3]², material 2 [5,7] × [0,2] (area 4√2).
const PlaneText kTilted{"1 0 1 -10",
                        {"0 0 10", "4 0 6", "4 4 6", "0 4 10",
                         "1 1 9", "3 1 7", "3 3 7", "1 3 9",
                         "5 0 5", "7 0 3", "7 2 3", "5 2 5"},
                        {"0 1 1 0", "1 2 1 0", "2 3 1 0", "3 0 1 0",
                         "4 5 0 1", "5 6 0 1", "6 7 0 1", "7 4 0 1",
                         "8 9 2 0", "9 10 2 0", "10 11 2 0", "11 8 2 0"}};

/// The edge "i j l r" as "j i r l".
std::string flipped(const std::string& edge) {
  std::istringstream ss(edge);
  std::string i, j, l, r;
  ss >> i >> j >> l >> r;
  return j + " " + i + " " + r + " " + l;
}

/// The file's text: `count` planes announced (-1: as many as given), edges flipped when asked.
std::string fileText(const std::vector<PlaneText>& planes, bool flip = false, int count = -1) {
  std::string s = std::to_string(count < 0 ? int(planes.size()) : count) + "\n";
  for (const PlaneText& p : planes) {
    s += p.equation + "\n" + std::to_string(p.vertices.size()) + " " + std::to_string(p.edges.size()) + "\n";
    for (const auto& v : p.vertices) s += v + "\n";
    for (const auto& e : p.edges) s += (flip ? flipped(e) : e) + "\n";
  }
  return s;
}

struct TempFiles {
  fs::path dir = test::freshDir("contour");
  ~TempFiles() { fs::remove_all(dir); }
  std::string write(const std::string& name, const std::string& text) const {
    test::writeFile(dir / name, text);
    return (dir / name).string();
  }
};

std::vector<const Section*> withLabel(const std::vector<Section>& sections, int label) {
  std::vector<const Section*> out;
  for (const Section& s : sections)
    if (s.label == label) out.push_back(&s);
  return out;
}

void expectOriented(const Section& s) {
  EXPECT_GT(signedArea(s.outer), 0);
  for (const Ring& h : s.holes) EXPECT_LT(signedArea(h), 0);
}

/// The message of the InputError reading `path` throws ("" if none).
std::string errorOf(const std::string& path) {
  try {
    readContourFile(path);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError for " << path;
  return "";
}

}  // namespace

TEST(ContourFile, TwoMaterialsOnThreePlanes) {
  TempFiles t;
  const std::string path = t.write("two.contour", fileText({kZ0, kX0, kTilted}));
  std::vector<std::string> warnings;
  const ContourFile cf = readContourFile(path, &warnings);
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(cf.materials, (std::vector<int>{1, 2}));
  ASSERT_EQ(cf.planes.size(), 3u);
  ASSERT_EQ(cf.labelled.size(), 3u);
  const double r2 = std::sqrt(2.0);
  const double scale[3] = {1, 1, r2};            // area factor of each plane's parametrisation
  const double area2[3] = {8, 2, 4};             // material 2 before scaling
  for (int p = 0; p < 3; ++p) {
    SCOPED_TRACE("plane " + std::to_string(p + 1));
    const CuttingPlane& cp = cf.planes[p];
    EXPECT_EQ(cp.slice, p);
    EXPECT_EQ(cp.name, "plane " + std::to_string(p + 1));
    EXPECT_TRUE(cp.observed_everywhere);
    EXPECT_NEAR(cp.plane.u.cross(cp.plane.v).dot(cp.plane.normal), 1.0, 1e-12);
    // material 1: one annulus
    const auto m1 = withLabel(cf.labelled[p], 1);
    ASSERT_EQ(m1.size(), 1u);
    ASSERT_EQ(m1[0]->holes.size(), 1u);
    EXPECT_NEAR(signedArea(m1[0]->outer), 16 * scale[p], 1e-9);
    EXPECT_NEAR(signedArea(m1[0]->holes[0]), -4 * scale[p], 1e-9);
    EXPECT_NEAR(sectionArea(*m1[0]), 12 * scale[p], 1e-9);
    expectOriented(*m1[0]);
    // material 2: one square
    const auto m2 = withLabel(cf.labelled[p], 2);
    ASSERT_EQ(m2.size(), 1u);
    EXPECT_TRUE(m2[0]->holes.empty());
    EXPECT_NEAR(sectionArea(*m2[0]), area2[p] * scale[p], 1e-9);
    expectOriented(*m2[0]);
    EXPECT_EQ(cf.labelled[p].size(), 2u);
    for (const Section& s : cp.sections) {
      EXPECT_EQ(s.label, 1);
      expectOriented(s);
    }
  }
  // the union: on z = 0 the two materials share an edge and make one section (the annulus's hole
  // kept); elsewhere two
  ASSERT_EQ(cf.planes[0].sections.size(), 1u);
  EXPECT_EQ(cf.planes[0].sections[0].holes.size(), 1u);
  EXPECT_NEAR(sectionArea(cf.planes[0].sections[0]), 20.0, 1e-9);
  EXPECT_EQ(cf.planes[0].sections[0].outer.size(), 6u);  // (4,0) and (4,4) stay vertices
  for (int p : {1, 2}) {
    ASSERT_EQ(cf.planes[p].sections.size(), 2u);
    double total = 0;
    for (const Section& s : cf.planes[p].sections) total += sectionArea(s);
    EXPECT_NEAR(total, (12 + area2[p]) * scale[p], 1e-9);
  }
  // frames: the normals are the equations', the vertices lie on the planes
  EXPECT_TRUE(cf.planes[0].plane.normal.isApprox(Vec3(0, 0, 1)));
  EXPECT_TRUE(cf.planes[1].plane.normal.isApprox(Vec3(1, 0, 0)));
  EXPECT_TRUE(cf.planes[2].plane.normal.isApprox(Vec3(1, 0, 1) / r2));
  EXPECT_NEAR(cf.planes[2].plane.signedDistance(Vec3(5, 0, 5)), 0.0, 1e-12);
  const Vec3 corner = cf.planes[2].plane.toWorld(cf.planes[2].sections[0].outer[0]);
  EXPECT_NEAR(corner.x() + corner.z(), 10.0, 1e-9);
  // extent: the union's bounds in plane coordinates (z = 0: u = y in [0,4], v = -x in [-6,0])
  EXPECT_NEAR(cf.planes[0].extent.max.x() - cf.planes[0].extent.min.x(), 4.0, 1e-12);
  EXPECT_NEAR(cf.planes[0].extent.max.y() - cf.planes[0].extent.min.y(), 6.0, 1e-12);
}

TEST(ContourFile, EitherSpellingOfAnEdgeGivesTheSameSections) {
  TempFiles t;
  const ContourFile a = readContourFile(t.write("a.contour", fileText({kZ0, kX0, kTilted})));
  const ContourFile b = readContourFile(t.write("b.contour", fileText({kZ0, kX0, kTilted}, true)));
  EXPECT_EQ(a.materials, b.materials);
  ASSERT_EQ(a.planes.size(), b.planes.size());
  ASSERT_EQ(a.labelled.size(), b.labelled.size());
  const auto summary = [](const std::vector<Section>& sections) {
    std::vector<std::tuple<int, double, std::size_t, double, double>> s;  // label, area, holes, bounds
    for (const Section& x : sections) {
      const auto box = ringBounds(x.outer);
      s.emplace_back(x.label, std::round(sectionArea(x) * 1e9), x.holes.size(), std::round(box.min().x() * 1e9),
                     std::round(box.max().y() * 1e9));
    }
    std::sort(s.begin(), s.end());
    return s;
  };
  for (std::size_t p = 0; p < a.planes.size(); ++p) {
    SCOPED_TRACE("plane " + std::to_string(p + 1));
    EXPECT_TRUE(a.planes[p].plane.origin.isApprox(b.planes[p].plane.origin));
    EXPECT_EQ(summary(a.planes[p].sections), summary(b.planes[p].sections));
    EXPECT_EQ(summary(a.labelled[p]), summary(b.labelled[p]));
  }
}

// Two squares of one material touching at a corner are two sections (not one figure-eight ring);
// a file with a single material (3) has no labelled sections; a plane without vertices is empty.
TEST(ContourFile, ContoursTouchingAtAVertexStaySeparate) {
  TempFiles t;
  const PlaneText pinch{"0 0 1 0",
                        {"0 0 0", "2 0 0", "2 2 0", "0 2 0", "4 2 0", "4 4 0", "2 4 0"},
                        {"0 1 3 0", "1 2 3 0", "2 3 3 0", "3 0 3 0",
                         "2 4 3 0", "4 5 3 0", "5 6 3 0", "6 2 3 0"}};
  const PlaneText empty{"0 0 1 -1", {}, {}};
  std::vector<std::string> warnings;
  const ContourFile cf = readContourFile(t.write("pinch.contour", fileText({pinch, empty})), &warnings);
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(cf.materials, std::vector<int>{3});
  EXPECT_TRUE(cf.labelled.empty());
  ASSERT_EQ(cf.planes.size(), 2u);
  ASSERT_EQ(cf.planes[0].sections.size(), 2u);
  for (const Section& s : cf.planes[0].sections) {
    EXPECT_EQ(s.label, 1);
    EXPECT_EQ(s.outer.size(), 4u);
    EXPECT_NEAR(signedArea(s.outer), 4.0, 1e-12);
  }
  EXPECT_TRUE(cf.planes[1].sections.empty());
  EXPECT_NEAR(std::abs(cf.planes[1].plane.origin.z()), 1.0, 1e-12);
}

TEST(ContourFile, MalformedFilesNameTheFileAndTheField) {
  TempFiles t;
  const auto edited = [](PlaneText p, std::size_t e, const std::string& edge) {
    p.edges[e] = edge;
    return p;
  };
  struct Case {
    std::string name, text;
    std::vector<std::string> mentions;
  };
  PlaneText nanVertex = kZ0, infNormal = kZ0, notClosed = kZ0, offPlane = kZ0;
  nanVertex.vertices[2] = "4 nan 0";
  infNormal.equation = "0 0 inf 0";
  notClosed.edges.erase(notClosed.edges.begin() + 5);  // a hole edge of material 1
  offPlane.vertices[3] = "0 4 1";
  PlaneText swapped = kX0;  // every material on the wrong side: material 1 unbounded
  for (auto& e : swapped.edges) {
    std::istringstream ss(e);
    std::string i, j, l, r;
    ss >> i >> j >> l >> r;
    e = i + " " + j + " " + r + " " + l;
  }
  const std::vector<Case> cases = {
      {"count.contour", fileText({kZ0, kX0}, false, 3), {"plane 3", "end of file"}},
      {"huge.contour", "999999999\n0 0 1 0\n0 0\n", {"plane count"}},
      {"index.contour", fileText({kZ0, edited(kX0, 7, "5 12 1 0")}), {"plane 2 edge 7", "out of range"}},
      {"nan.contour", fileText({nanVertex}), {"plane 1 vertex 2", "nan"}},
      {"inf.contour", fileText({infNormal}), {"plane 1 normal", "inf"}},
      {"same.contour", fileText({edited(kZ0, 1, "1 2 1 1")}), {"plane 1 edge 1", "both sides"}},
      {"negative.contour", fileText({edited(kZ0, 0, "0 1 -1 0")}), {"plane 1 edge 0", "material"}},
      {"open.contour", fileText({kX0, notClosed}), {"plane 2 material 1", "closed contours"}},
      {"twice.contour", fileText({edited(kZ0, 10, "2 1 2 1")}), {"plane 1 edge 10", "twice"}},
      {"junk.contour", fileText({kZ0}) + "7\n", {"after the last plane"}},
      {"zero.contour", fileText({PlaneText{"0 0 0 1", {}, {}}}), {"plane 1 normal", "zero"}},
      {"offplane.contour", fileText({offPlane}), {"plane 1", "one plane"}},
      {"swapped.contour", fileText({swapped}), {"plane 1 material 1", "unbounded"}},
      {"word.contour", fileText({edited(kZ0, 3, "3 zero 1 0")}), {"plane 1 edge 3", "zero"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = t.write(c.name, c.text);
    const std::string msg = errorOf(path);
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    for (const auto& m : c.mentions) EXPECT_NE(msg.find(m), std::string::npos) << "'" << m << "' not in: " << msg;
  }
  // line numbers: the edge "1 2 1 1" is on line 1 + 2 + 10 + 1 + 1 = 15
  const std::string msg = errorOf(t.write("line.contour", fileText({edited(kZ0, 1, "1 2 1 1")})));
  EXPECT_NE(msg.find(":15: plane 1 edge 1"), std::string::npos) << msg;
  EXPECT_NE(errorOf((t.dir / "missing.contour").string()).find("cannot open"), std::string::npos);
}

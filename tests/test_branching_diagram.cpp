// The labeling Φ, the graph G'' and the branching points (thesis ch. 2 §5.2, Def. 44-45;
// geometry/delaunay/branching_diagram.h): on parallel planes the branching diagram is the
// projection of the 2D Voronoi diagram of the other plane's sections (Fig. 2.32-left); on random
// configurations G ⊆ G' ⊆ G'' edge by edge (Propositions 5 and 10).
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <sstream>

#include "geometry/arrangement/connectivity_graph.h"
#include "geometry/arrangement/section_arrangement.h"
#include "geometry/core/polygon.h"
#include "geometry/core/section_ids.h"
#include "geometry/delaunay/branching_diagram.h"
#include "geometry/reconstruction/section_voronoi_reconstruction.h"
#include "geometry/slicing/mesh_sections.h"
#include "mesh_fixtures.h"
#include "section_fixtures.h"

using namespace xsect;

namespace {

CuttingPlane emptyPlane(int axis, double offset) {
  CuttingPlane cp;
  cp.plane = test::axisPlane(axis, offset);
  return cp;
}

Section disk(const Vec2& c, double r) {
  Section s;
  s.outer = test::circle(c, r, 128);
  return s;
}

/// The planes with a closing box of empty planes (half-width `half`, mm) and their rasters
/// (node spacing 0.05 mm, band 0.6 mm), every plane counted as given.
SectionScene sceneOf(std::vector<CuttingPlane> planes, double half) {
  for (int axis = 0; axis < 3; ++axis) {
    planes.push_back(emptyPlane(axis, -half));
    planes.push_back(emptyPlane(axis, half));
  }
  SectionScene s;
  s.planes = planes;
  s.real_planes = planes.size();
  for (const auto& p : s.planes) s.fields.push_back(sectionDistanceField(p.sections, 0.05, 0.6));
  return s;
}

std::string str(const GraphEdge& e) {
  std::ostringstream o;
  o << e.plane_a << ":" << e.section_a << " - " << e.plane_b << ":" << e.section_b << " (cell " << e.cell << ")";
  return o.str();
}

}  // namespace

// A disk on z = 0 under two disks on z = 2 (centres (±2, 0)): the lower disk's points take the
// label of the upper disk nearest in the plane (the root of |x(t) - b| = t is (H² + δ²) / 2H, which
// grows with the in-plane distance δ), so its branching points lie on the 2D Voronoi diagram of
// the upper disks: the perpendicular bisector x = 0 for equal radii, the hyperbola δ_left =
// δ_right for unequal ones. The upper disks see one section only: no branching point there.
TEST(BranchingDiagram, ParallelPlanesFollowTheVoronoiDiagramOfTheOtherPlane) {
  const double spacing = 0.2, H = 2.0;
  const Vec2 cl(-2, 0), cr(2, 0);
  for (const auto& [rl, rr] : {std::pair{1.0, 1.0}, std::pair{0.6, 1.4}}) {
    SCOPED_TRACE(rl);
    CuttingPlane lower, upper;
    lower.plane = test::axisPlane(2, 0);
    lower.sections = {disk(Vec2(0.03, -0.02), 4.0)};
    upper.plane = test::axisPlane(2, H);
    upper.sections = {disk(cl, rl), disk(cr, rr)};
    const SectionScene scene = sceneOf({lower, upper}, 8);
    const SectionArrangement arr = arrangeSections(scene.planes, spacing);
    const BranchingDiagram d = branchingDiagram(scene, arr);
    const SectionIds ids = scene.ids();
    const auto dl = [&](const Vec2& p) { return std::max((p - cl).norm() - rl, 0.0); };
    const auto dr = [&](const Vec2& p) { return std::max((p - cr).norm() - rr, 0.0); };

    int slab = -1;  // the cell between the planes
    for (const SectionPoint& sp : arr.points)
      if (sp.plane == 0 && sp.kind == SectionPoint::sample) slab = sp.cell[1];
    ASSERT_GE(slab, 0);
    // Labels point by point: the nearer upper disk in the plane, or none once the root
    // (H² + δ²) / 2H passes the upper plane (δ > H).
    int labelled = 0;
    for (std::size_t q = 0; q < arr.points.size(); ++q) {
      const SectionPoint& sp = arr.points[q];
      if (sp.kind == SectionPoint::trace) continue;
      if (sp.plane == 1) {
        EXPECT_EQ(d.label[q][0], ids.of(0, 0)) << sp.p.transpose();  // down, into the slab
        EXPECT_EQ(d.label[q][1], -1);                                  // up: nothing but the box
        continue;
      }
      EXPECT_EQ(d.label[q][0], -1);
      const double a = dl(sp.p), b = dr(sp.p), delta = std::min(a, b);
      if (std::abs(a - b) < 0.05 || std::abs(delta - H) < 0.05) continue;  // ties: either answer
      const int want = delta > H ? -1 : ids.of(1, a < b ? 0 : 1);
      EXPECT_EQ(d.label[q][1], want) << sp.p.transpose();
      labelled += want >= 0;
    }
    EXPECT_GT(labelled, 500);
    // Branching points: on the lower disk, in the slab, within the lattice's reach of δ_l = δ_r;
    // about one per lattice row across the part of the curve that is labelled (24 rows here).
    int onCurve = 0;
    for (const BranchingPoint& b : d.points) {
      EXPECT_EQ(b.plane, 0);
      EXPECT_EQ(b.section, 0);
      EXPECT_EQ(b.cell, slab);
      EXPECT_LE(std::abs(dl(b.p) - dr(b.p)), spacing + 0.02) << b.p.transpose();
      if (rl == rr) {
        EXPECT_LE(std::abs(b.p.x()), 1.5 * spacing) << b.p.transpose();
      }
      onCurve += std::abs(dl(b.p) - dr(b.p)) <= spacing + 0.02;
    }
    EXPECT_GE(onCurve, 18);
    // G'': the lower disk with each upper disk, in the slab only (the box holds no section).
    EXPECT_EQ(d.g_double_prime.size(), 2u);
    for (const GraphEdge& e : d.g_double_prime) {
      EXPECT_EQ(e.cell, slab);
      EXPECT_EQ(e.plane_a, 0);
      EXPECT_EQ(e.plane_b, 1);
    }
    // Where labels change to none too: the curve δ = H (rays leaving through the upper plane).
    const BranchingDiagram exits = branchingDiagram(scene, arr, true);
    int exitPoints = 0;
    for (const BranchingPoint& b : exits.points) {
      const double delta = std::min(dl(b.p), dr(b.p));
      EXPECT_TRUE(std::abs(dl(b.p) - dr(b.p)) <= spacing + 0.02 || std::abs(delta - H) <= spacing + 0.02)
          << b.p.transpose();
      exitPoints += std::abs(delta - H) <= spacing + 0.02;
    }
    EXPECT_GT(exitPoints, 40);
    EXPECT_EQ(exits.g_double_prime, d.g_double_prime);
  }
}

// The same input gives the same diagram whatever the thread count (per point, then sorted).
TEST(BranchingDiagram, SameOutputOnOneThread) {
  std::mt19937_64 rng(11);
  std::vector<CuttingPlane> planes = test::randomShellPlanes(8, rng, Vec3(0.2, 0.1, -0.1), 5.0, 6.0, 3.0, 96);
  const SectionScene scene = sceneOf(planes, 7.5);
  const SectionArrangement arr = arrangeSections(scene.planes, 0.25);
  const BranchingDiagram a = branchingDiagram(scene, arr);
  BranchingDiagram b;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    b = branchingDiagram(scene, arr);
  }
  EXPECT_GT(a.points.size(), 0u);
  EXPECT_EQ(a.label, b.label);
  EXPECT_EQ(a.g_double_prime, b.g_double_prime);
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t k = 0; k < a.points.size(); ++k) {
    EXPECT_EQ(a.points[k].cell, b.points[k].cell);
    EXPECT_EQ(a.points[k].p, b.points[k].p);
  }
}

namespace {

/// Random planes of uniform orientation at offsets within `spread` of `centre` (mm).
std::vector<Plane> randomPlanes(int count, std::mt19937_64& rng, const Vec3& centre, double spread) {
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(-spread, spread);
  std::vector<Plane> out;
  for (int i = 0; i < count; ++i) {
    Plane p;
    p.normal = Vec3(g(rng), g(rng), g(rng)).normalized();
    p.u = p.normal.unitOrthogonal();
    p.v = p.normal.cross(p.u);
    p.origin = centre + u(rng) * p.normal;
    out.push_back(p);
  }
  return out;
}

/// G' as connectivity_graph.h samples it, on the rays of the points of e's two sections facing
/// e's cell only, at `step` (mm) along each ray and then by bisection down to 1e-9 mm where the
/// ray leaves its own section's lift: whether some ray goes from that lift straight into the
/// other section's (method 2's decision on either side of the transition).
bool liftsMeetAlongARay(const SectionScene& scene, const SectionArrangement& arr, const SectionVoronoiPoints& query,
                        const GraphEdge& e, double step) {
  for (const SectionPoint& sp : arr.points) {
    if (sp.kind == SectionPoint::trace) continue;
    const bool isA = sp.plane == e.plane_a && sp.section == e.section_a;
    const bool isB = sp.plane == e.plane_b && sp.section == e.section_b;
    if (!isA && !isB) continue;
    const int otherPlane = isA ? e.plane_b : e.plane_a, otherSection = isA ? e.section_b : e.section_a;
    const CuttingPlane& other = scene.planes[std::size_t(otherPlane)];
    const Plane& P = scene.planes[std::size_t(sp.plane)].plane;
    for (int side = 0; side < 2; ++side) {
      if (sp.cell[std::size_t(side)] != e.cell) continue;
      const Vec3 a = P.toWorld(sp.p), n = (side == 0 ? -1.0 : 1.0) * P.normal;
      double exit = 1e300;
      for (std::size_t j = 0; j < scene.planes.size(); ++j) {
        const double h = scene.planes[j].plane.signedDistance(a), c = scene.planes[j].plane.normal.dot(n);
        if (int(j) != sp.plane && c != 0 && -h / c > 0) exit = std::min(exit, -h / c);
      }
      const auto own = [&](double t) {
        const SectionVoronoiPoints::Answer ans = query.at(a + t * n);
        return ans.inside && ans.section_plane == sp.plane;
      };
      double lo = 0, hi = -1;
      for (double t = 0.5 * step; t < exit; t += step) {
        if (!own(t)) {
          hi = t;
          break;
        }
        lo = t;
      }
      if (hi < 0) continue;
      for (int it = 0; it < 60 && hi - lo > 1e-9; ++it) (own(0.5 * (lo + hi)) ? lo : hi) = 0.5 * (lo + hi);
      const Vec3 x = a + hi * n;
      const SectionVoronoiPoints::Answer ans = query.at(x);
      if (ans.inside && ans.section_plane == otherPlane &&
          sectionContains(other.sections[std::size_t(otherSection)], other.plane.toPlane(x)))
        return true;
    }
  }
  return false;
}

/// Edge counts of the graphs over configurations.
struct Inclusions {
  int g = 0, g_prime = 0, g_double_prime = 0, branching = 0;
  int g_missing = 0;      ///< G edges not in G'' (each a failure)
  int g_prime_extra = 0;  ///< G' edges not in G'' whose lifts do not meet when resampled
};

/// Checks G ⊆ G'' and G' ⊆ G'' (up to G''s sampling) on the planes closed by a box of half-width
/// 7.5 mm, lattice spacing `spacing` (mm); adds to the counts.
void checkInclusions(const std::vector<CuttingPlane>& planes, double spacing, Inclusions* n) {
  const SectionScene scene = sceneOf(planes, 7.5);
  const SectionArrangement arr = arrangeSections(scene.planes, spacing);
  SectionVoronoiParams vp;
  vp.slab_mm = 0.17;
  const ConnectivityGraphs graphs = connectivityGraphs(scene, arr, vp, true);
  const BranchingDiagram d = branchingDiagram(scene, arr);
  const auto& gpp = d.g_double_prime;
  for (const GraphEdge& e : graphs.g)
    if (!std::binary_search(gpp.begin(), gpp.end(), e)) {
      ++n->g_missing;
      ADD_FAILURE() << "G edge " << str(e) << " is not in G''";
    }
  const SectionVoronoiPoints query(scene.planes, scene.fields, vp);
  for (const GraphEdge& e : graphs.g_prime) {
    if (std::binary_search(gpp.begin(), gpp.end(), e)) continue;
    ++n->g_prime_extra;
    EXPECT_FALSE(liftsMeetAlongARay(scene, arr, query, e, spacing / 10))
        << "G' edge " << str(e) << " is not in G'', and its lifts meet";
  }
  n->g += int(graphs.g.size());
  n->g_prime += int(graphs.g_prime.size());
  n->g_double_prime += int(gpp.size());
  n->branching += int(d.points.size());
  std::cout << planes.size() << " planes: G " << graphs.g.size() << " G' " << graphs.g_prime.size() << " G'' "
            << gpp.size() << " branching points " << d.points.size() << " rays " << d.rays << " labelled "
            << d.labelled << " witnesses " << d.witnesses << " hidden roots " << d.hidden_roots
            << " polygon distances " << d.polygon_distances << "\n";
}

void report(const Inclusions& n) {
  std::cout << "G in G'': " << n.g - n.g_missing << "/" << n.g << ", G' in G'': " << n.g_prime - n.g_prime_extra << "/"
            << n.g_prime << " (the others G' sampling artefacts), G'' " << n.g_double_prime << " edges, "
            << n.branching << " branching points\n";
}

}  // namespace

// Propositions 5 and 10 on random balls, shells and tori cut by 6 to 12 random planes: every edge
// of G (connectivity_graph.h) is an edge of G'' in the same cell, and so is every edge of G' except
// where G''s own sampling made it: G' follows each ray in steps of about the lattice spacing and
// joins A and B when one step leaves A's lift and the next lands in B's, so a gap thinner than a
// step between the lifts (points of V_C(B) projecting outside B, or a third section's lift) joins
// them wrongly. Such an edge is resampled along the same rays where they leave their own lift
// (to 1e-9 mm): it must then vanish (otherwise G'' missed a real connection), and stay rare.
TEST(BranchingDiagram, GAndGPrimeAreSubgraphsOfGDoublePrime) {
  Inclusions n;
  const TriangleMesh torus = test::torusMesh(4.0, 1.6, 96, 48);
  for (int seed = 0; seed < 9; ++seed) {
    SCOPED_TRACE(seed);
    std::mt19937_64 rng(std::uint64_t(100 + seed));
    const int count = 6 + seed % 7;
    const int shape = seed % 3;  // ball, shell, torus
    std::vector<CuttingPlane> planes;
    if (shape < 2) {
      planes = test::randomShellPlanes(count, rng, Vec3(0.2, 0.1, -0.1), 5.0, 6.0, shape == 0 ? 0.0 : 3.0, 128);
    } else {
      for (const Plane& p : randomPlanes(count, rng, Vec3::Zero(), 1.5)) {
        CuttingPlane cp;
        cp.slice = int(planes.size());
        cp.plane = p;
        cp.sections = meshSections(torus, p);
        planes.push_back(cp);
      }
    }
    checkInclusions(planes, 0.2, &n);
  }
  report(n);
  EXPECT_GT(n.g, 1000);
  EXPECT_GE(n.g_double_prime, n.g_prime - n.g_prime_extra);
  EXPECT_LE(n.g_prime_extra, std::max(1, n.g_prime / 200));
  EXPECT_GT(n.branching, 10000);
}

// The same on three orthogonal stacks through a shell (1 mm apart): cubic cells, where lifts end
// on edges of the Voronoi diagram (several sections at the same distance) at many lattice points.
// Every section at that distance is a label (the point is on the boundary of each Voronoi cell):
// with the nearest one only, G loses edges here.
TEST(BranchingDiagram, TiesOnOrthogonalStacks) {
  Inclusions n;
  checkInclusions(test::multiaxialShell(Vec3(0.2, 0.1, -0.1), 6.0, 3.0, 1.0, 6.0), 0.2, &n);
  report(n);
  EXPECT_GT(n.g, 5000);
  EXPECT_GE(n.g_double_prime, n.g_prime - n.g_prime_extra);
  EXPECT_LE(n.g_prime_extra, n.g_prime / 100);
}

// Cells of the arrangement holding sections (thesis ch. 2 §5.1) and the connectivity graphs:
// counts on configurations whose cells are known, G ⊆ G' edge by edge (Proposition 5) on random
// configurations, and each graph grouping the sections as the voxel reconstruction of its method.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "geometry/arrangement/connectivity_graph.h"
#include "geometry/reconstruction/nearest_plane_reconstruction.h"
#include "geometry/arrangement/section_arrangement.h"
#include "geometry/reconstruction/section_voronoi_reconstruction.h"
#include "section_fixtures.h"

using namespace xsect;

namespace {

CuttingPlane diskPlane(int axis, double offset, double radius) {
  CuttingPlane cp;
  cp.plane = test::axisPlane(axis, offset);
  if (radius > 0) {
    Section s;
    s.outer = test::circle(Vec2(0.01, -0.02), radius, 64);
    cp.sections.push_back(s);
  }
  return cp;
}

/// The scene of planes whose rasters were made by hand (every plane counted as given).
SectionScene sceneOf(const std::vector<CuttingPlane>& planes, const std::vector<SectionDistanceField>& fields) {
  SectionScene s;
  s.planes = planes;
  s.real_planes = planes.size();
  s.fields = fields;
  return s;
}

std::vector<CuttingPlane> boxAround(double half) {
  std::vector<CuttingPlane> out;
  for (int axis = 0; axis < 3; ++axis) {
    out.push_back(diskPlane(axis, -half, 0));
    out.push_back(diskPlane(axis, half, 0));
  }
  return out;
}

}  // namespace

/// `count` planes through the line {centre + t axis}, at evenly spread angles about it, cutting the
/// ball of `radius` about the origin.
std::vector<CuttingPlane> fanOfPlanes(int count, const Vec3& centre, const Vec3& axis, double radius) {
  const Vec3 d = axis.normalized(), e = d.unitOrthogonal(), f = d.cross(e);
  std::vector<CuttingPlane> planes;
  for (int i = 0; i < count; ++i) {
    const double a = M_PI * (i + 0.13) / count;
    CuttingPlane cp;
    cp.slice = i;
    cp.plane.u = std::cos(a) * e + std::sin(a) * f;
    cp.plane.v = d;
    cp.plane.normal = cp.plane.u.cross(d);
    cp.plane.origin = centre;
    cp.sections = test::shellSections(cp.plane, Vec3::Zero(), radius, 0, 200);
    planes.push_back(cp);
  }
  return planes;
}

// Method 3 needs general position along the sections (pipeline/arrange_stage.cpp refuses it
// otherwise): the arrangement counts contour crossings lying on three planes of one pencil. A fan
// through the ball: every plane's contour crosses the axis twice, on all the other planes at once.
// The same fan with its axis beside the ball, random planes, a plane listed twice, and planes on a
// lattice meeting three at a point on the contours: none.
TEST(ConnectivityGraphArrangement, CountsContourCrossingsOnAPencilOfPlanes) {
  std::mt19937_64 rng(17);
  std::normal_distribution<double> g(0, 1);
  for (int trial = 0; trial < 6; ++trial) {
    const int n = 5 + 3 * trial;
    const Vec3 axis(g(rng), g(rng), g(rng)), off = 2.0 * Vec3(g(rng), g(rng), g(rng)).cross(axis).normalized();
    const SectionArrangement fan = arrangeSections(fanOfPlanes(n, off, axis, 10), 0.5);
    EXPECT_EQ(fan.pencil_crossings, 2 * n * (n - 1)) << "trial " << trial;  // two per plane pair, on each plane
    EXPECT_NE(fan.pencil_planes[2], -1);
    const SectionArrangement beside = arrangeSections(fanOfPlanes(n, 6.0 * off, axis, 10), 0.5);
    EXPECT_EQ(beside.pencil_crossings, 0) << "axis 12 mm off the centre of a ball of radius 10";
    std::vector<CuttingPlane> random = test::randomShellPlanes(5 * n, rng, Vec3::Zero(), 8, 10, 4);
    random.push_back(random.front());
    const SectionArrangement r = arrangeSections(random, 0.5);
    EXPECT_GT(r.trace_points, 0);
    EXPECT_EQ(r.pencil_crossings, 0);
    EXPECT_EQ(r.pencil_planes[0], -1);
  }
  // Planes x, y, z = integers: contours of the ball of radius sqrt(3) pass through (1, 1, 1), where
  // three planes meet in a point (not a line).
  std::vector<CuttingPlane> lattice;
  for (int axis = 0; axis < 3; ++axis)
    for (int t = -1; t <= 1; ++t) {
      CuttingPlane cp;
      cp.slice = int(lattice.size());
      cp.plane = test::axisPlane(axis, t);
      cp.sections = test::shellSections(cp.plane, Vec3::Zero(), std::sqrt(3.0), 0, 360);
      lattice.push_back(cp);
    }
  const SectionArrangement l = arrangeSections(lattice, 0.25);
  EXPECT_GT(l.trace_points, 0);
  EXPECT_EQ(l.pencil_crossings, 0);
}

TEST(ConnectivityGraphArrangement, CellsOfAStackAndOfAStackCutAcross) {
  std::vector<CuttingPlane> planes = {diskPlane(2, 0, 2), diskPlane(2, 1, 2), diskPlane(2, 2, 2)};
  for (auto& p : boxAround(5)) planes.push_back(p);
  SectionArrangement a = arrangeSections(planes, 0.1);
  EXPECT_EQ(a.cells, 4);  // below, two slabs, above
  EXPECT_EQ(a.sub_sections.size(), 6u);
  EXPECT_EQ(a.trace_points, 0);
  // A plane x = 0.3 crosses every disk: each splits into two sub-sections, every cell into two.
  planes.push_back(diskPlane(0, 0.3, 0));
  a = arrangeSections(planes, 0.1);
  EXPECT_EQ(a.cells, 8);
  EXPECT_EQ(a.sub_sections.size(), 12u);
  EXPECT_EQ(a.trace_points, 6);  // two contour crossings per disk
  for (const SubSection& s : a.sub_sections) EXPECT_GT(s.points, 50);
}

TEST(ConnectivityGraph, GIsASubgraphOfGPrimeAndMatchesTheVoxels) {  // Proposition 5
  std::mt19937_64 rng(3);
  const Vec3 centre(0.2, 0.1, -0.1);
  int edgesG = 0, extra = 0;
  for (const int count : {4, 10, 24}) {
    SCOPED_TRACE(count);
    // Shells: annuli, non-convex sections.
    std::vector<CuttingPlane> planes = test::randomShellPlanes(count, rng, centre, 5.5, 6.0, 3.0);
    for (auto& p : boxAround(7.5)) planes.push_back(p);
    std::vector<SectionDistanceField> fields;
    for (const auto& p : planes) fields.push_back(sectionDistanceField(p.sections, 0.05, 0.6));
    const SectionArrangement arr = arrangeSections(planes, 0.2);
    SectionVoronoiParams vp;
    vp.slab_mm = 0.17;
    const SectionScene scene = sceneOf(planes, fields);
    const ConnectivityGraphs graphs = connectivityGraphs(scene, arr, vp, true);
    // Edge by edge, in the same cell. The lift point of method 1 lies on lift'(A) ∩ lift'(B)
    // exactly (proof of Theorem 18); G' finds it with the rasters, which may disagree with the
    // exact polygon test when it projects within their tolerance of a contour: at most 1% of the
    // edges, and never a pair of sections that G' leaves unconnected in every cell.
    int missing = 0;
    for (const GraphEdge& e : graphs.g) {
      if (std::binary_search(graphs.g_prime.begin(), graphs.g_prime.end(), e)) continue;
      ++missing;
      const bool elsewhere = std::any_of(graphs.g_prime.begin(), graphs.g_prime.end(), [&](const GraphEdge& f) {
        return f.plane_a == e.plane_a && f.section_a == e.section_a && f.plane_b == e.plane_b &&
               f.section_b == e.section_b;
      });
      EXPECT_TRUE(elsewhere) << "G edge " << e.plane_a << ":" << e.section_a << " - " << e.plane_b
                             << ":" << e.section_b << " (cell " << e.cell << ") has no G' edge";
    }
    EXPECT_LE(missing, std::max<int>(1, int(graphs.g.size()) / 100));
    edgesG += int(graphs.g.size());
    extra += int(graphs.g_prime.size() - graphs.g.size());

    GridSpec grid;
    grid.voxel = 0.2;
    grid.origin = Vec3::Constant(-7.4);
    grid.dims = {75, 75, 75};
    const auto m1 = nearestPlaneReconstruction(planes, fields, grid);
    const auto m2 = sectionVoronoiReconstruction(planes, fields, grid, vp);
    std::vector<std::uint8_t> in1(m1.value.values.size()), in2(in1.size());
    for (std::size_t q = 0; q < in1.size(); ++q) {
      in1[q] = m1.value.values[q] < 0;
      in2[q] = m2.value.values[q] < 0;
    }
    const GraphVoxelCheck c1 = compareWithVoxels(graphs.g, scene, arr, in1, grid);
    const GraphVoxelCheck c2 = compareWithVoxels(graphs.g_prime, scene, arr, in2, grid);
    EXPECT_TRUE(c1.same_partition) << c1.pairs_joined_by_graph_only << " " << c1.pairs_joined_by_voxels_only;
    EXPECT_TRUE(c2.same_partition) << c2.pairs_joined_by_graph_only << " " << c2.pairs_joined_by_voxels_only;
    EXPECT_LE(c2.graph_components, c1.graph_components);
  }
  EXPECT_GT(edgesG, 20);
  EXPECT_GT(extra, 0) << "method 2 should make connections method 1 does not";
}

// Cell by cell (issue 4: sections per component, per cell): a cylinder cut by two discs (z = 0,
// z = 4) and crossed by an empty plane (x = 0.3), so the slab between the discs is two cells.
// Method 1's solid joins the discs in both halves, as G does. Cutting the solid in one half keeps
// the discs in one component (joined through the other half): the global check cannot see it;
// the per-cell check finds the one cell where G and the solid now differ.
#include "geometry/arrangement/cell_connectivity_check.h"

namespace {

std::vector<std::uint8_t> method1Solid(const std::vector<CuttingPlane>& planes,
                                       const std::vector<SectionDistanceField>& fields, const GridSpec& grid) {
  const auto m1 = nearestPlaneReconstruction(planes, fields, grid);
  std::vector<std::uint8_t> inside(m1.value.values.size());
  for (std::size_t q = 0; q < inside.size(); ++q) inside[q] = m1.value.values[q] < 0;
  return inside;
}

/// Planes inside a box of half-width 8 with their rasters, cells and graph G.
struct Scene {
  SectionScene sections;
  SectionArrangement arr;
  ConnectivityGraphs graphs;
};

Scene sceneInBox(std::vector<CuttingPlane> planes) {
  Scene s;
  for (auto& p : boxAround(8)) planes.push_back(p);
  std::vector<SectionDistanceField> fields;
  for (const auto& p : planes) fields.push_back(sectionDistanceField(p.sections, 0.05, 0.6));
  s.sections = sceneOf(planes, fields);
  s.arr = arrangeSections(planes, 0.2);
  s.graphs = connectivityGraphs(s.sections, s.arr, {}, false);
  return s;
}

GridSpec offPlanesGrid() {  // voxel centres off every plane of these tests
  GridSpec grid;
  grid.voxel = 0.2;
  grid.origin = Vec3::Constant(-7.93);
  grid.dims = {80, 80, 80};
  return grid;
}

}  // namespace

TEST(ConnectivityGraph, PerCellCheckSeesAConnectionLostInOneCell) {
  const Scene scene = sceneInBox({diskPlane(2, 0, 3), diskPlane(2, 4, 3), diskPlane(0, 0.3, 0)});
  const auto& [sections, arr, graphs] = scene;
  const auto& planes = sections.planes;
  const auto& fields = sections.fields;
  const GridSpec grid = offPlanesGrid();
  std::vector<std::uint8_t> inside = method1Solid(planes, fields, grid);

  // Between the discs, on either side of x = 0.3: the two cells bounded by two sections.
  const CellConnectivityCheck before = compareCellsWithVoxels(graphs.g, sections, arr, inside, grid);
  EXPECT_EQ(arr.cells, 6);
  EXPECT_EQ(before.cells_compared, 2);
  EXPECT_EQ(before.cells_unresolved, 0);
  EXPECT_EQ(before.cells_differing, 0);
  int between = -1;  // the one on the side x > 0.3
  for (const SectionPoint& sp : arr.points)
    if (sp.plane == 0 && sp.kind == SectionPoint::sample && sp.p.x() > 1.0) between = sp.cell[1];
  ASSERT_GE(between, 0);

  // Without the graph's edge of that cell, the solid joins what the graph does not.
  std::vector<GraphEdge> fewer;
  for (const GraphEdge& e : graphs.g)
    if (e.cell != between) fewer.push_back(e);
  ASSERT_LT(fewer.size(), graphs.g.size());
  const CellConnectivityCheck missing = compareCellsWithVoxels(fewer, sections, arr, inside, grid);
  EXPECT_EQ(missing.differing_cells, std::vector<int>{between});
  EXPECT_EQ(missing.pairs_joined_by_voxels_only, 1);
  EXPECT_EQ(missing.pairs_joined_by_graph_only, 0);

  // A gap 0.6 mm thick at z = 2 on the side x > 0.3.
  for (int k = 0; k < grid.dims[2]; ++k)
    for (int j = 0; j < grid.dims[1]; ++j)
      for (int i = 0; i < grid.dims[0]; ++i) {
        const Vec3 x = grid.centre(i, j, k);
        if (x.x() > 0.3 && std::abs(x.z() - 2.0) < 0.3) inside[std::size_t(grid.index(i, j, k))] = 0;
      }
  const GraphVoxelCheck global = compareWithVoxels(graphs.g, sections, arr, inside, grid);
  EXPECT_TRUE(global.same_partition) << "still one component, through the other half";
  const CellConnectivityCheck after = compareCellsWithVoxels(graphs.g, sections, arr, inside, grid);
  EXPECT_EQ(after.differing_cells, std::vector<int>{between});
  EXPECT_EQ(after.pairs_joined_by_graph_only, 1);
  EXPECT_EQ(after.pairs_joined_by_voxels_only, 0);
  EXPECT_FALSE(keepsCellConnectivity(after, before));
  EXPECT_TRUE(keepsCellConnectivity(before, after));
}

// A section touching two components of a cell joins them; a U-shaped section whose two arms
// each hold one component is not a disagreement with the graph (a false alarm with one seed).
TEST(ConnectivityGraph, PerCellCheckSeedsEveryPartOfASubSection) {
  CuttingPlane u;
  u.plane = test::axisPlane(2, 0);
  u.sections.push_back(Section{Ring{{-3, -2}, {3, -2}, {3, 4}, {1, 4}, {1, -1}, {-1, -1}, {-1, 4}, {-3, 4}}, {}, 1});
  CuttingPlane top;
  top.plane = test::axisPlane(2, 4);
  top.sections.push_back(Section{test::circle(Vec2(-2, 2.5), 0.9, 64), {}, 1});
  top.sections.push_back(Section{test::circle(Vec2(2, 2.5), 0.9, 64), {}, 1});
  const Scene scene = sceneInBox({u, top, diskPlane(1, -0.5, 0)});
  const auto& [sections, arr, graphs] = scene;
  const auto& planes = sections.planes;
  const auto& fields = sections.fields;
  const GridSpec grid = offPlanesGrid();
  const CellConnectivityCheck c = compareCellsWithVoxels(graphs.g, sections, arr, method1Solid(planes, fields, grid), grid);
  EXPECT_GT(c.cells_compared, 0);
  EXPECT_EQ(c.cells_differing, 0) << c.pairs_joined_by_graph_only << " " << c.pairs_joined_by_voxels_only;
}

// Re-deciding a cell on finer lattices (cell_refinement.h): two discs (z = 0, z = 4) and, between
// them, a solid made of a slab on each disc and a neck of radius 0.06 mm whose axis runs midway
// between the grid's voxel centres (0.2 mm apart). On the grid the neck holds no voxel centre, so
// the solid splits the discs that G (and method 1's solid) joins in that cell; on the lattice of
// half the spacing the axis is a row of voxel centres and the cell agrees with G again. Without
// the neck the finer lattice confirms the split; with too small a budget nothing is evaluated.
#include "geometry/arrangement/cell_refinement.h"

TEST(ConnectivityGraph, RefinementResolvesAPassageThinnerThanAVoxel) {
  const Scene scene = sceneInBox({diskPlane(2, 0, 3), diskPlane(2, 4, 3)});
  const auto& [sections, arr, graphs] = scene;
  const auto& planes = sections.planes;
  const auto& fields = sections.fields;
  const GridSpec grid = offPlanesGrid();  // centres at x, y = ... 0.07, 0.27 ...
  const auto solidOn = [](bool neck) {
    return [neck](const GridSpec& g) {
      std::vector<std::uint8_t> in(std::size_t(g.count()), 0);
      for (int k = 0; k < g.dims[2]; ++k)
        for (int j = 0; j < g.dims[1]; ++j)
          for (int i = 0; i < g.dims[0]; ++i) {
            const Vec3 x = g.centre(i, j, k);
            const bool slab = std::hypot(x.x(), x.y()) < 3.5 && (std::abs(x.z()) < 0.5 || std::abs(x.z() - 4) < 0.5);
            const bool inNeck = neck && std::hypot(x.x() - 0.17, x.y() - 0.17) < 0.06 && x.z() > 0 && x.z() < 4;
            in[std::size_t(g.index(i, j, k))] = slab || inNeck;
          }
      return in;
    };
  };
  const CellConnectivityCheck reference =
      compareCellsWithVoxels(graphs.g, sections, arr, method1Solid(planes, fields, grid), grid);
  const CellConnectivityCheck coarse = compareCellsWithVoxels(graphs.g, sections, arr, solidOn(true)(grid), grid);
  const std::vector<int> disputed = cellsDifferingMore(coarse, reference);
  ASSERT_EQ(disputed.size(), 1u) << "the neck is invisible on the grid";
  const int cell = disputed[0];
  EXPECT_EQ(reference.pairs_by_cell[std::size_t(cell)], 0);
  EXPECT_EQ(coarse.pairs_by_cell[std::size_t(cell)], 1);
  // Restricted to that cell, the comparison is the same.
  const CellConnectivityCheck only =
      compareCellsWithVoxels(graphs.g, sections, arr, solidOn(true)(grid), grid, {cell});
  EXPECT_EQ(only.cells_compared, 1);
  EXPECT_EQ(only.pairs_by_cell[std::size_t(cell)], 1);

  const auto withNeck = refineCellComparison(disputed, coarse, reference, graphs.g, sections, arr, grid, solidOn(true));
  ASSERT_EQ(withNeck.size(), 1u);
  EXPECT_EQ(withNeck[0].cell, cell);
  EXPECT_EQ(withNeck[0].factor, 2);
  EXPECT_EQ(withNeck[0].refined_pairs, 0);
  EXPECT_TRUE(withNeck[0].accepted);
  // The box covers the cell (the slab between the discs, all 80 voxel centres across the box of
  // half-width 8, indices 0..79) and two voxels more on each side: 2·(79 + 4) + 1 lattice points.
  EXPECT_EQ(withNeck[0].dims[0], 167);

  const auto noNeck = refineCellComparison(disputed, coarse, reference, graphs.g, sections, arr, grid, solidOn(false));
  EXPECT_EQ(noNeck[0].factor, 2);
  EXPECT_EQ(noNeck[0].refined_pairs, 1);
  EXPECT_FALSE(noNeck[0].accepted);

  const auto tooBig = refineCellComparison(disputed, coarse, reference, graphs.g, sections, arr, grid,
                                           solidOn(true), 8, 1000);
  EXPECT_EQ(tooBig[0].factor, 0);
  EXPECT_FALSE(tooBig[0].accepted);
}

// G on observed pieces (issue 20, connectivity_graph.h): method 1 on the pieces, R_Ω, decides x by
// the nearest point of the union of the pieces, so its lifts pass unobserved parts of planes and
// end on pieces. Two balls cut by random planes, each observed only on a random image rectangle
// (the sections are the discs cut down to it, as a segmentation sees them): G_Ω groups the
// sections as R_Ω's voxels do, globally and cell by cell (edges listed where the lifts meet), more
// closely than G on whole planes does; with whole pieces G_Ω is G, edge for edge.
#include "geometry/core/polygon.h"
#include "geometry/reconstruction/observed_section_voronoi.h"
#include "geometry/scene/observed_piece.h"

namespace {

/// The part of convex ring `r` inside rectangle `box` (Sutherland-Hodgman), counter-clockwise.
Ring clipToRect(const Ring& r, const PlaneRect& box) {
  Ring out = r;
  for (int side = 0; side < 4 && !out.empty(); ++side) {
    const int axis = side / 2;
    const double bound = side % 2 ? box.max[axis] : box.min[axis], sgn = side % 2 ? -1.0 : 1.0;
    const auto inside = [&](const Vec2& p) { return sgn * (p[axis] - bound) >= 0; };
    Ring in = out;
    out.clear();
    for (std::size_t k = 0; k < in.size(); ++k) {
      const Vec2 &a = in[k], &b = in[(k + 1) % in.size()];
      if (inside(a)) out.push_back(a);
      if (inside(a) != inside(b)) out.push_back(a + (bound - a[axis]) / (b[axis] - a[axis]) * (b - a));
    }
  }
  return out;
}

/// G_Ω's section pairs by its definition, brute force: from each section point's foot on its piece
/// (the point itself inside it), rays along ±n and, where the point lies beyond the piece, every
/// 2° of the edge's normal cone; on each, the first t where another plane's piece is as near as
/// t, by bisection on [0, 40] mm for each plane (d(x, Ω_Q) - t is non-increasing), and the section
/// holding that piece's nearest point.
std::set<std::pair<int, int>> observedGraphPairsByDefinition(const SectionScene& scene, const SectionArrangement& arr) {
  const std::vector<CuttingPlane>& planes = scene.planes;
  const SectionIds ids = scene.ids();
  const auto nearestOn = [&](std::size_t q, const Vec3& x, Vec2* foot) {
    const Vec2 at = planes[q].plane.toPlane(x);
    double na, nb;
    const double o = scene.pieces[q].distance(at.x(), at.y(), &na, &nb), s = planes[q].plane.signedDistance(x);
    *foot = Vec2(na, nb);
    return std::sqrt(s * s + o * o);
  };
  const auto sectionHolding = [&](std::size_t q, const Vec2& p) {
    for (std::size_t t = 0; t < planes[q].sections.size(); ++t)
      if (sectionContains(planes[q].sections[t], p)) return int(t);
    return -1;
  };
  std::set<std::pair<int, int>> pairs;
  for (const SectionPoint& sp : arr.points) {
    if (sp.kind == SectionPoint::trace) continue;
    const std::size_t A = std::size_t(sp.plane);
    const Plane& P = planes[A].plane;
    double na, nb;
    const double o = scene.pieces[A].distance(sp.p.x(), sp.p.y(), &na, &nb);
    if (o > 0 && sectionHolding(A, Vec2(na, nb)) != sp.section) continue;  // a point of the section beyond Ω_A
    const Vec3 a = P.toWorld(Vec2(na, nb));
    std::vector<Vec3> dirs{P.normal, -P.normal};
    if (o > 0) {
      const Vec2 m = (sp.p - Vec2(na, nb)) / o;
      const Vec3 out = m.x() * P.u + m.y() * P.v;
      for (int deg = 2; deg < 90; deg += 2)
        for (const double side : {-1.0, 1.0})
          dirs.push_back(std::cos(deg * M_PI / 180) * side * P.normal + std::sin(deg * M_PI / 180) * out);
    }
    for (const Vec3& d : dirs) {
      double best = std::numeric_limits<double>::infinity();
      std::size_t bq = 0;
      Vec2 foot;
      for (std::size_t q = 0; q < planes.size(); ++q) {
        if (q == A || scene.pieces[q].empty) continue;
        const auto f = [&](double t) { return nearestOn(q, a + t * d, &foot) - t; };
        double lo = 0, hi = 40;
        if (f(hi) > 0) continue;
        for (int k = 0; k < 45; ++k) (f(0.5 * (lo + hi)) > 0 ? lo : hi) = 0.5 * (lo + hi);
        if (hi < best) {
          best = hi;
          bq = q;
        }
      }
      if (!std::isfinite(best)) continue;
      nearestOn(bq, a + best * d, &foot);
      const int b = sectionHolding(bq, foot);
      if (b < 0) continue;
      const int u = ids.of(sp.plane, sp.section), v = ids.of(int(bq), b);
      pairs.insert({std::min(u, v), std::max(u, v)});
    }
  }
  return pairs;
}

std::set<std::pair<int, int>> pairsOf(const std::vector<GraphEdge>& edges, const SectionIds& ids) {
  std::set<std::pair<int, int>> pairs;
  for (const GraphEdge& e : edges) {
    const int u = ids.of(e.plane_a, e.section_a), v = ids.of(e.plane_b, e.section_b);
    pairs.insert({std::min(u, v), std::max(u, v)});
  }
  return pairs;
}

}  // namespace

TEST(ConnectivityGraph, OnObservedPiecesGroupsTheSectionsAsMethod1OnThePieces) {
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> small(1.0, 8.0), large(4.0, 14.0), offset(-5.0, 5.0);
  std::normal_distribution<double> g(0, 1);
  const std::array<Vec3, 2> centres{Vec3(-3.2, 0.1, 0.2), Vec3(3.6, -0.3, -0.1)};
  const std::array<double, 2> radii{3.4, 2.8};
  int wholeSolidOnly = 0, observedSolidOnly = 0, wholeGraphOnly = 0, observedGraphOnly = 0, compared = 0, edgesAdded = 0, left = 0, samePartition = 0, samePrimePartition = 0, primeAdded = 0, primeWholeSolidOnly = 0, primeSolidOnly = 0, runs = 0, pairsCompared = 0, pairsDiffering = 0;
  for (const int count : {6, 10, 14, 20, 30, 6, 10, 14, 20, 30}) {
    ++runs;
    SCOPED_TRACE(std::to_string(count) + " planes");
    std::vector<CuttingPlane> planes;
    for (int i = 0; i < count; ++i) {
      CuttingPlane cp;
      cp.slice = i;
      const Vec3 n = Vec3(g(rng), g(rng), g(rng)).normalized();
      cp.plane.normal = n;
      cp.plane.u = n.unitOrthogonal();
      cp.plane.v = n.cross(cp.plane.u);
      cp.plane.origin = offset(rng) * n + Vec3(offset(rng), 0, 0);
      cp.pixel_mm = 0.1;
      auto& size = runs <= 5 ? small : large;  // images smaller than the balls, then most larger
      cp.extent = {Vec2(-size(rng), -size(rng)), Vec2(size(rng), size(rng))};
      const Vec2 shift = cp.plane.toPlane(Vec3(0.3 * offset(rng), 0, 0));  // about the balls
      cp.extent.min += shift;
      cp.extent.max += shift;
      for (int b = 0; b < 2; ++b) {
        const double d = cp.plane.signedDistance(centres[std::size_t(b)]), r = radii[std::size_t(b)];
        if (std::abs(d) >= r) continue;
        Section s;
        s.outer = clipToRect(test::circle(cp.plane.toPlane(centres[std::size_t(b)]), std::sqrt(r * r - d * d), 96), cp.extent);
        if (s.outer.size() >= 3 && std::abs(signedArea(s.outer)) > 0.05) cp.sections.push_back(s);
      }
      planes.push_back(cp);
    }
    for (CuttingPlane& p : boxAround(7.5)) {
      p.is_virtual = true;
      p.slice = -1;
      planes.push_back(p);
    }
    std::vector<SectionDistanceField> fields;
    for (const auto& p : planes) fields.push_back(sectionDistanceField(p.sections, 0.05, 0.6));
    const SectionArrangement arr = arrangeSections(planes, 0.2);
    SectionScene whole = sceneOf(planes, fields), observed = whole;
    whole.pieces = observedPieces(planes, false);
    observed.pieces = observedPieces(planes, true);
    SectionVoronoiParams vp;
    vp.slab_mm = 0.17;
    const ConnectivityGraphs g = connectivityGraphs(whole, arr, {}, false);
    const ConnectivityGraphs gOmega = connectivityGraphs(observed, arr, vp, true);
    EXPECT_TRUE(g.g == connectivityGraphs(sceneOf(planes, fields), arr, {}, false).g) << "whole pieces: G itself";
    edgesAdded += int(gOmega.g.size()) - int(g.g.size());
    if (runs <= 5) {  // the section pairs, against the definition computed by brute force
      const std::set<std::pair<int, int>> byDefinition = observedGraphPairsByDefinition(observed, arr),
                                          computed = pairsOf(gOmega.g, observed.ids());
      std::vector<std::pair<int, int>> onlyOne;
      std::set_symmetric_difference(byDefinition.begin(), byDefinition.end(), computed.begin(), computed.end(),
                                    std::back_inserter(onlyOne));
      pairsCompared += int(byDefinition.size());
      pairsDiffering += int(onlyOne.size());
    }

    const GridSpec grid = offPlanesGrid();
    const auto m1 = nearestPlaneReconstruction(planes, fields, grid, {}, &observed.pieces);
    std::vector<std::uint8_t> inside(m1.value.values.size());
    for (std::size_t q = 0; q < inside.size(); ++q) inside[q] = m1.value.values[q] < 0;
    const GraphVoxelCheck global = compareWithVoxels(gOmega.g, observed, arr, inside, grid);
    samePartition += global.same_partition;
    // G'_Ω along the lifts of R'_Ω = R_Ω ∪ the lifts of R' that the pieces keep: G_Ω ⊆ G'_Ω
    // (R_Ω ⊆ R'_Ω), and the same grouping as R'_Ω's voxels.
    EXPECT_TRUE(std::includes(gOmega.g_prime.begin(), gOmega.g_prime.end(), gOmega.g.begin(), gOmega.g.end()));
    primeAdded += int(gOmega.g_prime.size() - gOmega.g.size());
    {
      std::vector<std::uint8_t> in2(std::size_t(grid.count()), 0);
      const BlockGrid<float> numbering(grid, 0.f);
      forEachObservedSectionVoronoiBlock(planes, fields, observed.pieces, grid, vp,
                                         [&](std::int64_t b, const SectionVoronoiBlock& v) {
                                           forEachVoxelOfBlock(grid, numbering.blockOrigin(b), [&](int i, int j, int k, int o) {
                                             in2[std::size_t(grid.index(i, j, k))] = v.value[std::size_t(o)] < 0;
                                           });
                                         });
      const GraphVoxelCheck c2 = compareWithVoxels(gOmega.g_prime, observed, arr, in2, grid);
      const CellConnectivityCheck cp = compareCellsWithVoxels(gOmega.g_prime, observed, arr, in2, grid);
      const CellConnectivityCheck cpw =
          compareCellsWithVoxels(connectivityGraphs(whole, arr, vp, true).g_prime, whole, arr, in2, grid);
      primeWholeSolidOnly += cpw.pairs_joined_by_voxels_only;
      primeSolidOnly += cp.pairs_joined_by_voxels_only;
      samePrimePartition += c2.same_partition;
    }
    const CellConnectivityCheck cw = compareCellsWithVoxels(g.g, whole, arr, inside, grid);
    const CellConnectivityCheck co = compareCellsWithVoxels(gOmega.g, observed, arr, inside, grid);
    EXPECT_TRUE(g.cells_left_through_unobserved.empty());
    wholeGraphOnly += cw.pairs_joined_by_graph_only;
    observedGraphOnly += co.pairs_joined_by_graph_only;
    wholeSolidOnly += cw.pairs_joined_by_voxels_only;
    observedSolidOnly += co.pairs_joined_by_voxels_only;
    compared += co.cells_compared;
    left += int(gOmega.cells_left_through_unobserved.size());
  }
  EXPECT_GT(edgesAdded, 0) << "the pieces must join sections that whole planes keep apart";
  EXPECT_GT(pairsCompared, 100);
  EXPECT_LE(pairsDiffering, pairsCompared / 100) << "section pairs joined by G_Ω or by its definition only";
  EXPECT_GT(left, 0) << "lifts must pass unobserved parts of planes, or the test shows nothing";
  EXPECT_GT(wholeSolidOnly, 0) << "G on whole planes must disagree with R_Ω somewhere, or the test shows nothing";
  // Solid-only pairs: R_Ω joins sections in a cell that the graph keeps apart there (what G on
  // whole planes misses); graph-only pairs: a lift's meeting narrower than a voxel, as on whole
  // planes (G_Ω has more edges, so somewhat more of them).
  EXPECT_LE(observedSolidOnly, wholeSolidOnly / 4) << "of " << compared << " cells compared";
  EXPECT_LE(observedGraphOnly, wholeGraphOnly * 3 / 2 + 5) << "of " << compared << " cells compared";
  EXPECT_GE(samePartition, runs - 2) << "the same grouping globally (a contact narrower than the sample spacing can be missed)";
  EXPECT_GE(samePrimePartition, runs - 2) << "G'_Ω: the same grouping as R'_Ω";
  EXPECT_GT(primeAdded, 0) << "R'_Ω's kept lifts must join sections that G_Ω does not";
  EXPECT_LE(primeSolidOnly, primeWholeSolidOnly / 4) << "G'_Ω against R'_Ω cell by cell, G' on whole planes "
                                                      << primeWholeSolidOnly;
}


// Pieces that cover every ball (image rectangles 100 mm across, on the observed-piece code path):
// G_Ω and G'_Ω are the thesis' G and G', edge for edge and cell for cell, on random shells; and on
// the slanted tube of thesis Fig. 2.1-2.2, with planes beside it, G' joins the two discs where G
// does not (method 2's lift passes the planes beside the tube).
TEST(ConnectivityGraph, OnPiecesThatCoverEveryBallAreTheThesisGraphs) {
  std::mt19937_64 rng(31);
  const PlaneRect all{Vec2(-50, -50), Vec2(50, 50)};
  SectionVoronoiParams vp;
  vp.slab_mm = 0.17;
  for (const int count : {5, 12, 25}) {
    SCOPED_TRACE(std::to_string(count) + " planes");
    std::vector<CuttingPlane> planes = test::randomShellPlanes(count, rng, Vec3(0.2, 0.1, -0.1), 5.5, 6.0, 3.0, 96);
    for (CuttingPlane& p : boxAround(7.5)) {
      p.is_virtual = true;
      p.slice = -1;
      planes.push_back(p);
    }
    for (CuttingPlane& p : planes) {
      p.pixel_mm = 0.1;
      p.extent = all;
    }
    std::vector<SectionDistanceField> fields;
    for (const auto& p : planes) fields.push_back(sectionDistanceField(p.sections, 0.05, 0.6));
    const SectionArrangement arr = arrangeSections(planes, 0.2);
    SectionScene covering = sceneOf(planes, fields);
    covering.pieces = observedPieces(planes, true);
    ASSERT_FALSE(covering.pieces.front().whole) << "the observed-piece code path";
    const ConnectivityGraphs w = connectivityGraphs(sceneOf(planes, fields), arr, vp, true);
    const ConnectivityGraphs o = connectivityGraphs(covering, arr, vp, true);
    EXPECT_GT(w.g.size(), 10u);
    EXPECT_TRUE(o.g == w.g);
    EXPECT_TRUE(o.g_prime == w.g_prime);
    EXPECT_TRUE(o.cells_left_through_unobserved.empty());
  }
  std::vector<CuttingPlane> tube;
  const auto add = [&](const Plane& p, std::vector<Section> s, bool closing) {
    tube.push_back(test::observedPlane(p, std::move(s), all, 0.02, int(tube.size()), closing));
  };
  Section a, b;
  a.outer = test::circle(Vec2(0, 0), 1.0, 128);
  b.outer = test::circle(Vec2(1.5, 0), 1.0, 128);
  add(test::axisPlane(2, 0.0), {a}, false);
  add(test::axisPlane(2, 6.0), {b}, false);
  for (int axis = 0; axis < 2; ++axis) {
    add(test::axisPlane(axis, -8.0), {}, true);
    add(test::axisPlane(axis, 9.0), {}, true);
  }
  add(test::axisPlane(2, -3.0), {}, true);
  add(test::axisPlane(2, 9.0), {}, true);
  add(test::axisPlane(0, -1.6), {}, false);  // beside the tube (x in [-1, 2.5])
  add(test::axisPlane(0, 3.1), {}, false);
  std::vector<SectionDistanceField> fields;
  for (const auto& p : tube) fields.push_back(sectionDistanceField(p.sections, 0.02, 0.3));
  const SectionArrangement arr = arrangeSections(tube, 0.1);
  SectionScene scene = sceneOf(tube, fields);
  scene.pieces = observedPieces(tube, true);
  vp.slab_mm = 0.09;
  const ConnectivityGraphs o = connectivityGraphs(scene, arr, vp, true);
  const auto discs = [](const std::vector<GraphEdge>& edges) {
    return std::count_if(edges.begin(), edges.end(), [](const GraphEdge& e) { return e.plane_a == 0 && e.plane_b == 1; });
  };
  EXPECT_EQ(discs(o.g), 0) << "method 1: the planes beside the tube part the discs";
  EXPECT_EQ(discs(o.g_prime), 1) << "method 2: the discs' lifts meet";
}

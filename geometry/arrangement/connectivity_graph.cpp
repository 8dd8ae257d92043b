// Connectivity graphs G and G' along the lifts of section points (see connectivity_graph.h).
#include "geometry/arrangement/connectivity_graph.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <array>
#include <functional>
#include <limits>
#include <memory>
#include <numeric>
#include <tuple>

#include "geometry/core/digital_topology.h"
#include "geometry/core/disjoint_sets.h"
#include "geometry/core/polygon.h"
#include "geometry/core/section_ids.h"
#include "geometry/core/section_locator.h"
#include "geometry/reconstruction/observed_section_voronoi.h"

namespace xsect {

bool GraphEdge::operator<(const GraphEdge& o) const {
  return std::tie(cell, plane_a, section_a, plane_b, section_b) <
         std::tie(o.cell, o.plane_a, o.section_a, o.plane_b, o.section_b);
}
bool GraphEdge::operator==(const GraphEdge& o) const {
  return std::tie(cell, plane_a, section_a, plane_b, section_b) ==
         std::tie(o.cell, o.plane_a, o.section_a, o.plane_b, o.section_b);
}

namespace {

/// The section of plane cp holding x (its projection), or -1.
int sectionAt(const CuttingPlane& cp, const SectionLocator& locator, const Vec3& x) {
  return locator.holding(cp.plane.toPlane(x));
}

/// The section of plane cp holding the nearest point of its observed piece to x, or -1.
int sectionAtPiece(const CuttingPlane& cp, const ObservedPiece& piece, const SectionLocator& locator, const Vec3& x) {
  const Vec2 at = cp.plane.toPlane(x);
  double na, nb;
  if (!std::isfinite(piece.distance(at.x(), at.y(), &na, &nb))) return -1;
  return locator.holding(Vec2(na, nb));
}

/// G on observed pieces: the first t > 0 where d(a + t n, Ω_Q) = t, or +inf when it is not below
/// `below`. f(t) = d(a + t n, Ω_Q) - t is non-increasing (the distance is 1-Lipschitz along the
/// unit-speed ray) and f(root) >= 0 at the plane's root (d(x, Ω_Q) >= |d(x, Q)|), so the first
/// zero is bracketed from there and found by bisection to 1e-12 of its value. With no finite bound
/// yet, the bracket's end doubles (a piece behind the ray is never reached: +inf).
double pieceRoot(const ObservedPiece& piece, const Plane& Q, const Vec3& a, const Vec3& n, double root, double below) {
  if (piece.empty) return std::numeric_limits<double>::infinity();
  const auto f = [&](double t) {
    const Vec3 x = a + t * n;
    const Vec2 at = Q.toPlane(x);
    double na, nb;
    const double o = piece.distance(at.x(), at.y(), &na, &nb), s = Q.signedDistance(x);
    return std::sqrt(s * s + o * o) - t;
  };
  double lo = root, hi = below;
  if (!std::isfinite(hi)) {
    hi = 2 * root;
    for (int k = 0; k < 60 && f(hi) > 0; ++k) hi *= 2;
  }
  if (f(hi) > 0) return std::numeric_limits<double>::infinity();
  if (f(lo) <= 0) return lo;
  for (int k = 0; k < 200 && hi - lo > 1e-12 * hi; ++k) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) > 0 ? lo : hi) = mid;
  }
  return hi;
}

/// G_Ω's lift of a, started into `cell`, ends at x: the cell holding x, or `cell` when no
/// section point bounds it. The segment [a, x] touches no piece, so every plane it crosses is
/// crossed where it was not observed; each crossing flips that plane's sign in the cell's key.
/// `scanned`: the planes that may cross it (all within 2|x - a| of a's section). When it crosses
/// any, `cell` is appended to `passed`.
int meetingCell(const std::vector<CuttingPlane>& planes, const SectionArrangement& arr, const std::vector<int>& scanned,
                int own, const Vec3& a, const Vec3& x, int cell, std::vector<int>& passed) {
  CellKey key = cellKey(arr, cell);
  bool crossed = false;
  for (const int j : scanned) {
    if (j == own) continue;
    const Plane& P = planes[std::size_t(j)].plane;
    const double sa = P.signedDistance(a), sx = P.signedDistance(x);
    if ((sa < 0 && sx > 0) || (sa > 0 && sx < 0)) {
      key = keyAcross(arr, key, j);
      crossed = true;
    }
  }
  if (!crossed) return cell;
  passed.push_back(cell);
  const int id = cellOfKey(arr, key);
  return id >= 0 ? id : cell;
}

GraphEdge edge(int pa, int sa, int pb, int sb, int cell) {
  if (std::tie(pb, sb) < std::tie(pa, sa)) {
    std::swap(pa, pb);
    std::swap(sa, sb);
  }
  return {pa, sa, pb, sb, cell};
}

/// What every section point's lifts read (connectivityGraphs): the scene, the arrangement, the
/// sections' locators and nearby planes, and method 2's query (null without G').
struct LiftContext {
  const SectionScene& scene;
  const std::vector<CuttingPlane>& planes;
  const SectionArrangement& arr;
  SectionIds ids;
  bool partial = false;  ///< observed pieces, one of them not its whole plane (issue 20)
  double step = 0;       ///< the arrangement's sample spacing, mm
  std::vector<SectionLocator> locators;
  /// Per section: the other planes by distance to its bounding disk.
  std::vector<std::vector<std::pair<double, int>>> near_planes;
  const SectionVoronoiPoints* query = nullptr;
  const ObservedLiftTest* lift_test = nullptr;
};

/// The lifts of one section point sp (not a trace point) on both sides of its plane: method 1's
/// (G), on observed pieces swept over the point's normal cone, and method 2's walk (G'); the
/// edges are appended to `out`.
class PointLifts {
 public:
  PointLifts(const LiftContext& k, const SectionPoint& sp, ConnectivityGraphs& out)
      : k_(k), sp_(sp), out_(out), sectionId_(k.ids.of(sp.plane, sp.section)) {}

  void run() {
    // Observed pieces: the lift starts at the nearest point of Ω_A (the point itself inside it),
    // and only from a point of the section. A section runs past its piece by up to a pixel (where
    // the contour follows the image's edge); beyond the piece's edge the region of A is swept by
    // rays in the edge's normal cone, cos θ (±n) + sin θ m (m the outward normal in the plane):
    // sampled at 15° steps and halved between two rays that meet different sections (or none)
    // and end farther apart than the sample spacing, to 1/64 of the first step.
    const Plane& P = k_.planes[std::size_t(sp_.plane)].plane;
    const ObservedPiece* piece = k_.partial ? &k_.scene.pieces[std::size_t(sp_.plane)] : nullptr;
    Vec3 a = P.toWorld(sp_.p), outward = Vec3::Zero();
    if (piece && !piece->whole) {
      double na, nb;
      const double o = piece->distance(sp_.p.x(), sp_.p.y(), &na, &nb);
      if (!std::isfinite(o)) return;
      if (o > 0) {
        if (k_.locators[std::size_t(sp_.plane)].holding(Vec2(na, nb)) != sp_.section) return;
        a = P.toWorld(Vec2(na, nb));
        const Vec2 m = (sp_.p - Vec2(na, nb)) / o;
        outward = m.x() * P.u + m.y() * P.v;
      }
    }
    for (int side = 0; side < 2; ++side) {
      const Vec3 n = (side == 0 ? -1.0 : 1.0) * P.normal;
      const int cell = sp_.cell[std::size_t(side)];
      const LiftEnd e = liftEnd(a, n, k_.partial);
      meets(a, n, e, cell);
      if (outward != Vec3::Zero()) fan(a, n, outward, cell);
      if (k_.query) method2(a, n, e, cell);
    }
  }

 private:
  // Method 1: first t > 0 with d(a + t d, Q) = t for some other plane Q (or its piece); `exit`:
  // where the ray first crosses another plane.
  struct LiftEnd {
    double best = std::numeric_limits<double>::infinity(), exit = best;
    int bq = -1;
  };
  LiftEnd liftEnd(const Vec3& a, const Vec3& d, bool onPieces) {
    LiftEnd e;
    scanned_.clear();
    for (const auto& [lb, jj] : k_.near_planes[std::size_t(sectionId_)]) {
      if (lb >= std::max(2 * e.best, e.exit)) break;
      const std::size_t j = std::size_t(jj);
      const double hq = k_.planes[j].plane.signedDistance(a), c = k_.planes[j].plane.normal.dot(d);
      if (k_.partial) scanned_.push_back(int(j));
      double root = std::numeric_limits<double>::infinity();  // first t with |d(a + t d, Q)| = t
      for (const double t : {c != 1 ? hq / (1 - c) : -1.0, c != -1 ? -hq / (1 + c) : -1.0})
        if (t > 1e-9) root = std::min(root, t);
      if (onPieces && root < e.best && !k_.scene.pieces[j].whole)
        root = pieceRoot(k_.scene.pieces[j], k_.planes[j].plane, a, d, root, e.best);
      if (root < e.best) {
        e.best = root;
        e.bq = int(j);
      }
      if (c != 0 && -hq / c > 0) e.exit = std::min(e.exit, -hq / c);
    }
    return e;
  }

  // Method 1 on the pieces at x = a + t n: the plane and section holding the nearest point of
  // the union of the pieces, or -1s when that point is in no section. A plane Q with bound lb
  // (nearPlanes) is at least lb - t from x.
  std::pair<int, int> nearestPieceSection(const Vec3& x, double t) const {
    double best = std::numeric_limits<double>::infinity();
    int bp = -1;
    Vec2 foot = Vec2::Zero();
    const auto consider = [&](int j) {
      const Plane& Q = k_.planes[std::size_t(j)].plane;
      const Vec2 at = Q.toPlane(x);
      double na, nb;
      const double o = k_.scene.pieces[std::size_t(j)].distance(at.x(), at.y(), &na, &nb), sq = Q.signedDistance(x);
      const double d = std::sqrt(sq * sq + o * o);
      if (d < best || (d == best && j < bp)) {
        best = d;
        bp = j;
        foot = Vec2(na, nb);
      }
    };
    consider(sp_.plane);
    for (const auto& [lb, j] : k_.near_planes[std::size_t(sectionId_)]) {
      if (lb - t > best) break;
      consider(j);
    }
    const int section = bp >= 0 ? k_.locators[std::size_t(bp)].holding(foot) : -1;
    return std::pair<int, int>(section >= 0 ? bp : -1, section);
  }

  // The section the lift meets (-1: none), and the edge of G in the cell where they meet.
  int meets(const Vec3& a, const Vec3& d, const LiftEnd& e, int cell) {
    if (e.bq < 0) return -1;
    const Vec3 x = a + e.best * d;
    const CuttingPlane& Q = k_.planes[std::size_t(e.bq)];
    const int b = k_.partial ? sectionAtPiece(Q, k_.scene.pieces[std::size_t(e.bq)], k_.locators[std::size_t(e.bq)], x)
                          : sectionAt(Q, k_.locators[std::size_t(e.bq)], x);
    const int meeting = k_.partial && cell >= 0 && e.best > e.exit
                            ? meetingCell(k_.planes, k_.arr, scanned_, sp_.plane, a, x, cell, out_.cells_left_through_unobserved)
                            : cell;
    if (b >= 0) out_.g.push_back(edge(sp_.plane, sp_.section, e.bq, b, meeting));
    return b >= 0 ? k_.ids.of(e.bq, b) : -1;
  }

  /// Observed pieces: the rays of the point's normal cone beyond its piece's edge (see run).
  void fan(const Vec3& a, const Vec3& n, const Vec3& outward, int cell) {
    struct Ray {
      double theta;
      int met;
      Vec3 end;
    };
    const auto cast = [&](double theta) {
      const Vec3 d = std::cos(theta) * n + std::sin(theta) * outward;
      const LiftEnd f = liftEnd(a, d, true);
      const int met = meets(a, d, f, cell);
      return Ray{theta, met, std::isfinite(f.best) ? Vec3(a + f.best * d) : Vec3(a + 1e3 * k_.step * d)};
    };
    const double first = M_PI / 12;
    std::vector<Ray> rays;
    for (int k = 1; k <= 6; ++k) rays.push_back(cast(std::min(k * first, 0.5 * M_PI - first / 64)));
    for (std::size_t k = 0; k + 1 < rays.size();) {
      const Ray &r0 = rays[k], &r1 = rays[k + 1];
      if ((r0.met != r1.met || r0.met < 0) && (r0.end - r1.end).norm() > k_.step && r1.theta - r0.theta > first / 64) {
        rays.insert(rays.begin() + std::ptrdiff_t(k + 1), cast(0.5 * (r0.theta + r1.theta)));
        continue;
      }
      ++k;
    }
  }

  void method2(const Vec3& a, const Vec3& n, const LiftEnd& e, int cell) {
    // Method 2: the ray from a lies in A's lift up to method 1's lift point (proof of Theorem
    // 18), where lift'(a) = lift(a) whenever that point projects into a section. From there on
    // it is followed at evenly spaced points (at least one before it leaves the cell), starting
    // just beyond lift(a), while it stays in A's lift. On observed pieces R'_Ω = R_Ω ∪ the points
    // of R' its test keeps (observed_section_voronoi.h): G'_Ω is G_Ω (added below) and the
    // meetings of R''s lifts along the same walk (method 1's lift point on whole planes) while
    // every point is kept.
    const LiftEnd w = k_.partial ? liftEnd(a, n, false) : e;
    const double best = w.best, exit = w.exit;
    const double from = std::min(best, exit);
    std::vector<double> ts;
    if (best < exit) ts.push_back(best * (1 + 1e-9) + 1e-9);
    const int m = std::max(1, std::min(4096, int(std::ceil((exit - from) / k_.step))));
    if (std::isfinite(exit))
      for (int q2 = 0; q2 < m; ++q2) ts.push_back(from + (exit - from) * (q2 + 0.5) / m);
    memo_.radius = -1;  // the ray's points lie in one cell: it is clipped once
    for (const double t : ts) {
      const Vec3 x = a + t * n;
      const SectionVoronoiPoints::Answer ans = k_.query->at(x, &memo_);
      if (!ans.inside) break;
      if (k_.partial) {  // the planes that may meet B(x, h): within h + t of a's section, and A's
        const double h = ans.lift_height;
        ball_.assign(1, sp_.plane);
        for (const auto& [lb, j] : k_.near_planes[std::size_t(sectionId_)]) {
          if (lb > (h + t) * (1 + 1e-9)) break;
          ball_.push_back(j);
        }
        if (!k_.lift_test->keeps(x, h, ans.section_plane, ball_)) {
          // Not kept: x is method 1's on the pieces (R_Ω), the section holding its nearest
          // piece point (or outside).
          const auto [plane, section] = nearestPieceSection(x, t);
          if (plane < 0) break;
          if (plane == sp_.plane && section == sp_.section) continue;
          out_.g_prime.push_back(edge(sp_.plane, sp_.section, plane, section, cell));
          break;
        }
      }
      if (ans.section_plane == sp_.plane) continue;
      const int b = sectionAt(k_.planes[std::size_t(ans.section_plane)], k_.locators[std::size_t(ans.section_plane)], x);
      if (b >= 0) out_.g_prime.push_back(edge(sp_.plane, sp_.section, ans.section_plane, b, cell));
      break;
    }
  }

  const LiftContext& k_;
  const SectionPoint& sp_;
  ConnectivityGraphs& out_;
  const int sectionId_;
  SectionVoronoiPoints::CellMemo memo_;
  std::vector<int> scanned_;  ///< observed pieces: the planes the lift's scan met
  std::vector<int> ball_;     ///< and those that may meet a ball of method 2's test
};

}  // namespace

ConnectivityGraphs connectivityGraphs(const SectionScene& scene, const SectionArrangement& arr,
                                      const SectionVoronoiParams& method2, bool withGPrime) {
  const std::vector<CuttingPlane>& planes = scene.planes;
  const std::vector<SectionDistanceField>& fields = scene.fields;
  LiftContext k{scene, planes, arr, scene.ids(), false, 0, {}, {}, nullptr, nullptr};
  std::unique_ptr<SectionVoronoiPoints> query;
  if (withGPrime) query = std::make_unique<SectionVoronoiPoints>(planes, fields, method2);
  k.query = query.get();
  k.step = arr.sample_spacing_mm;
  // Observed pieces (issue 20): G's lifts end where another plane's piece is as near as the lift's
  // own plane, and join the section holding that piece's nearest point (connectivity_graph.h).
  k.partial = scene.pieces.size() == planes.size() &&
              std::any_of(scene.pieces.begin(), scene.pieces.end(), [](const ObservedPiece& p) { return !p.whole; });
  k.locators.reserve(planes.size());
  for (const CuttingPlane& p : planes) k.locators.emplace_back(p.sections);
  std::unique_ptr<ObservedLiftTest> liftTest;
  if (k.partial && query) liftTest = std::make_unique<ObservedLiftTest>(planes, scene.pieces, k.locators);
  k.lift_test = liftTest.get();
  // Per section: the other planes by distance to its bounding disk. A plane at distance >= 2t
  // from a section point cannot end the lift of length t (|h + t c| = t needs |h| <= 2t), nor
  // bound the ray's exit below |h|: the scan stops at the first plane too far for both.
  k.near_planes.resize(std::size_t(k.ids.count()));
  tbb::parallel_for(std::size_t(0), planes.size(), [&](std::size_t i) {
    for (std::size_t s = 0; s < planes[i].sections.size(); ++s) {
      const Eigen::AlignedBox2d& b = k.locators[i].boxes()[s];
      const Vec3 c = planes[i].plane.toWorld(b.center());
      const double rad = 0.5 * b.diagonal().norm() + 1e-9;
      auto& L = k.near_planes[std::size_t(k.ids.of(int(i), int(s)))];
      for (std::size_t j = 0; j < planes.size(); ++j)
        if (j != i) L.push_back({std::abs(planes[j].plane.signedDistance(c)) - rad, int(j)});
      std::sort(L.begin(), L.end());
    }
  });
  tbb::enumerable_thread_specific<ConnectivityGraphs> local;
  tbb::parallel_for(std::size_t(0), arr.points.size(), [&](std::size_t q) {
    if (arr.points[q].kind == SectionPoint::trace) return;
    PointLifts(k, arr.points[q], local.local()).run();
  });
  ConnectivityGraphs all;
  for (auto& l : local) {
    all.g.insert(all.g.end(), l.g.begin(), l.g.end());
    all.g_prime.insert(all.g_prime.end(), l.g_prime.begin(), l.g_prime.end());
    all.cells_left_through_unobserved.insert(all.cells_left_through_unobserved.end(), l.cells_left_through_unobserved.begin(),
                                        l.cells_left_through_unobserved.end());
  }
  if (k.partial && query) all.g_prime.insert(all.g_prime.end(), all.g.begin(), all.g.end());  // R_Ω ⊆ R'_Ω
  std::vector<int>& passed = all.cells_left_through_unobserved;
  std::sort(passed.begin(), passed.end());
  passed.erase(std::unique(passed.begin(), passed.end()), passed.end());
  for (auto* v : {&all.g, &all.g_prime}) {
    std::sort(v->begin(), v->end());
    v->erase(std::unique(v->begin(), v->end()), v->end());
  }
  return all;
}

GraphVoxelCheck compareWithVoxels(const std::vector<GraphEdge>& edges, const SectionScene& scene,
                                  const SectionArrangement& arrangement, const std::vector<std::uint8_t>& inside,
                                  const GridSpec& grid) {
  return compareWithVoxels(edges, scene, arrangement, solidComponentIndex(inside, grid));
}

GraphVoxelCheck compareWithVoxels(const std::vector<GraphEdge>& edges, const SectionScene& scene,
                                  const SectionArrangement& arrangement, const BlockGrid<std::uint8_t>& inside) {
  return compareWithVoxels(edges, scene, arrangement, solidComponentIndex(inside));
}

GraphVoxelCheck compareWithVoxels(const std::vector<GraphEdge>& edges, const SectionScene& scene,
                                  const SectionArrangement& arr, const SolidComponentIndex& solid) {
  const GridSpec& grid = solid.grid;
  const std::vector<CuttingPlane>& planes = scene.planes;
  const std::vector<SectionDistanceField>& fields = scene.fields;
  const SectionIds ids = scene.ids();
  const int n = ids.count();
  DisjointSets components{std::size_t(n)};
  for (const GraphEdge& e : edges)
    components.unite(std::size_t(ids.of(e.plane_a, e.section_a)), std::size_t(ids.of(e.plane_b, e.section_b)));
  const auto find = [&](int s) { return int(components.find(std::size_t(s))); };
  // The deepest lattice point of each section, and the voxel holding it.
  std::vector<float> depth(std::size_t(n), 0.f);
  std::vector<Vec3> where(std::size_t(n), Vec3::Zero());
  for (const SectionPoint& sp : arr.points) {
    if (sp.kind != SectionPoint::sample || std::size_t(sp.plane) >= fields.size()) continue;
    const int id = ids.of(sp.plane, sp.section);
    const float f = fields[std::size_t(sp.plane)].sample(sp.p.x(), sp.p.y());
    if (f < depth[std::size_t(id)]) {
      depth[std::size_t(id)] = f;
      where[std::size_t(id)] = planes[std::size_t(sp.plane)].plane.toWorld(sp.p);
    }
  }
  std::vector<int> voxel(std::size_t(n), -1);
  GraphVoxelCheck r;
  for (int s = 0; s < n; ++s) {
    if (depth[std::size_t(s)] >= 0) {
      ++r.sections_unlocated;
      continue;
    }
    const Vec3 g = (where[std::size_t(s)] - grid.origin) / grid.voxel;
    const int i = int(std::lround(g.x())), j = int(std::lround(g.y())), k = int(std::lround(g.z()));
    if (i < 0 || j < 0 || k < 0 || i >= grid.dims[0] || j >= grid.dims[1] || k >= grid.dims[2] ||
        solid.at(i, j, k) < 0) {
      ++r.sections_unlocated;
      continue;
    }
    voxel[std::size_t(s)] = solid.at(i, j, k);
  }
  std::vector<int> roots, labels;
  for (int s = 0; s < n; ++s) {
    roots.push_back(find(s));
    if (voxel[std::size_t(s)] >= 0) labels.push_back(voxel[std::size_t(s)]);
  }
  std::sort(roots.begin(), roots.end());
  std::sort(labels.begin(), labels.end());
  r.graph_components = int(std::unique(roots.begin(), roots.end()) - roots.begin());
  r.voxel_components = int(std::unique(labels.begin(), labels.end()) - labels.begin());
  for (int s = 0; s < n; ++s)
    for (int t = s + 1; t < n; ++t) {
      if (voxel[std::size_t(s)] < 0 || voxel[std::size_t(t)] < 0) continue;
      const bool g = find(s) == find(t), v = voxel[std::size_t(s)] == voxel[std::size_t(t)];
      r.pairs_joined_by_graph_only += g && !v;
      r.pairs_joined_by_voxels_only += v && !g;
    }
  r.same_partition = r.pairs_joined_by_graph_only == 0 && r.pairs_joined_by_voxels_only == 0;
  return r;
}

}  // namespace xsect

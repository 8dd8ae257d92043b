// The labeling Φ along the lift rays of the section points, G'' and the branching points (see
// branching_diagram.h).
#include "geometry/delaunay/branching_diagram.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <utility>

#include "geometry/core/polygon.h"
#include "geometry/core/section_locator.h"
#include "geometry/core/section_ids.h"

namespace xsect {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Roots are bracketed to this fraction of the ray's length: ties between planes are resolved
/// far below the lattice spacing (rays of small cells are short).
constexpr double kRelative = 1e-9;
/// Roots this close (relative) are ties: lift'(a) lies on the boundary of several Voronoi cells
/// (an edge or vertex of the diagram), every one of them a label for G'' (Def. 44).
constexpr double kTie = 1e-8;

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

using Nearest = SectionLocator::Nearest;
using RingRef = SectionLocator::RingRef;

/// Half-plane a·u + b·v + c >= 0 in a plane's coordinates (mm).
struct HalfPlane {
  double a, b, c;
  double at(const Vec2& p) const { return a * p.x() + b * p.y() + c; }
};

/// One plane's sections, its raster of f_P and the bounds that prune polygon queries.
struct PlaneSections {
  const Plane* plane = nullptr;
  const std::vector<Section>* sections = nullptr;
  const SectionDistanceField* field = nullptr;
  SectionLocator locator;  ///< holding, nearest contour point, runs of edges

  explicit PlaneSections(const CuttingPlane& cp, const SectionDistanceField& f)
      : plane(&cp.plane), sections(&cp.sections), field(&f), locator(cp.sections) {}
  bool empty() const { return sections->empty(); }
  double boxBound(const Vec2& p) const { return locator.boxBound(p); }
  int holding(const Vec2& p) const { return locator.holding(p); }
  Nearest nearestContour(const Vec2& p) const { return locator.nearestContour(p); }
  /// The point of the sections nearest to p (p itself inside one).
  Nearest nearest(const Vec2& p) const {
    const int s = holding(p);
    return s >= 0 ? Nearest{0.0, p, s} : nearestContour(p);
  }

  /// The point nearest to p of the sections clipped to K = square(p, rho) ∩ half-planes (the
  /// face of a cell seen from a point above p); d = +inf when that part is empty. The boundary of
  /// (sections ∩ K) near p consists of contour pieces inside K and pieces of the half-planes'
  /// lines inside the sections; the square's edges lie rho from p or farther.
  Nearest nearestVisible(const Vec2& p, double rho, const std::vector<HalfPlane>& hp) const {
    bool pIn = true;
    for (const HalfPlane& H : hp) pIn = pIn && H.at(p) >= 0;
    if (pIn) {
      const int s = holding(p);
      if (s >= 0) return {0.0, p, s};
    }
    std::vector<Vec2> poly = {p + Vec2(-rho, -rho), p + Vec2(rho, -rho), p + Vec2(rho, rho), p + Vec2(-rho, rho)};
    std::vector<bool> onLine = {false, false, false, false};  // edge i (poly[i] -> poly[i+1]) on a half-plane's line
    std::vector<Vec2> np;
    std::vector<bool> nl;
    for (const HalfPlane& H : hp) {
      np.clear();
      nl.clear();
      for (std::size_t i = 0; i < poly.size(); ++i) {
        const Vec2& A = poly[i];
        const Vec2& B = poly[(i + 1) % poly.size()];
        const double fa = H.at(A), fb = H.at(B);
        if (fa >= 0) {
          np.push_back(A);
          nl.push_back(onLine[i]);
          if (fb < 0) {
            np.push_back(A + (fa / (fa - fb)) * (B - A));
            nl.push_back(true);
          }
        } else if (fb >= 0) {
          np.push_back(A + (fa / (fa - fb)) * (B - A));
          nl.push_back(onLine[i]);
        }
      }
      poly.swap(np);
      onLine.swap(nl);
      if (poly.size() < 3) return {};
    }
    Eigen::AlignedBox2d kb;
    for (const Vec2& v : poly) kb.extend(v);
    const std::size_t m = poly.size();
    Nearest best;
    const auto consider = [&](const Vec2& a, const Vec2& b, int s) {
      const Vec2 q = nearestOnSegment(p, a, b);
      const double d = (q - p).norm();
      if (d < best.d) best = {d, q, s};
    };
    // Contour pieces inside K (Liang-Barsky against K's edges; K is counter-clockwise).
    const auto meetsK = [&](const Eigen::AlignedBox2d& b) { return b.intersects(kb); };
    for (const RingRef& r : locator.rings()) {
      if (!r.box.intersects(kb)) continue;
      SectionLocator::forEdges(r, meetsK, [&](const Vec2& s0, const Vec2& s1) {
        const Vec2 d = s1 - s0;
        double t0 = 0, t1 = 1;
        for (std::size_t i = 0; i < m && t0 <= t1; ++i) {
          const Vec2 e = poly[(i + 1) % m] - poly[i];
          const double c0 = cross2(e, s0 - poly[i]), cd = cross2(e, d);
          if (cd == 0) {
            if (c0 < 0) t1 = -1;
          } else if (cd > 0) {
            t0 = std::max(t0, -c0 / cd);
          } else {
            t1 = std::min(t1, -c0 / cd);
          }
        }
        if (t0 <= t1) consider(s0 + t0 * d, s0 + t1 * d, r.section);
      });
    }
    // Pieces of K's edges on the half-planes' lines (other planes' traces) inside the sections.
    std::vector<double> ts;
    for (std::size_t i = 0; i < m; ++i) {
      if (!onLine[i]) continue;
      const Vec2 A = poly[i], B = poly[(i + 1) % m], e = B - A;
      if ((nearestOnSegment(p, A, B) - p).norm() >= best.d) continue;
      Eigen::AlignedBox2d eb(A.cwiseMin(B), A.cwiseMax(B));
      ts.assign({0.0, 1.0});
      const auto meetsEdge = [&](const Eigen::AlignedBox2d& b) { return b.intersects(eb); };
      for (const RingRef& r : locator.rings()) {
        if (!r.box.intersects(eb)) continue;
        SectionLocator::forEdges(r, meetsEdge, [&](const Vec2& s0, const Vec2& s1) {
          const Vec2 d = s1 - s0;
          const double den = cross2(e, d);
          if (den == 0) return;
          const double t = cross2(s0 - A, d) / den, u = cross2(s0 - A, e) / den;
          if (t > 0 && t < 1 && u >= 0 && u <= 1) ts.push_back(t);
        });
      }
      std::sort(ts.begin(), ts.end());
      for (std::size_t k = 0; k + 1 < ts.size(); ++k) {
        if (ts[k + 1] - ts[k] <= 1e-12) continue;
        const Vec2 a = A + ts[k] * e, b = A + ts[k + 1] * e;
        if ((nearestOnSegment(p, a, b) - p).norm() >= best.d) continue;
        const int s = holding(0.5 * (a + b));
        if (s >= 0) consider(a, b, s);
      }
    }
    return best;
  }
};

/// The last in-plane distance to the sections evaluated on the polygons along one ray (0 inside):
/// it is 1-Lipschitz in p, so nearby queries are often decided without the polygons.
struct Memo {
  Vec2 p = Vec2::Zero();
  double d = -1;
};

/// Whether the distance from x to Q's sections (all of them, hidden or not) is at most t (mm).
/// The raster decides where its four nodes hold exact distances and its value is farther than a
/// node spacing from the threshold; the polygons elsewhere (beyond the band, near ties).
bool reaches(const PlaneSections& Q, const Vec3& x, double t, Memo& memo, std::int64_t& polygon) {
  const double h = Q.plane->signedDistance(x);
  if (!(std::abs(h) <= t)) return false;
  const double rho = std::sqrt(std::max(0.0, t * t - h * h));
  const Vec2 p = Q.plane->toPlane(x);
  const SectionDistanceField& F = *Q.field;
  const bool raster = F.nu >= 2 && F.nv >= 2;
  double lb = Q.boxBound(p);
  float v;
  if (raster && F.sampleWithinBand(p.x(), p.y(), &v)) {
    if (std::abs(double(v) - rho) > F.step) return double(v) <= rho;
  } else if (raster && F.sample(p.x(), p.y()) < 0) {
    return true;  // deeper than the band inside a section
  } else if (raster) {
    // Beyond the band (a node of the square holds +band, f_Q is 1-Lipschitz): f_Q >= band - 1.5 step.
    lb = std::max(lb, double(F.band) - 1.5 * F.step);
  }
  if (lb > rho) return false;
  if (memo.d >= 0) {
    const double m = (p - memo.p).norm();
    if (memo.d - m > rho) return false;
    if (memo.d + m <= rho) return true;
  }
  ++polygon;
  memo = {p, Q.nearest(p).d};
  return memo.d <= rho;
}

/// First t >= 0 with |h + t c| <= t: where the ray first comes as near to plane Q as to its own
/// (h: signed distance of the ray's origin to Q, c: cosine of the ray with Q's normal).
double planeRoot(double h, double c) {
  if (h == 0) return 0;
  double r = kInf;
  if (c != 1 && h / (1 - c) >= 0) r = std::min(r, h / (1 - c));
  if (c != -1 && -h / (1 + c) >= 0) r = std::min(r, -h / (1 + c));
  return r;
}

struct Scratch {
  std::vector<int> cand;                      ///< planes near enough to end the ray or hide a point
  std::vector<std::pair<double, int>> order;  ///< (plane root, plane) of candidates with sections
  std::vector<HalfPlane> hp;
  std::int64_t rays = 0, labelled = 0, hidden = 0, polygon = 0;
};

/// A section whose Voronoi cell the ray reaches at lift'(a), and where.
struct Hit {
  double t = kInf;        ///< length of the ray, mm
  int label = -1;         ///< flat section id
  int foot_side = -1;     ///< side of the section's plane facing the cell (0: negative, 1: positive)
  bool interior = false;  ///< lift'(a) projects into the section (lift'(a) ∈ lift'(Φ(a)))
  Vec2 foot = Vec2::Zero();  ///< that projection, plane coordinates of the section's plane (mm)
};

/// Φ at one point: the nearest hit first, then the ones as near (to kTie), up to three (a point of
/// the cell has at most four nearest sections in general position, one of them the ray's own).
struct RayLabel {
  std::array<Hit, 3> hits;
  int count = 0;
  int label() const { return count > 0 ? hits[0].label : -1; }
};

/// Follows the rays of section points (see branching_diagram.h).
class Labeller {
 public:
  Labeller(const SectionScene& scene, const std::vector<PlaneSections>& info)
      : planes_(scene.planes), info_(info), ids_(scene.ids()), near_(std::size_t(ids_.count())) {
    // Per section: the other planes by a lower bound of their distance to its bounding disk. A
    // plane at distance >= 2t from a section point cannot end a ray of length t (|h + t c| <= t
    // needs |h| <= 2t) nor hide a point at distance t from x(t); one at distance >= t_exit is not
    // crossed before t_exit.
    tbb::parallel_for(std::size_t(0), planes_.size(), [&](std::size_t i) {
      for (std::size_t s = 0; s < planes_[i].sections.size(); ++s) {
        const Eigen::AlignedBox2d& b = info_[i].locator.boxes()[s];
        const Vec3 c = planes_[i].plane.toWorld(b.center());
        const double rad = 0.5 * b.diagonal().norm() + 1e-9;
        auto& L = near_[std::size_t(ids_.of(int(i), int(s)))];
        for (std::size_t j = 0; j < planes_.size(); ++j)
          if (j != i) L.push_back({std::abs(planes_[j].plane.signedDistance(c)) - rad, int(j)});
        std::sort(L.begin(), L.end());
      }
    });
  }

  /// Φ at point p (plane coordinates, mm) of section `section` of plane `plane`, on side `side`.
  RayLabel label(int plane, int section, const Vec2& p, int side, Scratch& w) const {
    const Plane& P = planes_[std::size_t(plane)].plane;
    const Vec3 a = P.toWorld(p);
    const Vec3 n = (side == 0 ? -1.0 : 1.0) * P.normal;
    const auto at = [&](double t) -> Vec3 { return a + t * n; };
    const auto& near = near_[std::size_t(ids_.of(plane, section))];
    double exit = kInf;
    for (const auto& [lb, j] : near) {
      if (lb >= exit) break;
      const Plane& R = planes_[std::size_t(j)].plane;
      const double h = R.signedDistance(a), c = R.normal.dot(n);
      if (c != 0 && -h / c > 0) exit = std::min(exit, -h / c);
    }
    w.cand.clear();
    w.order.clear();
    for (const auto& [lb, j] : near) {
      if (lb >= 2 * exit) break;
      w.cand.push_back(j);
      if (info_[std::size_t(j)].empty()) continue;
      const Plane& Q = planes_[std::size_t(j)].plane;
      const double t1 = planeRoot(Q.signedDistance(a), Q.normal.dot(n));
      if (t1 < exit) w.order.push_back({t1, j});
    }
    std::sort(w.order.begin(), w.order.end());
    std::array<Hit, 8> found;  // per plane whose root comes within the ties of the nearest
    int nf = 0;
    double best = kInf;
    for (const auto& [t1, qi] : w.order) {
      const double hi = std::min(best * (1 + kTie), exit);
      if (!(t1 <= hi) || nf == int(found.size())) break;
      const PlaneSections& Q = info_[std::size_t(qi)];
      Memo memo;
      if (!reaches(Q, at(hi), hi, memo, w.polygon)) continue;
      double lo = t1, up = hi;
      if (reaches(Q, at(lo), lo, memo, w.polygon)) {
        up = lo;
      } else {
        for (int it = 0; it < 64 && up - lo > kRelative * hi; ++it) {
          const double mid = 0.5 * (lo + up);
          (reaches(Q, at(mid), mid, memo, w.polygon) ? up : lo) = mid;
        }
      }
      Nearest m = Q.nearest(Q.plane->toPlane(at(up)));
      if (m.section < 0) continue;
      if (hidden(at(up), Q.plane->toWorld(m.q), plane, qi, w)) {
        // The root found with every point of Q's sections is a lower bound: solve again with the
        // visible part only.
        ++w.hidden;
        if (!visibleWithin(Q, qi, plane, at(hi), hi, &m, w)) continue;
        Nearest mm;
        lo = up;
        up = hi;
        if (visibleWithin(Q, qi, plane, at(lo), lo, &mm, w)) {
          up = lo;
          m = mm;
        } else {
          for (int it = 0; it < 64 && up - lo > kRelative * hi; ++it) {
            const double mid = 0.5 * (lo + up);
            if (visibleWithin(Q, qi, plane, at(mid), mid, &mm, w)) {
              up = mid;
              m = mm;
            } else {
              lo = mid;
            }
          }
        }
        if (m.section < 0) continue;
      }
      found[std::size_t(nf++)] = {up, ids_.of(qi, m.section), Q.plane->signedDistance(at(up)) > 0 ? 1 : 0,
                                  m.d == 0, m.q};
      best = std::min(best, up);
    }
    // The nearest first (the earlier plane in the walk on equal lengths), then its ties.
    std::stable_sort(found.begin(), found.begin() + nf, [](const Hit& l, const Hit& r) { return l.t < r.t; });
    RayLabel out;
    for (int k = 0; k < nf && out.count < int(out.hits.size()); ++k)
      if (found[std::size_t(k)].t <= best * (1 + kTie)) out.hits[std::size_t(out.count++)] = found[std::size_t(k)];
    return out;
  }

 private:
  /// Whether point s of plane `own` is hidden from x (in the cell, off the planes) by a plane of
  /// w.cand or by the ray's plane: C is convex, s lies on ∂C exactly when no plane separates them.
  bool hidden(const Vec3& x, const Vec3& s, int rayPlane, int own, const Scratch& w) const {
    const double eps = 1e-9 * (x - s).norm();
    const auto separates = [&](int r) {
      const Plane& R = planes_[std::size_t(r)].plane;
      const double sx = R.signedDistance(x), ss = R.signedDistance(s);
      return (sx > 0 && ss < -eps) || (sx < 0 && ss > eps);
    };
    if (separates(rayPlane)) return true;
    for (const int r : w.cand)
      if (r != own && separates(r)) return true;
    return false;
  }

  /// The nearest point of Q's sections on the face of the cell seen from x, when it lies within
  /// t (mm) of x: the disk of Q within t of x clipped by the planes nearer to x than t.
  bool visibleWithin(const PlaneSections& Q, int qi, int rayPlane, const Vec3& x, double t, Nearest* m,
                     Scratch& w) const {
    const double h = Q.plane->signedDistance(x);
    if (!(std::abs(h) <= t)) return false;
    const double rho = std::sqrt(std::max(0.0, t * t - h * h));
    w.hp.clear();
    bool all = false;  // a plane parallel to Q hides all of it
    const auto add = [&](int r) {
      const Plane& R = planes_[std::size_t(r)].plane;
      const double sx = R.signedDistance(x);
      if (r == qi || sx == 0 || std::abs(sx) >= t) return;
      const double sg = sx > 0 ? 1 : -1;
      const HalfPlane H{sg * R.normal.dot(Q.plane->u), sg * R.normal.dot(Q.plane->v),
                        sg * R.normal.dot(Q.plane->origin - R.origin)};
      if (H.a == 0 && H.b == 0) all = all || H.c < 0;
      else w.hp.push_back(H);
    };
    add(rayPlane);
    for (const int r : w.cand) add(r);
    if (all) return false;
    ++w.polygon;
    *m = Q.nearestVisible(Q.plane->toPlane(x), rho, w.hp);
    return m->d <= rho;
  }

  const std::vector<CuttingPlane>& planes_;
  const std::vector<PlaneSections>& info_;
  SectionIds ids_;
  std::vector<std::vector<std::pair<double, int>>> near_;
};

using Directed = std::tuple<int, int, int, int, int>;  // cell, plane, section, label plane, label section

/// A point of a section where a ray from another section ended (a foot of lift'(a) inside B).
struct Witness {
  int cell, plane, section, side;
  Vec2 p;
  auto key() const { return std::make_tuple(cell, plane, section, side, p.x(), p.y()); }
};

/// What the labelling steps share: the arrangement, the labeller (Φ along rays), each section's
/// (plane, section) by flat id, and the threads' scratch.
struct Labelling {
  const SectionArrangement& arr;
  const Labeller& labeller;
  const std::vector<std::pair<int, int>>& sectionOf;
  tbb::enumerable_thread_specific<Scratch>& scratch;
};

/// A label tied with a point's nearest one (point q, its side).
struct Tie {
  std::size_t q;
  int side, label;
  bool operator<(const Tie& o) const { return std::tie(q, side, label) < std::tie(o.q, o.side, o.label); }
};

/// Φ at the points: the nearest label per side (into out.label), and the labels tied with it.
std::vector<Tie> labelPoints(const Labelling& k, BranchingDiagram& out) {
  const SectionArrangement& arr = k.arr;
  tbb::enumerable_thread_specific<std::vector<Tie>> tiesLocal;
  tbb::parallel_for(std::size_t(0), arr.points.size(), [&](std::size_t q) {
    const SectionPoint& sp = arr.points[q];
    if (sp.kind == SectionPoint::trace) return;
    Scratch& w = k.scratch.local();
    for (int side = 0; side < 2; ++side)
      if (sp.cell[std::size_t(side)] >= 0) {
        const RayLabel r = k.labeller.label(sp.plane, sp.section, sp.p, side, w);
        ++w.rays;
        w.labelled += r.count > 0;
        out.label[q][std::size_t(side)] = r.label();
        for (int h = 1; h < r.count; ++h) tiesLocal.local().push_back({q, side, r.hits[std::size_t(h)].label});
      }
  });
  std::vector<Tie> ties;
  for (const auto& l : tiesLocal) ties.insert(ties.end(), l.begin(), l.end());
  std::sort(ties.begin(), ties.end());
  return ties;
}

/// Directed label (cell, A) -> Φ: appended.
void addDirected(const Labelling& k, std::vector<Directed>& directed, int cell, int plane, int section, int label) {
  const auto& [lp, ls] = k.sectionOf[std::size_t(label)];
  directed.emplace_back(cell, plane, section, lp, ls);
}

/// The directed labels of the points and their ties, sorted and unique.
std::vector<Directed> directedLabels(const Labelling& k, const BranchingDiagram& out, const std::vector<Tie>& ties) {
  const SectionArrangement& arr = k.arr;
  std::vector<Directed> directed;
  for (std::size_t q = 0; q < arr.points.size(); ++q)
    for (int side = 0; side < 2; ++side)
      if (out.label[q][std::size_t(side)] >= 0) {
        const SectionPoint& sp = arr.points[q];
        addDirected(k, directed, sp.cell[std::size_t(side)], sp.plane, sp.section, out.label[q][std::size_t(side)]);
      }
  for (const Tie& t : ties) {
    const SectionPoint& sp = arr.points[t.q];
    addDirected(k, directed, sp.cell[std::size_t(t.side)], sp.plane, sp.section, t.label);
  }
  tbb::parallel_sort(directed.begin(), directed.end());
  directed.erase(std::unique(directed.begin(), directed.end()), directed.end());
  return directed;
}

/// Where A -> B has no B -> A among the samples, B is labelled again at the feet of the lifts
/// that reached B's Voronoi cell from A inside B: a region of B thinner than the lattice (a
/// small sub-section, a narrow Voronoi face) is seen there. Then lift'(a) = lift'(b) in theory,
/// and Φ(b) = A unless a third section is as near (evaluated, not assumed). The rays of A's
/// points labelled B are followed again for their feet (not kept for every point).
/// Returns the witnesses labelled; their labels are added to `directed`.
std::int64_t labelWitnesses(const Labelling& lab, const BranchingDiagram& out, const std::vector<Tie>& ties,
                            std::vector<Directed>& directed) {
  const SectionArrangement& arr = lab.arr;
  const auto& sectionOf = lab.sectionOf;
  const Labeller& labeller = lab.labeller;
  auto& scratch = lab.scratch;
  const auto unresolved = [&](int cell, int plane, int section, int label) {
    const auto& [lp, ls] = sectionOf[std::size_t(label)];
    return !std::binary_search(directed.begin(), directed.end(), Directed{cell, lp, ls, plane, section});
  };
  std::vector<std::pair<std::size_t, int>> again;  // (point, side)
  for (std::size_t q = 0; q < arr.points.size(); ++q)
    for (int side = 0; side < 2; ++side) {
      const SectionPoint& sp = arr.points[q];
      const int l = out.label[q][std::size_t(side)];
      if (l >= 0 && unresolved(sp.cell[std::size_t(side)], sp.plane, sp.section, l))
        again.push_back({q, side});
    }
  for (const Tie& t : ties) {
    const SectionPoint& sp = arr.points[t.q];
    if (unresolved(sp.cell[std::size_t(t.side)], sp.plane, sp.section, t.label))
      again.push_back({t.q, t.side});
  }
  tbb::parallel_sort(again.begin(), again.end());
  again.erase(std::unique(again.begin(), again.end()), again.end());
  tbb::enumerable_thread_specific<std::vector<Witness>> witnessesLocal;
  tbb::parallel_for(std::size_t(0), again.size(), [&](std::size_t k) {
    const auto [q, side] = again[k];
    const SectionPoint& sp = arr.points[q];
    const int cell = sp.cell[std::size_t(side)];
    const RayLabel r = labeller.label(sp.plane, sp.section, sp.p, side, scratch.local());
    for (int h = 0; h < r.count; ++h) {
      const Hit& hit = r.hits[std::size_t(h)];
      if (!hit.interior || !unresolved(cell, sp.plane, sp.section, hit.label)) continue;
      const auto& [lp, ls] = sectionOf[std::size_t(hit.label)];
      witnessesLocal.local().push_back({cell, lp, ls, hit.foot_side, hit.foot});
    }
  });
  std::vector<Witness> witnesses;
  for (const auto& l : witnessesLocal) witnesses.insert(witnesses.end(), l.begin(), l.end());
  tbb::parallel_sort(witnesses.begin(), witnesses.end(),
                     [](const Witness& l, const Witness& r) { return l.key() < r.key(); });
  witnesses.erase(std::unique(witnesses.begin(), witnesses.end(),
                              [](const Witness& l, const Witness& r) { return l.key() == r.key(); }),
                  witnesses.end());
  std::vector<RayLabel> witnessLabel(witnesses.size());
  tbb::parallel_for(std::size_t(0), witnesses.size(), [&](std::size_t k) {
    const Witness& v = witnesses[k];
    witnessLabel[k] = labeller.label(v.plane, v.section, v.p, v.side, scratch.local());
  });
  for (std::size_t k = 0; k < witnesses.size(); ++k) {
    const Witness& v = witnesses[k];
    for (int h = 0; h < witnessLabel[k].count; ++h)
      addDirected(lab, directed, v.cell, v.plane, v.section, witnessLabel[k].hits[std::size_t(h)].label);
  }
  return std::int64_t(witnesses.size());
}

/// G'': the directed labels kept where the reverse exists too.
std::vector<GraphEdge> symmetricLabels(std::vector<Directed>& directed) {
  std::vector<GraphEdge> g;
  tbb::parallel_sort(directed.begin(), directed.end());
  directed.erase(std::unique(directed.begin(), directed.end()), directed.end());
  for (const auto& [cell, pa, sa, pb, sb] : directed)
    if (std::tie(pa, sa) < std::tie(pb, sb) &&
        std::binary_search(directed.begin(), directed.end(), Directed{cell, pb, sb, pa, sa}))
      g.push_back(GraphEdge{pa, sa, pb, sb, cell});
  std::sort(g.begin(), g.end());
  return g;
}

/// Branching points: lattice samples of one section and cell side, 4-neighbours, labelled with
/// two different sections. Lattice index: samples lie at (k + ½)·spacing.
std::vector<BranchingPoint> branchingPoints(const SectionArrangement& arr, const BranchingDiagram& out, bool withCellExits) {
  const double spacing = arr.sample_spacing_mm;
  std::vector<BranchingPoint> points;
  struct Sample {
    int plane, section, cell;
    std::int64_t j, i;
    int label;
    Vec2 p;
    auto key() const { return std::make_tuple(plane, section, cell, j, i); }
  };
  std::vector<std::size_t> firstSample(arr.points.size() + 1, 0);
  for (std::size_t q = 0; q < arr.points.size(); ++q) {
    const SectionPoint& sp = arr.points[q];
    firstSample[q + 1] = firstSample[q] + (sp.kind == SectionPoint::sample
                                               ? std::size_t(sp.cell[0] >= 0) + std::size_t(sp.cell[1] >= 0)
                                               : 0);
  }
  std::vector<Sample> samples(firstSample.back());
  tbb::parallel_for(std::size_t(0), arr.points.size(), [&](std::size_t q) {
    const SectionPoint& sp = arr.points[q];
    if (sp.kind != SectionPoint::sample) return;
    const std::int64_t i = std::llround(sp.p.x() / spacing - 0.5);
    const std::int64_t j = std::llround(sp.p.y() / spacing - 0.5);
    std::size_t k = firstSample[q];
    for (std::size_t side = 0; side < 2; ++side)
      if (sp.cell[side] >= 0) samples[k++] = {sp.plane, sp.section, sp.cell[side], j, i, out.label[q][side], sp.p};
  });
  // Sorted in parallel (the whole sample is the key: no two are equivalent but equal ones), the
  // 4-neighbours looked up in parallel and gathered in order (multiaxial-3x40: from the samples to
  // the branching points 0.16 s on one thread, 0.14 s so, beside the graphs).
  const auto byKey = [](const Sample& l, const Sample& r) { return l.key() < r.key(); };
  tbb::parallel_sort(samples.begin(), samples.end(), [](const Sample& l, const Sample& r) {
    return std::make_tuple(l.key(), l.label, l.p.x(), l.p.y()) < std::make_tuple(r.key(), r.label, r.p.x(), r.p.y());
  });
  const auto branches = [&](int l1, int l2) { return l1 != l2 && ((l1 >= 0 && l2 >= 0) || withCellExits); };
  std::vector<std::array<std::int64_t, 2>> neighbour(samples.size(), {-1, -1});  // right, up
  tbb::parallel_for(std::size_t(0), samples.size(), [&](std::size_t k) {
    const Sample& s = samples[k];
    Sample right = s, up = s;
    ++right.i;
    ++up.j;
    for (int n = 0; n < 2; ++n) {
      const Sample& probe = n == 0 ? right : up;
      const auto it = std::lower_bound(samples.begin(), samples.end(), probe, byKey);
      if (it == samples.end() || it->key() != probe.key() || !branches(s.label, it->label)) continue;
      neighbour[k][std::size_t(n)] = it - samples.begin();
    }
  });
  for (std::size_t k = 0; k < samples.size(); ++k)
    for (const std::int64_t o : neighbour[k]) {
      if (o < 0) continue;
      const Sample& s = samples[k];
      points.push_back(BranchingPoint{s.cell, s.plane, s.section, 0.5 * (s.p + samples[std::size_t(o)].p)});
    }
  const auto pointKey = [](const BranchingPoint& b) {
    return std::make_tuple(b.cell, b.plane, b.section, b.p.x(), b.p.y());
  };
  tbb::parallel_sort(points.begin(), points.end(),
                     [&](const BranchingPoint& l, const BranchingPoint& r) { return pointKey(l) < pointKey(r); });
  const auto same = [&](const BranchingPoint& l, const BranchingPoint& r) { return pointKey(l) == pointKey(r); };
  points.erase(std::unique(points.begin(), points.end(), same), points.end());
  return points;
}

}  // namespace

BranchingDiagram branchingDiagram(const SectionScene& scene, const SectionArrangement& arr,
                                  bool withCellExits) {
  const std::vector<CuttingPlane>& planes = scene.planes;
  const SectionIds ids = scene.ids();
  std::vector<PlaneSections> info;
  info.reserve(planes.size());
  for (std::size_t i = 0; i < planes.size(); ++i) info.emplace_back(planes[i], scene.fields[i]);
  std::vector<std::pair<int, int>> sectionOf(std::size_t(ids.count()));  // flat id -> (plane, section)
  for (std::size_t i = 0; i < planes.size(); ++i)
    for (std::size_t s = 0; s < planes[i].sections.size(); ++s)
      sectionOf[std::size_t(ids.of(int(i), int(s)))] = {int(i), int(s)};
  const Labeller labeller(scene, info);
  tbb::enumerable_thread_specific<Scratch> scratch;
  const Labelling k{arr, labeller, sectionOf, scratch};

  BranchingDiagram out;
  out.label.assign(arr.points.size(), {-1, -1});
  const std::vector<Tie> ties = labelPoints(k, out);
  std::vector<Directed> directed = directedLabels(k, out, ties);
  out.witnesses = labelWitnesses(k, out, ties, directed);
  for (const Scratch& w : scratch) {
    out.rays += w.rays;
    out.labelled += w.labelled;
    out.hidden_roots += w.hidden;
    out.polygon_distances += w.polygon;
  }
  out.g_double_prime = symmetricLabels(directed);
  out.points = branchingPoints(arr, out, withCellExits);
  return out;
}

}  // namespace xsect

// Method 2 on a voxel grid: nearest visible section by a walk over planes sorted by distance
// (see section_voronoi_reconstruction.h).
#include "geometry/reconstruction/section_voronoi_reconstruction.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "geometry/core/polygon.h"

namespace xsect {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct PlaneRow {
  Vec3 n, u, v, o, an;  // unit normal, frame, origin, |n| componentwise
  double d = 0;         // n.o
  double s(const Vec3& x) const { return n.dot(x) - d; }
};

/// Contour segments of one plane's sections, bucketed on a uniform grid for local queries.
struct SegmentGrid {
  std::vector<std::array<Vec2, 2>> segs;
  Vec2 lo = Vec2::Zero();
  double cell = 1;
  int nx = 0, ny = 0;
  std::vector<int> start, items, empty;

  void build(const std::vector<Section>& sections) {
    const auto addRing = [&](const Ring& r) {
      for (std::size_t i = 0; i < r.size(); ++i) segs.push_back({r[i], r[(i + 1) % r.size()]});
    };
    for (const Section& s : sections) {
      addRing(s.outer);
      for (const Ring& h : s.holes) addRing(h);
    }
    if (segs.empty()) return;
    Vec2 hi = segs[0][0];
    lo = hi;
    double len = 0;
    for (const auto& s : segs) {
      for (const Vec2& p : s) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
      len += (s[1] - s[0]).norm();
    }
    const Vec2 ext = hi - lo;
    cell = std::max({ext.maxCoeff() / 128.0, 4.0 * len / double(segs.size()), 1e-6});
    nx = std::max(1, int(std::ceil(ext.x() / cell)) + 1);
    ny = std::max(1, int(std::ceil(ext.y() / cell)) + 1);
    std::vector<int> count(std::size_t(nx) * ny + 1, 0);
    const auto range = [&](const std::array<Vec2, 2>& s, int* i0, int* i1, int* j0, int* j1) {
      *i0 = std::clamp(int((std::min(s[0].x(), s[1].x()) - lo.x()) / cell), 0, nx - 1);
      *i1 = std::clamp(int((std::max(s[0].x(), s[1].x()) - lo.x()) / cell), 0, nx - 1);
      *j0 = std::clamp(int((std::min(s[0].y(), s[1].y()) - lo.y()) / cell), 0, ny - 1);
      *j1 = std::clamp(int((std::max(s[0].y(), s[1].y()) - lo.y()) / cell), 0, ny - 1);
    };
    for (const auto& s : segs) {
      int i0, i1, j0, j1;
      range(s, &i0, &i1, &j0, &j1);
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) ++count[std::size_t(j) * nx + i + 1];
    }
    for (std::size_t c = 1; c < count.size(); ++c) count[c] += count[c - 1];
    start = count;
    items.resize(std::size_t(count.back()));
    for (std::size_t q = 0; q < segs.size(); ++q) {
      int i0, i1, j0, j1;
      range(segs[q], &i0, &i1, &j0, &j1);
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) items[std::size_t(count[std::size_t(j) * nx + i]++)] = int(q);
    }
    // Chebyshev distance (in buckets) from each bucket to the nearest non-empty one: the rings of
    // a nearest-point query start there (two chamfer passes, exact for that metric).
    empty.assign(std::size_t(nx) * ny, std::numeric_limits<int>::max() / 2);
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const std::size_t c = std::size_t(j) * nx + i;
        if (start[c + 1] > start[c]) empty[c] = 0;
      }
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        int& e = empty[std::size_t(j) * nx + i];
        for (const auto& [di, dj] : {std::pair{-1, 0}, {-1, -1}, {0, -1}, {1, -1}}) {
          const int a = i + di, b = j + dj;
          if (a >= 0 && b >= 0 && a < nx) e = std::min(e, empty[std::size_t(b) * nx + a] + 1);
        }
      }
    for (int j = ny - 1; j >= 0; --j)
      for (int i = nx - 1; i >= 0; --i) {
        int& e = empty[std::size_t(j) * nx + i];
        for (const auto& [di, dj] : {std::pair{1, 0}, {1, 1}, {0, 1}, {-1, 1}}) {
          const int a = i + di, b = j + dj;
          if (a >= 0 && a < nx && b < ny) e = std::min(e, empty[std::size_t(b) * nx + a] + 1);
        }
      }
  }

  /// Distance from p to the nearest contour point within maxR (that point in *q); +inf if none.
  double nearest(const Vec2& p, double maxR, Vec2* q) const {
    if (segs.empty()) return kInf;
    const int ci = std::clamp(int(std::floor((p.x() - lo.x()) / cell)), 0, nx - 1);
    const int cj = std::clamp(int(std::floor((p.y() - lo.y()) / cell)), 0, ny - 1);
    double best = kInf;
    for (int r = empty[std::size_t(cj) * nx + ci]; r <= nx + ny; ++r) {
      if ((r - 1) * cell > std::min(best, maxR)) break;
      for (int j = cj - r; j <= cj + r; ++j) {
        if (j < 0 || j >= ny) continue;
        const bool edgeRow = j == cj - r || j == cj + r;
        for (int i = ci - r; i <= ci + r; i += edgeRow ? 1 : 2 * std::max(r, 1)) {
          if (i < 0 || i >= nx) continue;
          const std::size_t c = std::size_t(j) * nx + i;
          for (int k = start[c]; k < start[c + 1]; ++k) {
            const auto& sg = segs[std::size_t(items[std::size_t(k)])];
            const Vec2 d = sg[1] - sg[0];
            const double l2 = d.squaredNorm();
            const double t = l2 > 0 ? std::clamp((p - sg[0]).dot(d) / l2, 0.0, 1.0) : 0.0;
            const Vec2 y = sg[0] + t * d;
            const double dist = (y - p).norm();
            if (dist < best) {
              best = dist;
              *q = y;
            }
          }
          if (r == 0) break;
        }
      }
    }
    return best <= maxR ? best : kInf;
  }

  /// Calls f(segment) for every segment whose bucket meets [a, b] (a segment may repeat).
  template <class F>
  void forEach(const Vec2& a, const Vec2& b, F&& f) const {
    if (segs.empty()) return;
    if (b.x() < lo.x() - cell || b.y() < lo.y() - cell) return;
    const int i0 = std::clamp(int(std::floor((a.x() - lo.x()) / cell)), 0, nx - 1);
    const int i1 = std::clamp(int(std::floor((b.x() - lo.x()) / cell)), 0, nx - 1);
    const int j0 = std::clamp(int(std::floor((a.y() - lo.y()) / cell)), 0, ny - 1);
    const int j1 = std::clamp(int(std::floor((b.y() - lo.y()) / cell)), 0, ny - 1);
    if (a.x() > lo.x() + nx * cell || a.y() > lo.y() + ny * cell) return;
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const std::size_t c = std::size_t(j) * nx + i;
        for (int q = start[c]; q < start[c + 1]; ++q) f(segs[std::size_t(items[std::size_t(q)])]);
      }
  }
};

struct PlaneInfo {
  PlaneRow row;
  bool has_sections = false;
  Vec2 lo = Vec2::Zero(), hi = Vec2::Zero();  // bounds of the sections, plane coordinates
  std::vector<std::array<Vec2, 2>> boxes;    // bounds of each section
  SegmentGrid segments;
  const std::vector<Section>* sections = nullptr;
  const SectionDistanceField* field = nullptr;
};

/// Half-plane a*x + b*y + c >= 0 in a plane's coordinates.
struct HalfPlane {
  double a, b, c;
  double at(const Vec2& p) const { return a * p.x() + b * p.y() + c; }
};

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

double pointSegmentDistance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 d = b - a;
  const double l2 = d.squaredNorm();
  const double t = l2 > 0 ? std::clamp((p - a).dot(d) / l2, 0.0, 1.0) : 0.0;
  return (a + t * d - p).norm();
}

/// Point of a plane inside one of its sections: the raster decides away from the contours, the
/// polygons near them.
bool insideSections(const PlaneInfo& P, const Vec2& m) {
  const float f = P.field->sample(m.x(), m.y());
  const double eps = 2.0 * P.field->step;
  if (f < -eps) return true;
  if (f > eps) return false;
  for (const Section& s : *P.sections)
    if (sectionContains(s, m)) return true;
  return false;
}

/// Distance from p (plane coordinates) to the part of P's sections lying in the visible face
/// K = {half-planes} ∩ square(p, rho); +inf when that part is empty. The boundary of
/// (sections ∩ K) consists of contour pieces inside K and pieces of K's edges inside the sections;
/// p lies outside (sections ∩ K), so the nearest point is on one of them.
double visibleSectionDistance(const PlaneInfo& P, const Vec2& p, double rho,
                              const std::vector<HalfPlane>& hp) {
  std::vector<Vec2> poly = {p + Vec2(-rho, -rho), p + Vec2(rho, -rho), p + Vec2(rho, rho),
                            p + Vec2(-rho, rho)};
  std::vector<int> tag = {-1, -1, -1, -1};  // edge i (poly[i] -> poly[i+1]) lies on hp[tag] or the square
  std::vector<Vec2> np;
  std::vector<int> nt;
  for (std::size_t q = 0; q < hp.size() && !poly.empty(); ++q) {
    const HalfPlane& H = hp[q];
    bool allIn = true;
    for (const Vec2& v : poly)
      if (H.at(v) < 0) {
        allIn = false;
        break;
      }
    if (allIn) continue;
    np.clear();
    nt.clear();
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Vec2& A = poly[i];
      const Vec2& B = poly[(i + 1) % poly.size()];
      const double fa = H.at(A), fb = H.at(B);
      const bool ia = fa >= 0, ib = fb >= 0;
      if (ia) {
        np.push_back(A);
        nt.push_back(tag[i]);
        if (!ib) {
          np.push_back(A + (fa / (fa - fb)) * (B - A));
          nt.push_back(int(q));
        }
      } else if (ib) {
        np.push_back(A + (fa / (fa - fb)) * (B - A));
        nt.push_back(tag[i]);
      }
    }
    poly.swap(np);
    tag.swap(nt);
    if (poly.size() < 3) return kInf;
  }
  if (poly.size() < 3) return kInf;
  Vec2 bl = poly[0], bh = poly[0];
  for (const Vec2& v : poly) {
    bl = bl.cwiseMin(v);
    bh = bh.cwiseMax(v);
  }
  const std::size_t m = poly.size();
  double best = kInf;
  // Contour pieces inside K (Liang-Barsky against K's edges; K is counter-clockwise).
  P.segments.forEach(bl, bh, [&](const std::array<Vec2, 2>& s) {
    double t0 = 0, t1 = 1;
    const Vec2 d = s[1] - s[0];
    for (std::size_t i = 0; i < m && t0 <= t1; ++i) {
      const Vec2 e = poly[(i + 1) % m] - poly[i];
      const double c0 = cross2(e, s[0] - poly[i]), cd = cross2(e, d);
      if (cd == 0) {
        if (c0 < 0) t1 = -1;
      } else {
        const double t = -c0 / cd;
        if (cd > 0) t0 = std::max(t0, t);
        else t1 = std::min(t1, t);
      }
    }
    if (t0 <= t1) best = std::min(best, pointSegmentDistance(p, s[0] + t0 * d, s[0] + t1 * d));
  });
  // Pieces of K's edges (traces of other planes) inside the sections.
  std::vector<double> ts;
  for (std::size_t i = 0; i < m; ++i) {
    if (tag[i] < 0) continue;
    const Vec2 A = poly[i], B = poly[(i + 1) % m];
    const Vec2 e = B - A;
    if (pointSegmentDistance(p, A, B) >= std::min(best, rho)) continue;
    ts.assign({0.0, 1.0});
    P.segments.forEach(A.cwiseMin(B), A.cwiseMax(B), [&](const std::array<Vec2, 2>& s) {
      const Vec2 d = s[1] - s[0];
      const double den = cross2(e, d);
      if (den == 0) return;
      const double t = cross2(s[0] - A, d) / den, u = cross2(s[0] - A, e) / den;
      if (t > 0 && t < 1 && u >= 0 && u <= 1) ts.push_back(t);
    });
    std::sort(ts.begin(), ts.end());
    for (std::size_t k = 0; k + 1 < ts.size(); ++k) {
      if (ts[k + 1] - ts[k] <= 1e-12) continue;
      const Vec2 a = A + ts[k] * e, b = A + ts[k + 1] * e;
      if (pointSegmentDistance(p, a, b) >= best) continue;
      if (insideSections(P, 0.5 * (a + b))) best = std::min(best, pointSegmentDistance(p, a, b));
    }
  }
  return best;
}

enum class Verdict { inside, outside, undecided };
struct Decision {
  Verdict verdict = Verdict::undecided;
  float value = 0;
  int section_plane = -1;
  float lift = 0;
  float plane_distance = 0;
  int nearest_plane = -1;
  double suggest_radius = 0;  ///< undecided: a visible section point lies this far (0: unknown)
};

struct Candidate {
  int plane;
  double s, a;  // signed and absolute distance of the voxel to the plane
};
struct Pending {
  int t;        // position in the walk
  double f;     // raster value at the projection (>= band when clamped)
  double lb;    // lower bound of the distance to a visible section point of this plane
  bool visible; // the projection itself is visible
  Vec2 p;
};

struct Scratch {
  std::vector<Candidate> order, pool;
  std::vector<Pending> pend;
  std::vector<HalfPlane> hp;
  std::vector<int> cand, inList;
  std::vector<double> inBound;
  std::vector<std::pair<double, int>> inOrder;
  std::vector<int> todo, next;
  std::int64_t exact = 0;
};

class Evaluator {
 public:
  Evaluator(const std::vector<PlaneInfo>& planes, double slab) : P_(planes), slab_(slab) {}

  /// Within the thickened nearest plane, x is decided by it alone (R' = R there): fills *out and
  /// returns true. `cand` must hold the nearest plane.
  bool decideInSlab(const Vec3& x, const std::vector<int>& cand, Decision* out) const {
    int best = -1;
    double ba = kInf;
    for (const int q : cand) {
      const double a = std::abs(P_[q].row.s(x));
      if (a < ba || (a == ba && q < best)) {
        ba = a;
        best = q;
      }
    }
    if (best < 0 || !(ba < slab_)) return false;
    const PlaneInfo& P = P_[std::size_t(best)];
    const Vec3 d = x - P.row.o;
    const float f = P.field->sample(d.dot(P.row.u), d.dot(P.row.v));
    out->verdict = f < 0 ? Verdict::inside : Verdict::outside;
    out->value = f;
    out->nearest_plane = best;
    out->plane_distance = float(ba);
    out->section_plane = f < 0 ? best : -1;
    out->lift = f < 0 ? float(ba) : 0.f;
    return true;
  }

  /// Decides x using the planes `cand` (which hold every plane within R of x). `isMax`: cand
  /// holds every plane.
  Decision decide(const Vec3& x, const std::vector<int>& cand, const std::vector<int>& inList,
                  const std::vector<double>& inBound, double R, bool isMax, Scratch& w) const {
    Decision out;
    // Distances to the candidate planes; the nearest one first (ties: lower index).
    auto& order = w.order;
    auto& pool = w.pool;
    order.clear();
    pool.clear();
    std::size_t nearest = 0;
    for (const int q : cand) {
      const double s = P_[q].row.s(x), a = std::abs(s);
      if (!(a <= R || isMax)) continue;
      pool.push_back({q, s, a});
      const Candidate& n = pool[nearest];
      if (a < n.a || (a == n.a && q < n.plane)) nearest = pool.size() - 1;
    }
    if (pool.empty()) return out;
    const Candidate c0 = pool[nearest];
    const PlaneInfo& P0 = P_[c0.plane];
    out.nearest_plane = c0.plane;
    out.plane_distance = float(c0.a);
    const Vec3 d0 = x - P0.row.o;
    const float f0 = P0.field->sample(d0.dot(P0.row.u), d0.dot(P0.row.v));
    if (c0.a < slab_) {  // thickened plane: R' = R here
      out.verdict = f0 < 0 ? Verdict::inside : Verdict::outside;
      out.value = f0;
      if (f0 < 0) {
        out.section_plane = c0.plane;
        out.lift = float(c0.a);
      }
      return out;
    }
    // Only planes whose projection of x falls in a section's bounding box can give x to R'.
    // inList comes sorted by decreasing upper bound `inBound` of the distance (over the block):
    // once that bound falls below the best found, no later plane can raise it.
    // Point queries pass every plane and no bounds: `hopeful` is then left unknown (+inf), which
    // only delays the conclusion "outside" to the end of the walk.
    double hopeful = inBound.empty() && !inList.empty() ? kInf : -1;
    for (std::size_t qi = 0; qi < inList.size() && hopeful < kInf; ++qi) {
      if (!inBound.empty() && inBound[qi] <= hopeful) break;
      const int q = inList[qi];
      const PlaneInfo& I = P_[q];
      const double a = std::abs(I.row.s(x));
      if (a <= hopeful) continue;
      const Vec3 dx = x - I.row.o;
      const Vec2 p(dx.dot(I.row.u), dx.dot(I.row.v));
      if (p.x() < I.lo.x() || p.x() > I.hi.x() || p.y() < I.lo.y() || p.y() > I.hi.y()) continue;
      for (const auto& b : I.boxes)
        if (p.x() >= b[0].x() && p.x() <= b[1].x() && p.y() >= b[0].y() && p.y() <= b[1].y()) {
          hopeful = a;
          break;
        }
    }
    if (hopeful < 0) return outsideWith(out, std::max(double(f0), 0.0));
    // Planes in order of distance, popped lazily from a heap: most voxels stop after a few.
    const auto farther = [](const Candidate& l, const Candidate& r) {
      return l.a > r.a || (l.a == r.a && l.plane > r.plane);
    };
    std::make_heap(pool.begin(), pool.end(), farther);
    const auto popNext = [&]() {
      if (pool.empty()) return false;
      std::pop_heap(pool.begin(), pool.end(), farther);
      order.push_back(pool.back());
      pool.pop_back();
      return true;
    };
    popNext();  // the nearest plane, c0
    // Walk the planes by distance: the first visible in-section projection gives H_in. A visible
    // section point found on the way (the exact nearest contour point to a projection, checked
    // for visibility) bounds d(x, S_C) from above by U: no plane farther than U can give x to R'.
    auto& pend = w.pend;
    pend.clear();
    int inIdx = -1;
    float inValue = 0;
    double U = kInf;
    float uValue = 0;
    // Tried on the first few planes whose sections may lie nearer than the current U.
    int tries = 0, farTries = 0;
    // near: the projection lies within the raster's band of a contour (a short query); far: any
    // other case (one query per voxel: in small cells such points are mostly hidden).
    const auto tryBound = [&](std::size_t t, const Vec2& p, bool near) {
      if (near ? tries >= 3 : farTries >= 1) return;
      ++(near ? tries : farTries);
      const double H = order[t].a;
      // A bound beyond `hopeful` is useless: the walk concludes there anyway.
      const double cap = std::min(U, hopeful);
      const double maxR = std::sqrt(std::max(0.0, cap * cap - H * H));
      const PlaneInfo& P = P_[order[t].plane];
      Vec2 q;
      const double d = P.segments.nearest(p, maxR, &q);
      if (!(d < kInf)) return;
      const double dist = std::hypot(H, d);
      const Vec3 qw = P.row.o + q.x() * P.row.u + q.y() * P.row.v;
      // Within R the candidates hold every possible occluder; beyond it, all planes are checked.
      const bool vis = (isMax || dist <= R) ? pointVisible(order, w.pool, t, qw, dist)
                                            : visibleAmongAll(x, order[t].plane, qw, dist);
      if (vis) {
        U = dist;
        uValue = float(d);
      }
    };
    bool exhausted = false;  // every plane that could give x to R' was walked
    for (std::size_t t = 0; t < order.size() || popNext(); ++t) {
      const double H = order[t].a;
      if (H >= U) break;
      if (H > hopeful) {
        exhausted = true;
        break;
      }
      const PlaneInfo& P = P_[order[t].plane];
      if (!P.has_sections) continue;
      const Vec3 dx = x - P.row.o;
      const Vec2 p(dx.dot(P.row.u), dx.dot(P.row.v));
      double boxd = kInf;  // in-plane distance to the nearest section's bounding box
      for (const auto& b : P.boxes)
        boxd = std::min(boxd, (p - p.cwiseMax(b[0]).cwiseMin(b[1])).norm());
      if (boxd > 0) {  // not an in-section projection; a lower bound is enough for now
        if (std::hypot(H, boxd) < U) tryBound(t, p, false);
        pend.push_back({int(t), std::nan(""), std::sqrt(H * H + boxd * boxd), false, p});
        continue;
      }
      const double f = P.field->sample(p.x(), p.y());
      const bool vis = visibleFrom(order, t, t);
      if (vis && f < 0) {
        inIdx = int(t);
        inValue = float(f);
        break;
      }
      const double lb = std::sqrt(H * H + std::max(f, 0.0) * std::max(f, 0.0));
      if (f > 0 && lb < U) tryBound(t, p, f < P.field->band);
      pend.push_back({int(t), f, lb, vis, p});
    }
    if (inIdx < 0) {
      exhausted = exhausted || hopeful <= R;  // every plane within R was walked
      if ((U < kInf && (U <= R || isMax)) || isMax || exhausted)
        return outsideWith(out, U < kInf ? double(uValue) : std::max(double(f0), 0.0));
      // Every plane that could still matter lies within min(U, hopeful) (`hopeful` counts every
      // plane, not only those within R): the next search radius needs no more.
      out.suggest_radius = std::min(U, hopeful);
      return out;  // undecided: the search radius must grow
    }
    const double T = order[std::size_t(inIdx)].a;
    const double v = anyHit(order, std::size_t(inIdx), T, w);
    if (v < kInf) return outsideWith(out, v);
    out.verdict = Verdict::inside;
    out.value = inValue;
    out.section_plane = order[std::size_t(inIdx)].plane;
    out.lift = float(T);
    return out;
  }

 private:
  static Decision outsideWith(Decision d, double v) {
    d.verdict = Verdict::outside;
    d.value = float(std::isfinite(v) ? std::max(v, 1e-6) : 1e30);
    return d;
  }

  /// The point sw of plane `own`, at distance dist from x, is hidden by no plane at all.
  bool visibleAmongAll(const Vec3& x, int own, const Vec3& sw, double dist) const {
    for (std::size_t q = 0; q < P_.size(); ++q) {
      if (int(q) == own) continue;
      const double sx = P_[q].row.s(x);
      if (sx == 0 || std::abs(sx) >= dist) continue;
      const double ss = P_[q].row.s(sw);
      if (sx > 0 ? ss < 0 : ss > 0) return false;
    }
    return true;
  }

  /// The projection of x on order[t]'s plane is hidden by none of order[0..end) (except t).
  bool visibleFrom(const std::vector<Candidate>& order, std::size_t t, std::size_t end) const {
    const PlaneRow& P = P_[order[t].plane].row;
    const double sP = order[t].s;
    for (std::size_t k = 0; k < end; ++k) {
      if (k == t || order[k].s == 0) continue;
      const double qp = order[k].s - sP * P_[order[k].plane].row.n.dot(P.n);
      if ((order[k].s > 0) ? qp < 0 : qp > 0) return false;
    }
    return true;
  }

  /// In-plane distance from p to the contour point of order[t]'s plane nearest to it, when that
  /// point lies within maxR and is visible from x; +inf otherwise. Exact (from the polygons).
  double exactNearestVisible(const std::vector<Candidate>& order,
                             const std::vector<Candidate>& pool, std::size_t t, const Vec2& p,
                             double maxR) const {
    const PlaneInfo& P = P_[order[t].plane];
    Vec2 q;
    const double d = P.segments.nearest(p, maxR, &q);
    if (!(d < kInf)) return kInf;
    const Vec3 qw = P.row.o + q.x() * P.row.u + q.y() * P.row.v;
    return pointVisible(order, pool, t, qw, std::hypot(order[t].a, d)) ? d : kInf;
  }

  /// The point sw of order[t]'s plane, at distance dist from x, is visible from x: no plane
  /// nearer than dist separates them.
  bool pointVisible(const std::vector<Candidate>& order, const std::vector<Candidate>& pool,
                    std::size_t t, const Vec3& sw, double dist) const {
    const auto hides = [&](const Candidate& q) {
      if (q.s == 0 || q.a >= dist) return false;
      const double qs = P_[q.plane].row.s(sw);
      return (q.s > 0) ? qs < 0 : qs > 0;
    };
    for (std::size_t k = 0; k < order.size(); ++k)
      if (k != t && hides(order[k])) return false;
    for (const Candidate& q : pool)
      if (hides(q)) return false;
    return true;
  }

  /// Smallest in-plane distance of a visible section point nearer to x than T among the pending
  /// planes, considering the planes order[0..end) as the possible occluders (every plane nearer
  /// than T); +inf when there is none.
  double anyHit(const std::vector<Candidate>& order, std::size_t end, double T, Scratch& w) const {
    for (Pending& E : w.pend) {
      if (std::size_t(E.t) >= end || E.lb >= T) continue;
      const Candidate& c = order[std::size_t(E.t)];
      const PlaneInfo& P = P_[c.plane];
      if (std::isnan(E.f)) {  // skipped by the bounding boxes during the walk
        E.f = P.field->sample(E.p.x(), E.p.y());
        E.visible = visibleFrom(order, std::size_t(E.t), std::size_t(E.t));
        E.lb = std::max(E.lb, std::sqrt(c.a * c.a + std::max(E.f, 0.0) * std::max(E.f, 0.0)));
        if (E.lb >= T) continue;
      }
      const double rho = std::sqrt(std::max(0.0, T * T - c.a * c.a));
      bool free = E.visible;
      double lineLb = 0;  // in-plane distance from p to the nearest hiding trace
      for (std::size_t k = 0; k < end; ++k) {
        if (k == std::size_t(E.t) || order[k].s == 0) continue;
        const Vec3& nq = P_[order[k].plane].row.n;
        const double cosq = nq.dot(P.row.n);
        const double qp = (order[k].s - c.s * cosq) * (order[k].s > 0 ? 1 : -1);
        const double sinq = std::sqrt(std::max(0.0, 1 - cosq * cosq));
        if (qp < rho * sinq) free = false;
        if (qp < 0) lineLb = std::max(lineLb, sinq > 0 ? -qp / sinq : kInf);
      }
      if (lineLb >= rho) continue;  // p hidden behind a trace farther than rho
      double d = kInf;
      if (free) {  // nothing hides the disk of radius rho: the nearest contour point decides
        Vec2 q;
        d = P.segments.nearest(E.p, rho, &q);
      } else if (E.visible && E.f > 0 &&
                 (d = exactNearestVisible(order, w.pool, std::size_t(E.t), E.p, rho)) < kInf) {
        // the nearest contour point is visible: it is the nearest visible section point
      } else {
        ++w.exact;
        w.hp.clear();
        bool hidden = false;  // a plane parallel to P hides all of it
        for (std::size_t k = 0; k < end; ++k) {
          if (k == std::size_t(E.t) || order[k].s == 0) continue;
          const PlaneRow& Q = P_[order[k].plane].row;
          const double sg = order[k].s > 0 ? 1 : -1;
          const HalfPlane H{sg * Q.n.dot(P.row.u), sg * Q.n.dot(P.row.v),
                            sg * (Q.n.dot(P.row.o) - Q.d)};
          if (H.a == 0 && H.b == 0) hidden = hidden || H.c < 0;
          else w.hp.push_back(H);
        }
        if (hidden) continue;
        d = visibleSectionDistance(P, E.p, rho, w.hp);
      }
      if (d < rho) return d;
    }
    return kInf;
  }

  const std::vector<PlaneInfo>& P_;
  double slab_;
};

std::vector<PlaneInfo> planeInfo(const std::vector<CuttingPlane>& planes,
                                 const std::vector<SectionDistanceField>& fields) {
  std::vector<PlaneInfo> info(planes.size());
  tbb::parallel_for(std::size_t(0), planes.size(), [&](std::size_t i) {
    const Plane& p = planes[i].plane;
    PlaneInfo& I = info[i];
    I.row.n = p.normal.normalized();
    I.row.u = p.u;
    I.row.v = p.v;
    I.row.o = p.origin;
    I.row.an = I.row.n.cwiseAbs();
    I.row.d = I.row.n.dot(p.origin);
    I.sections = &planes[i].sections;
    I.field = &fields[i];
    I.has_sections = !planes[i].sections.empty();
    if (I.has_sections) {
      I.segments.build(planes[i].sections);
      I.lo = I.hi = planes[i].sections[0].outer[0];
      for (const Section& s : planes[i].sections) {
        const Eigen::AlignedBox2d b = ringBounds(s.outer);
        I.boxes.push_back({b.min(), b.max()});
        I.lo = I.lo.cwiseMin(b.min());
        I.hi = I.hi.cwiseMax(b.max());
      }
    }
  });
  return info;
}

}  // namespace

void forEachSectionVoronoiBlock(const std::vector<CuttingPlane>& planes,
                                const std::vector<SectionDistanceField>& fields, const GridSpec& grid,
                                const SectionVoronoiParams& params,
                                const std::function<void(std::int64_t, const SectionVoronoiBlock&)>& visitBlock,
                                const std::function<void(std::int64_t, std::int64_t)>& progress,
                                SectionVoronoiStatistics* statistics) {
  if (planes.empty()) throw std::invalid_argument("method 2: no cutting plane");
  if (fields.size() != planes.size())
    throw std::invalid_argument("method 2: one distance raster per plane is required");
  if (!(grid.voxel > 0)) throw std::invalid_argument("method 2: voxel size must be positive");
  if (!(params.slab_mm >= 0)) throw std::invalid_argument("method 2: slab must be >= 0");

  const std::vector<PlaneInfo> info = planeInfo(planes, fields);
  float band = 0;
  for (const auto& f : fields) band = std::max(band, f.band);

  const Evaluator ev(info, params.slab_mm);
  // Blocks of 4³ voxels share their candidate planes and search radius; the output goes by blocks
  // of 8³ (block_grid.h), each the union of eight of them.
  constexpr int kBlock = 4, kOut = BlockGrid<float>::kSide;
  const auto& D = grid.dims;
  const std::int64_t bx = (D[0] + kOut - 1) / kOut, by = (D[1] + kOut - 1) / kOut, bz = (D[2] + kOut - 1) / kOut;
  const std::int64_t blocks = bx * by * bz;
  const double h = grid.voxel;
  const Vec3 gridExt = h * Vec3(D[0], D[1], D[2]);
  const double rMax = gridExt.norm() + 4 * h;
  std::atomic<std::int64_t> exact{0}, restarts{0};

  struct Work {
    Scratch w;
    SectionVoronoiBlock out;
  };
  const auto doBlock = [&](int i0, int j0, int k0, Work& work) {
    Scratch& w = work.w;
    SectionVoronoiBlock& out = work.out;
    const int i1 = std::min(D[0], i0 + kBlock), j1 = std::min(D[1], j0 + kBlock),
              k1 = std::min(D[2], k0 + kBlock);
    if (i0 >= i1 || j0 >= j1 || k0 >= k1) return;
    const Vec3 lo = grid.centre(i0, j0, k0), hi = grid.centre(i1 - 1, j1 - 1, k1 - 1);
    const Vec3 c = 0.5 * (lo + hi), e = 0.5 * (hi - lo);
    double minHi = kInf;
    for (const PlaneInfo& I : info) minHi = std::min(minHi, std::abs(I.row.s(c)) + I.row.an.dot(e));
    const auto candidates = [&](double R, bool isMax) {
      w.cand.clear();
      for (std::size_t q = 0; q < info.size(); ++q) {
        const double lb = std::abs(info[q].row.s(c)) - info[q].row.an.dot(e);
        if (isMax || lb <= R) w.cand.push_back(int(q));
      }
    };
    const auto offsetOf = [](int i, int j, int k) { return BlockGrid<float>::offset(i, j, k); };
    const auto store = [&](int o, const Decision& dcs) {
      out.value[std::size_t(o)] = std::clamp(dcs.value, -band, band);
      out.plane_distance[std::size_t(o)] = dcs.plane_distance;
      out.nearest_plane[std::size_t(o)] = dcs.nearest_plane;
      out.section_plane[std::size_t(o)] = dcs.section_plane;
      out.lift_height[std::size_t(o)] = dcs.lift;
    };
    // Voxels within the thickened nearest plane first (all of them in dense sweeps). The voxels
    // left are kept by their place in the 8³ block (and their coordinates recomputed).
    double R = 2.0 * minHi + 2 * h;
    candidates(R, R >= rMax);
    w.todo.clear();
    for (int k = k0; k < k1; ++k)
      for (int j = j0; j < j1; ++j)
        for (int i = i0; i < i1; ++i) {
          Decision dcs;
          if (ev.decideInSlab(grid.centre(i, j, k), w.cand, &dcs)) store(offsetOf(i, j, k), dcs);
          else w.todo.push_back((i - i0) + kBlock * ((j - j0) + kBlock * (k - k0)));
        }
    if (w.todo.empty()) return;
    // Planes whose sections the block's projection can reach: without any, no voxel of the
    // block has an in-section projection and the whole block lies outside R' (and R).
    w.inList.clear();
    for (std::size_t q = 0; q < info.size(); ++q) {
      const PlaneInfo& I = info[q];
      if (!I.has_sections) continue;
      const Vec3 dc = c - I.row.o;
      const Vec2 pa(dc.dot(I.row.u), dc.dot(I.row.v));
      const Vec2 pr(I.row.u.cwiseAbs().dot(e), I.row.v.cwiseAbs().dot(e));
      const auto meets = [&](const Vec2& blo, const Vec2& bhi) {
        return (pa + pr).x() >= blo.x() && (pa - pr).x() <= bhi.x() && (pa + pr).y() >= blo.y() &&
               (pa - pr).y() <= bhi.y();
      };
      if (!meets(I.lo, I.hi)) continue;
      for (const auto& bb : I.boxes)
        if (meets(bb[0], bb[1])) {
          w.inList.push_back(int(q));
          break;
        }
    }
    {  // by decreasing upper bound of the distance over the block
      w.inOrder.clear();
      for (const int q : w.inList)
        w.inOrder.push_back({std::abs(info[std::size_t(q)].row.s(c)) + info[std::size_t(q)].row.an.dot(e), q});
      std::sort(w.inOrder.begin(), w.inOrder.end(), [](const auto& l, const auto& r) {
        return l.first > r.first || (l.first == r.first && l.second < r.second);
      });
      w.inList.clear();
      w.inBound.clear();
      for (const auto& [bnd, q] : w.inOrder) {
        w.inList.push_back(q);
        w.inBound.push_back(bnd);
      }
    }
    const auto voxelOf = [&](int t) {
      return std::array<int, 3>{i0 + t % kBlock, j0 + (t / kBlock) % kBlock, k0 + t / (kBlock * kBlock)};
    };
    if (w.inList.empty()) {
      for (const int t : w.todo) {
        const auto v = voxelOf(t);  // outside every section's reach: +band
        out.value[std::size_t(offsetOf(v[0], v[1], v[2]))] = band;
        out.plane_distance[std::size_t(offsetOf(v[0], v[1], v[2]))] = 0.f;
        out.nearest_plane[std::size_t(offsetOf(v[0], v[1], v[2]))] = -1;
        out.section_plane[std::size_t(offsetOf(v[0], v[1], v[2]))] = -1;
        out.lift_height[std::size_t(offsetOf(v[0], v[1], v[2]))] = 0.f;
      }
      return;
    }
    bool first = true;
    while (!w.todo.empty()) {
      const bool isMax = R >= rMax;
      if (!first) candidates(R, isMax);
      first = false;
      w.next.clear();
      double suggest = 0;
      for (const int t : w.todo) {
        const auto v = voxelOf(t);
        const Decision dcs = ev.decide(grid.centre(v[0], v[1], v[2]), w.cand, w.inList, w.inBound, R, isMax, w);
        if (dcs.verdict == Verdict::undecided) {
          suggest = std::max(suggest, dcs.suggest_radius);
          w.next.push_back(t);
          continue;
        }
        store(offsetOf(v[0], v[1], v[2]), dcs);
      }
      restarts += std::int64_t(w.next.size());
      w.todo.swap(w.next);
      // Grow to the farthest visible section point found by an undecided voxel (every plane that
      // could still matter to it lies nearer), at least doubling.
      R = std::max(2 * R, suggest * (1 + 1e-9) + 2 * h);
    }
  };
  const std::int64_t chunk = std::max<std::int64_t>(16, blocks / 32);
  for (std::int64_t first = 0; first < blocks; first += chunk) {
    const std::int64_t last = std::min(blocks, first + chunk);
    tbb::parallel_for(tbb::blocked_range<std::int64_t>(first, last, 1), [&](const tbb::blocked_range<std::int64_t>& r) {
      Work work;
      for (std::int64_t b = r.begin(); b != r.end(); ++b) {
        const int ib = int(b % bx) * kOut, jb = int((b / bx) % by) * kOut, kb = int(b / (bx * by)) * kOut;
        for (int dz = 0; dz < kOut; dz += kBlock)
          for (int dy = 0; dy < kOut; dy += kBlock)
            for (int dx = 0; dx < kOut; dx += kBlock) doBlock(ib + dx, jb + dy, kb + dz, work);
        // Voxels beyond the grid repeat the block's first.
        SectionVoronoiBlock& v = work.out;
        forEachBeyondGrid(grid, {ib, jb, kb}, [&](int o) {
          const std::size_t q = std::size_t(o);
          v.value[q] = v.value[0];
          v.plane_distance[q] = v.plane_distance[0];
          v.nearest_plane[q] = v.nearest_plane[0];
          v.section_plane[q] = v.section_plane[0];
          v.lift_height[q] = v.lift_height[0];
        });
        visitBlock(b, v);
      }
      exact += work.w.exact;
    });
    if (progress) progress(last, blocks);
  }
  if (statistics) {
    statistics->exact_face_tests = exact;
    statistics->search_restarts = restarts;
  }
}

SectionVoronoiField sectionVoronoiReconstruction(const std::vector<CuttingPlane>& planes,
                                                 const std::vector<SectionDistanceField>& fields,
                                                 const GridSpec& grid,
                                                 const SectionVoronoiParams& params,
                                                 const std::function<void(std::int64_t, std::int64_t)>& progress) {
  SectionVoronoiField out;
  out.value.grid = grid;
  const std::size_t n = std::size_t(grid.count());
  out.value.values.assign(n, 0.f);
  out.plane_distance.assign(n, 0.f);
  out.nearest_plane.assign(n, -1);
  out.section_plane.assign(n, -1);
  out.lift_height.assign(n, 0.f);
  const BlockGrid<float> numbering(grid, 0.f);
  SectionVoronoiStatistics statistics;
  forEachSectionVoronoiBlock(planes, fields, grid, params, [&](std::int64_t b, const SectionVoronoiBlock& v) {
    forEachVoxelOfBlock(grid, numbering.blockOrigin(b), [&](int i, int j, int k, int o) {
      const std::size_t idx = std::size_t(grid.index(i, j, k)), q = std::size_t(o);
      out.value.values[idx] = v.value[q];
      out.plane_distance[idx] = v.plane_distance[q];
      out.nearest_plane[idx] = v.nearest_plane[q];
      out.section_plane[idx] = v.section_plane[q];
      out.lift_height[idx] = v.lift_height[q];
    });
  }, progress, &statistics);
  out.exact_face_tests = statistics.exact_face_tests;
  out.search_restarts = statistics.search_restarts;
  return out;
}

struct SectionVoronoiPoints::Impl {
  std::vector<PlaneInfo> info;
  std::vector<int> all, withSections;
  Evaluator ev;
  Impl(std::vector<PlaneInfo> i, double slab) : info(std::move(i)), ev(info, slab) {}
};

SectionVoronoiPoints::SectionVoronoiPoints(const std::vector<CuttingPlane>& planes,
                                           const std::vector<SectionDistanceField>& fields,
                                           const SectionVoronoiParams& params)
    : impl_(new Impl(planeInfo(planes, fields), params.slab_mm)) {
  for (std::size_t q = 0; q < impl_->info.size(); ++q) {
    impl_->all.push_back(int(q));
    if (impl_->info[q].has_sections) impl_->withSections.push_back(int(q));
  }
}

SectionVoronoiPoints::~SectionVoronoiPoints() { delete impl_; }

SectionVoronoiPoints::Answer SectionVoronoiPoints::at(const Vec3& x) const {
  thread_local Scratch w;
  thread_local std::vector<int> cand;
  // First within a few times the nearest plane's distance (most points are decided there), then
  // with every plane.
  double d0 = kInf;
  for (const PlaneInfo& I : impl_->info) d0 = std::min(d0, std::abs(I.row.s(x)));
  const double R = 4 * d0 + 1e-6;
  cand.clear();
  for (std::size_t q = 0; q < impl_->info.size(); ++q)
    if (std::abs(impl_->info[q].row.s(x)) <= R) cand.push_back(int(q));
  Decision d = impl_->ev.decide(x, cand, impl_->withSections, {}, R, false, w);
  if (d.verdict == Verdict::undecided)
    d = impl_->ev.decide(x, impl_->all, impl_->withSections, {}, kInf, true, w);
  Answer a;
  a.inside = d.verdict == Verdict::inside;
  a.section_plane = d.section_plane;
  return a;
}

}  // namespace xsect

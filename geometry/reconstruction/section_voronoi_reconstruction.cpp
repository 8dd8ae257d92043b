// Method 2 on a voxel grid: nearest visible section by a walk over the facets of each voxel's cell
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

#include "geometry/arrangement/cell_facets.h"
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
    // How far p lies beyond its bucket (ci, cj) along each axis (0 within it: p beyond the grid
    // is clamped to a bucket of its border). A bucket of ring r is r buckets away along one axis,
    // so no point of ring r is nearer than hypot((r - 1) cell + min(ex, ey), max(ex, ey)). The
    // queries from beyond the sections' bounds (method 2's far bounds) used to scan every ring to
    // the grid's end by the weaker bound (r - 1) cell: 34% of a sparse run's time.
    const double bx = lo.x() + ci * cell, by = lo.y() + cj * cell;
    const double ex = std::max({0.0, bx - p.x(), p.x() - (bx + cell)});
    const double ey = std::max({0.0, by - p.y(), p.y() - (by + cell)});
    const double eLo = std::min(ex, ey), eHi = std::max(ex, ey);
    double best = kInf;
    for (int r = empty[std::size_t(cj) * nx + ci]; r <= nx + ny; ++r) {
      const double ring = std::max(0, r - 1) * cell + eLo;
      if (ring * ring + eHi * eHi > std::min(best, maxR) * std::min(best, maxR)) break;
      for (int j = cj - r; j <= cj + r; ++j) {
        if (j < 0 || j >= ny) continue;
        const bool edgeRow = j == cj - r || j == cj + r;
        for (int i = ci - r; i <= ci + r; i += edgeRow ? 1 : 2 * std::max(r, 1)) {
          if (i < 0 || i >= nx) continue;
          // No segment of a bucket farther than the best found can be nearer (the same result:
          // only strictly nearer segments replace the best).
          const double qx = std::max({0.0, lo.x() + i * cell - p.x(), p.x() - (lo.x() + (i + 1) * cell)});
          const double qy = std::max({0.0, lo.y() + j * cell - p.y(), p.y() - (lo.y() + (j + 1) * cell)});
          if (qx * qx + qy * qy > best * best) {
            if (r == 0) break;
            continue;
          }
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
  /// Plane point p lies in the bounding box of one of the sections (closed boxes).
  bool inSectionBox(const Vec2& p) const {
    if (p.x() < lo.x() || p.x() > hi.x() || p.y() < lo.y() || p.y() > hi.y()) return false;
    for (const auto& b : boxes)
      if (p.x() >= b[0].x() && p.x() <= b[1].x() && p.y() >= b[0].y() && p.y() <= b[1].y()) return true;
    return false;
  }
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

enum class Verdict { inside, outside };
struct Decision {
  Verdict verdict = Verdict::outside;
  float value = 0;
  int section_plane = -1;
  float lift = 0;
  float plane_distance = 0;
  int nearest_plane = -1;
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
  std::vector<int> cand, facets, inList;
  std::int64_t exact = 0;
};

class Evaluator {
 public:
  Evaluator(const std::vector<PlaneInfo>& planes, double slab) : P_(planes), slab_(slab) {}

  /// The nearest of the planes `cand` to x (ties: the lower index); -1 when cand is empty.
  int nearestPlane(const Vec3& x, const std::vector<int>& cand) const {
    int best = -1;
    double ba = kInf;
    for (const int q : cand) {
      const double a = std::abs(P_[q].row.s(x));
      if (a < ba || (a == ba && q < best)) {
        ba = a;
        best = q;
      }
    }
    return best;
  }

  /// Decides x from its nearest plane alone where that suffices: fills *out and returns true.
  /// Within the thickened nearest plane R' = R. Elsewhere, a projection on the nearest plane that
  /// lies in a section is visible (a plane hiding it would be nearer) and no section point is
  /// nearer than that plane, so x is in the lift of that section (exactly as decide() finds it).
  bool decideByNearest(const Vec3& x, int nearest, Decision* out) const {
    if (nearest < 0) return false;
    const PlaneInfo& P = P_[std::size_t(nearest)];
    const double a = std::abs(P.row.s(x));
    const Vec3 d = x - P.row.o;
    const Vec2 p(d.dot(P.row.u), d.dot(P.row.v));
    const float f = P.field->sample(p.x(), p.y());
    if (!(a < slab_)) {
      if (!(f < 0) || !P.has_sections) return false;
      if (!P.inSectionBox(p)) return false;
    }
    out->verdict = f < 0 ? Verdict::inside : Verdict::outside;
    out->value = f;
    out->nearest_plane = nearest;
    out->plane_distance = float(a);
    out->section_plane = f < 0 ? nearest : -1;
    out->lift = f < 0 ? float(a) : 0.f;
    return true;
  }

  /// Whether no plane of `inList` projects x into one of its sections' bounding boxes: then no
  /// projection of x lies in a section and x is not in R' (filled into *out, with the value of the
  /// nearest plane's raster, clamped at 0, as decide() gives it).
  bool outsideEveryBox(const Vec3& x, const std::vector<int>& inList, int nearest, Decision* out) const {
    for (const int q : inList) {
      const PlaneInfo& I = P_[std::size_t(q)];
      const Vec3 dx = x - I.row.o;
      if (I.inSectionBox(Vec2(dx.dot(I.row.u), dx.dot(I.row.v)))) return false;
    }
    const PlaneInfo& P = P_[std::size_t(nearest)];
    const Vec3 d = x - P.row.o;
    *out = outsideWith(Decision{}, std::max(double(P.field->sample(d.dot(P.row.u), d.dot(P.row.v))), 0.0));
    out->nearest_plane = nearest;
    out->plane_distance = float(std::abs(P.row.s(x)));
    return true;
  }

  /// What walking the candidate planes by distance found (decide()).
  struct PlaneWalk {
    int in_index = -1;  ///< in w.order: the first plane with a visible in-section projection; -1: none
    float in_value = 0;  ///< its raster's value there (< 0)
    double U = kInf;     ///< a visible section point's distance, an upper bound of d(x, S_C), mm
    float u_value = 0;   ///< its in-plane distance to the contour, mm
  };

  /// Walks the planes of w.pool (candidates, the nearest c0 at w.pool's front once popped) by
  /// distance: the first visible in-section projection gives H_in. A visible section point found
  /// on the way (the exact nearest contour point to a projection, checked for visibility) bounds
  /// d(x, S_C) from above by U: no plane farther than U can give x to R'. Planes are popped lazily
  /// from a heap (most voxels stop after a few); those walked past are left in w.pend.
  PlaneWalk walkPlanes(const Vec3& x, double cellRadius, Scratch& w) const {
    auto& order = w.order;
    auto& pool = w.pool;
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
    auto& pend = w.pend;
    pend.clear();
    PlaneWalk walk;
    int& inIdx = walk.in_index;
    float& inValue = walk.in_value;
    double& U = walk.U;
    float& uValue = walk.u_value;
    // Tried on the first few planes whose sections may lie nearer than the current U.
    int tries = 0, farTries = 0;
    // near: the projection lies within the raster's band of a contour (a short query); far: any
    // other case (one query per voxel: in small cells such points are mostly hidden).
    const auto tryBound = [&](std::size_t t, const Vec2& p, bool near) {
      if (near ? tries >= 3 : farTries >= 1) return;
      ++(near ? tries : farTries);
      const double H = order[t].a;
      // A section point beyond the cell's radius is not in the cell, so not visible.
      const double cap = std::min(U, cellRadius);
      const double maxR = std::sqrt(std::max(0.0, cap * cap - H * H));
      const PlaneInfo& P = P_[order[t].plane];
      Vec2 q;
      const double d = P.segments.nearest(p, maxR, &q);
      if (!(d < kInf)) return;
      const double dist = std::hypot(H, d);
      const Vec3 qw = P.row.o + q.x() * P.row.u + q.y() * P.row.v;
      if (pointVisible(order, w.pool, t, qw, dist)) {
        U = dist;
        uValue = float(d);
      }
    };
    for (std::size_t t = 0; t < order.size() || popNext(); ++t) {
      const double H = order[t].a;
      if (H >= U) break;
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
    return walk;
  }

  /// Decides x from the planes `cand`: the facets of x's cell of the arrangement (every plane that
  /// can hide a section point from x or give x a visible projection) and x's nearest plane.
  /// `inList`: those of them with sections; `cellRadius`: no point of the cell lies farther from x
  /// (mm), so no visible section point does either.
  Decision decide(const Vec3& x, const std::vector<int>& cand, const std::vector<int>& inList,
                  double cellRadius, Scratch& w) const {
    Decision out;
    // Distances to the candidate planes; the nearest one first (ties: lower index).
    auto& order = w.order;
    auto& pool = w.pool;
    order.clear();
    pool.clear();
    std::size_t nearest = 0;
    for (const int q : cand) {
      const double s = P_[q].row.s(x), a = std::abs(s);
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
    // No facet with sections: S_C is empty and so is R' in this cell.
    if (inList.empty()) return outsideWith(out, std::max(double(f0), 0.0));
    const PlaneWalk walk = walkPlanes(x, cellRadius, w);
    const int inIdx = walk.in_index;
    // Every facet nearer than U walked without a visible in-section projection: x is not in R'.
    if (inIdx < 0) return outsideWith(out, walk.U < kInf ? double(walk.u_value) : std::max(double(f0), 0.0));
    const double T = order[std::size_t(inIdx)].a;
    const double v = anyHit(order, std::size_t(inIdx), T, w);
    if (v < kInf) return outsideWith(out, v);
    out.verdict = Verdict::inside;
    out.value = walk.in_value;
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

/// What every cell of the arrangement is clipped from: the planes as normals and offsets, and a
/// box holding the grid and every section (so that the part of a cell cut off by the box holds no
/// section point, and visibility within the box is visibility in the cell).
struct CellGeometry {
  std::vector<Vec3> normals;
  std::vector<double> offsets;
  std::vector<std::uint8_t> has_sections;
  Vec3 lo, hi;
  double pad = 0;
  double tolerance = 0;
  /// The box [lo, hi] (may be empty: lo > hi) grown to hold every section, padded by `pad` mm.
  CellGeometry(const std::vector<PlaneInfo>& info, const Vec3& boxLo, const Vec3& boxHi, double pad_mm)
      : lo(boxLo), hi(boxHi), pad(pad_mm) {
    const Vec3 padding = Vec3::Constant(pad);
    for (const PlaneInfo& I : info) {
      normals.push_back(I.row.n);
      offsets.push_back(I.row.d);
      has_sections.push_back(I.has_sections);
      for (const Section& sc : *I.sections)
        for (const Vec2& p : sc.outer) {
          const Vec3 w = I.row.o + p.x() * I.row.u + p.y() * I.row.v;
          lo = lo.cwiseMin(w - padding);
          hi = hi.cwiseMax(w + padding);
        }
    }
    // Far below a voxel and far above the rounding of coordinates of this size.
    tolerance = 1e-9 * (hi - lo).norm();
  }
};

/// Every plane of g by increasing lower bound of its distance to the box [c - e, c + e] (e = 0:
/// the point c), ties by index: the order cellFacets takes.
void planesByDistanceBound(const CellGeometry& g, const Vec3& c, const Vec3& e,
                           std::vector<std::pair<double, int>>& scratch, std::vector<int>* order,
                           std::vector<double>* bound) {
  scratch.clear();
  for (std::size_t q = 0; q < g.normals.size(); ++q) {
    const double lb = std::abs(g.normals[q].dot(c) - g.offsets[q]) - g.normals[q].cwiseAbs().dot(e);
    scratch.push_back({std::max(lb, 0.0), int(q)});
  }
  std::sort(scratch.begin(), scratch.end());
  order->clear();
  bound->clear();
  for (const auto& [lb, q] : scratch) {
    order->push_back(q);
    bound->push_back(lb);
  }
}

/// The facets of one cell, and those of them whose plane has sections.
struct CellFacets {
  std::vector<std::uint8_t> key;  // side of each plane crossing the block
  std::uint64_t hash = 0;         // of the key (compared first)
  std::vector<int> facets, with_sections;
  Vec3 origin = Vec3::Zero();     // the point the cell was clipped around
  double radius = 0;              // no point of the cell lies farther from `origin`, mm
  /// No point of the cell lies farther from x (in the cell), mm.
  double radiusFrom(const Vec3& x) const { return radius * (1 + 1e-9) + (x - origin).norm(); }
};

/// The cells met by the voxels of one 8³ block, each clipped once, when a voxel first needs it:
/// voxels on the same side of every plane crossing the block share their cell.
class BlockCells {
 public:
  void startBlock(const Vec3& lo, const Vec3& hi, const CellGeometry& g) {
    c_ = 0.5 * (lo + hi);
    e_ = 0.5 * (hi - lo);
    crossing_.clear();
    for (std::size_t q = 0; q < g.normals.size(); ++q)
      if (std::abs(g.normals[q].dot(c_) - g.offsets[q]) <= g.normals[q].cwiseAbs().dot(e_) + g.tolerance)
        crossing_.push_back(int(q));
    used_ = 0;
    ordered_ = false;
  }

  const CellFacets& of(const Vec3& x, const CellGeometry& g) {
    key_.resize(crossing_.size());
    std::uint64_t hash = 1469598103934665603ull;  // FNV-1a over the sides
    for (std::size_t k = 0; k < crossing_.size(); ++k) {
      const std::size_t q = std::size_t(crossing_[k]);
      key_[k] = g.normals[q].dot(x) - g.offsets[q] >= 0;
      hash = (hash ^ key_[k]) * 1099511628211ull;
    }
    for (std::size_t c = 0; c < used_; ++c)
      if (cells_[c].hash == hash && cells_[c].key == key_) return cells_[c];
    if (!ordered_) orderPlanes(g);
    if (used_ == cells_.size()) cells_.emplace_back();
    CellFacets& cell = cells_[used_++];
    cell.key = key_;
    cell.hash = hash;
    cell.origin = x;
    cell.radius = cellFacets(x, g.normals, g.offsets, order_, bound_, g.lo, g.hi, g.tolerance, box_, &cell.facets) +
                  g.tolerance;
    cell.with_sections.clear();
    for (const int q : cell.facets)
      if (g.has_sections[std::size_t(q)]) cell.with_sections.push_back(q);
    ++clipped_;
    return cell;
  }

  /// Cells clipped since the last call.
  std::int64_t clipped() {
    const std::int64_t c = clipped_;
    clipped_ = 0;
    return c;
  }

 private:
  void orderPlanes(const CellGeometry& g) {
    planesByDistanceBound(g, c_, e_, byBound_, &order_, &bound_);
    ordered_ = true;
  }

  Vec3 c_ = Vec3::Zero(), e_ = Vec3::Zero();
  std::vector<int> crossing_, order_;
  std::vector<double> bound_;
  std::vector<std::pair<double, int>> byBound_;
  std::vector<std::uint8_t> key_;
  std::vector<CellFacets> cells_;  // the first used_ belong to this block
  std::size_t used_ = 0;
  bool ordered_ = false;
  std::int64_t clipped_ = 0;
  ClippedBox box_;
};

/// Method 2 on the voxels of one 4³ block: the planes that may be nearest to its voxels, and each
/// voxel decided by the thickened nearest plane, by the sections' boxes, or by the facets of its
/// cell of the arrangement.
struct SectionVoronoiBlockScan {
  const std::vector<PlaneInfo>& info;
  const Evaluator& ev;
  const CellGeometry& cells;
  float band = 0;

  struct Work {
    Scratch w;
    BlockCells cells;
    SectionVoronoiBlock out;
  };

  /// Planes whose sections' bounding boxes the block's projection reaches, found when a voxel off
  /// the thickened planes first needs them. Without any, no voxel of the block has an in-section
  /// projection: every such voxel lies outside R' (and R), and, as no plane's sections can reach
  /// it, is outside evidence for the repair (nearest plane -1, sampled_reconstruction.cpp).
  void listPlanesReached(const Vec3& c, const Vec3& e, Scratch& w) const {
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
  }

  /// Voxel x's decision; `listed` says whether w.inList holds the planes the block reaches yet.
  Decision decideVoxel(const Vec3& x, const Vec3& c, const Vec3& e, bool& listed, Work& work) const {
    Scratch& w = work.w;
    // Within the thickened nearest plane R' = R; elsewhere the facets of the voxel's cell
    // hold every plane that can hide a section point or give x a visible projection.
    Decision dcs;
    const int nearest = ev.nearestPlane(x, w.cand);
    if (!ev.decideByNearest(x, nearest, &dcs)) {
      if (!listed) {
        listPlanesReached(c, e, w);
        listed = true;
      }
      if (w.inList.empty()) {
        dcs = Decision{};
        dcs.value = band;  // outside every section's reach
      } else if (!ev.outsideEveryBox(x, w.inList, nearest, &dcs)) {
        const CellFacets& cf = work.cells.of(x, cells);
        w.facets.assign(cf.facets.begin(), cf.facets.end());
        if (!std::binary_search(w.facets.begin(), w.facets.end(), nearest))
          w.facets.insert(std::upper_bound(w.facets.begin(), w.facets.end(), nearest), nearest);
        dcs = ev.decide(x, w.facets, cf.with_sections, cf.radiusFrom(x), w);
      }
    }
    return dcs;
  }
};

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
  const auto& D = grid.dims;
  const Vec3 voxel = Vec3::Constant(grid.voxel);
  const CellGeometry cells(info, grid.centre(0, 0, 0) - voxel,
                           grid.centre(D[0] - 1, D[1] - 1, D[2] - 1) + voxel, grid.voxel);
  // Blocks of 4³ voxels share the planes that may be nearest (for the thickened planes); the
  // output goes by blocks of 8³ (block_grid.h), each the union of eight of them, and shares the
  // cells of the arrangement its voxels lie in.
  constexpr int kBlock = 4, kOut = BlockGrid<float>::kSide;
  const std::int64_t bx = (D[0] + kOut - 1) / kOut, by = (D[1] + kOut - 1) / kOut, bz = (D[2] + kOut - 1) / kOut;
  const std::int64_t blocks = bx * by * bz;
  std::atomic<std::int64_t> exact{0}, cellsClipped{0};

  const SectionVoronoiBlockScan scan{info, ev, cells, band};
  using Work = SectionVoronoiBlockScan::Work;
  const auto doBlock = [&](int i0, int j0, int k0, Work& work) {
    Scratch& w = work.w;
    SectionVoronoiBlock& out = work.out;
    const int i1 = std::min(D[0], i0 + kBlock), j1 = std::min(D[1], j0 + kBlock),
              k1 = std::min(D[2], k0 + kBlock);
    if (i0 >= i1 || j0 >= j1 || k0 >= k1) return;
    const Vec3 lo = grid.centre(i0, j0, k0), hi = grid.centre(i1 - 1, j1 - 1, k1 - 1);
    const Vec3 c = 0.5 * (lo + hi), e = 0.5 * (hi - lo);
    // The planes that may be nearest to a voxel of the block: within the smallest upper bound.
    double minHi = kInf;
    for (const PlaneInfo& I : info) minHi = std::min(minHi, std::abs(I.row.s(c)) + I.row.an.dot(e));
    w.cand.clear();
    for (std::size_t q = 0; q < info.size(); ++q)
      if (std::abs(info[q].row.s(c)) - info[q].row.an.dot(e) <= minHi + 1e-9 * (1 + minHi)) w.cand.push_back(int(q));
    bool listed = false;
    for (int k = k0; k < k1; ++k)
      for (int j = j0; j < j1; ++j)
        for (int i = i0; i < i1; ++i) {
          const Decision dcs = scan.decideVoxel(grid.centre(i, j, k), c, e, listed, work);
          const int o = BlockGrid<float>::offset(i, j, k);
          out.value[std::size_t(o)] = std::clamp(dcs.value, -band, band);
          out.plane_distance[std::size_t(o)] = dcs.plane_distance;
          out.nearest_plane[std::size_t(o)] = dcs.nearest_plane;
          out.section_plane[std::size_t(o)] = dcs.section_plane;
          out.lift_height[std::size_t(o)] = dcs.lift;
        }
  };
  const std::int64_t chunk = std::max<std::int64_t>(16, blocks / 32);
  for (std::int64_t first = 0; first < blocks; first += chunk) {
    const std::int64_t last = std::min(blocks, first + chunk);
    tbb::parallel_for(tbb::blocked_range<std::int64_t>(first, last, 1), [&](const tbb::blocked_range<std::int64_t>& r) {
      Work work;
      for (std::int64_t b = r.begin(); b != r.end(); ++b) {
        const int ib = int(b % bx) * kOut, jb = int((b / bx) % by) * kOut, kb = int(b / (bx * by)) * kOut;
        const int ie = std::min(D[0], ib + kOut) - 1, je = std::min(D[1], jb + kOut) - 1, ke = std::min(D[2], kb + kOut) - 1;
        work.cells.startBlock(grid.centre(ib, jb, kb), grid.centre(ie, je, ke), cells);
        for (int dz = 0; dz < kOut; dz += kBlock)
          for (int dy = 0; dy < kOut; dy += kBlock)
            for (int dx = 0; dx < kOut; dx += kBlock) doBlock(ib + dx, jb + dy, kb + dz, work);
        cellsClipped += work.cells.clipped();
        // Voxels beyond the grid repeat the block's first.
        repeatFirstBeyondGrid(grid, {ib, jb, kb}, work.out);
        visitBlock(b, work.out);
      }
      exact += work.w.exact;
    });
    if (progress) progress(last, blocks);
  }
  if (statistics) {
    statistics->exact_face_tests = exact;
    statistics->cells_clipped = cellsClipped;
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
  out.cells_clipped = statistics.cells_clipped;
  return out;
}

struct SectionVoronoiPoints::Impl {
  std::vector<PlaneInfo> info;
  Evaluator ev;
  CellGeometry cells;
  bool any_section = false;
  Impl(std::vector<PlaneInfo> i, double slab)
      : info(std::move(i)), ev(info, slab),
        cells(info, Vec3::Constant(kInf), Vec3::Constant(-kInf), std::max(slab, 1e-6)) {
    for (const PlaneInfo& I : info) any_section = any_section || I.has_sections;
  }
};

SectionVoronoiPoints::SectionVoronoiPoints(const std::vector<CuttingPlane>& planes,
                                           const std::vector<SectionDistanceField>& fields,
                                           const SectionVoronoiParams& params)
    : impl_(new Impl(planeInfo(planes, fields), params.slab_mm)) {}

SectionVoronoiPoints::~SectionVoronoiPoints() { delete impl_; }

SectionVoronoiPoints::Answer SectionVoronoiPoints::at(const Vec3& x, CellMemo* memo) const {
  Answer a;
  if (!impl_->any_section) return a;
  const CellGeometry& g = impl_->cells;
  Decision d;
  int nearest = -1;
  double nearestDistance = kInf;
  for (std::size_t q = 0; q < g.normals.size(); ++q) {
    const double s = std::abs(g.normals[q].dot(x) - g.offsets[q]);
    if (s < nearestDistance) {
      nearestDistance = s;
      nearest = int(q);
    }
  }
  if (impl_->ev.decideByNearest(x, nearest, &d)) {
    a.inside = d.verdict == Verdict::inside;
    a.section_plane = d.section_plane;
    a.lift_height = d.lift;
    return a;
  }
  thread_local Scratch w;
  thread_local CellMemo own;
  CellMemo& cell = memo ? *memo : own;
  if (!memo) cell.radius = -1;  // without a memo every query clips its own cell
  // x is in the memo's cell when it lies strictly on the cell's side of every facet, in its box.
  bool same = cell.radius >= 0 && (x - x.cwiseMax(cell.lo).cwiseMin(cell.hi)).isZero(0);
  for (std::size_t k = 0; same && k < cell.facets.size(); ++k) {
    const std::size_t q = std::size_t(cell.facets[k]);
    same = cell.sides[k] * (g.normals[q].dot(x) - g.offsets[q]) > g.tolerance;
  }
  if (same) ++cell.reuses;
  else {  // clip x's cell, the planes taken by distance from x
    thread_local ClippedBox box;
    thread_local std::vector<std::pair<double, int>> byDistance;
    thread_local std::vector<int> order;
    thread_local std::vector<double> bound;
    planesByDistanceBound(g, x, Vec3::Zero(), byDistance, &order, &bound);
    const Vec3 pad = Vec3::Constant(g.pad);
    cell.lo = g.lo.cwiseMin(x - pad);
    cell.hi = g.hi.cwiseMax(x + pad);
    cell.radius = cellFacets(x, g.normals, g.offsets, order, bound, cell.lo, cell.hi, g.tolerance, box, &cell.facets) +
                  g.tolerance;
    cell.origin = x;
    cell.sides.clear();
    for (const int q : cell.facets)
      cell.sides.push_back(g.normals[std::size_t(q)].dot(x) - g.offsets[std::size_t(q)] >= 0 ? 1 : -1);
  }
  w.facets = cell.facets;
  if (!std::binary_search(w.facets.begin(), w.facets.end(), nearest))
    w.facets.insert(std::upper_bound(w.facets.begin(), w.facets.end(), nearest), nearest);
  w.cand.clear();  // the facets with sections
  for (const int q : w.facets)
    if (g.has_sections[std::size_t(q)]) w.cand.push_back(q);
  d = impl_->ev.decide(x, w.facets, w.cand, cell.radius * (1 + 1e-9) + (x - cell.origin).norm(), w);
  a.inside = d.verdict == Verdict::inside;
  a.section_plane = d.section_plane;
  a.lift_height = d.lift;
  return a;
}

}  // namespace xsect

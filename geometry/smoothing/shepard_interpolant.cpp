// Shepard's interpolant: the O(k²) definition and the block-culled evaluation on a grid
// (see shepard_interpolant.h).
#include "geometry/smoothing/shepard_interpolant.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "geometry/reconstruction/plane_rows.h"

namespace xsect {

namespace {

/// (t_min / t)^p without overflow; common exponents without pow.
inline double weightRatio(double tmin, double t, double p) {
  const double r = tmin / t;
  if (p == 1) return r;
  if (p == 2) return r * r;
  if (p == 4) return (r * r) * (r * r);
  return std::pow(r, p);
}

/// The combination step shared by the definition and the grid: planes that see x, their
/// distances t and values fv, listed by increasing plane index. Planes with weight factor 0 take
/// no part (not even on their own plane), unless no other plane sees x: then f is the nearest
/// plane's value. p = inf is method 1: the nearest plane, factors ignored.
double combine(const int* plane, const double* t, const double* fv, int m, double p,
               const std::vector<double>* factor) {
  const auto weightOf = [&](int k) { return factor ? (*factor)[std::size_t(plane[k])] : 1.0; };
  double tmin = std::numeric_limits<double>::infinity(), tminWeighted = tmin;
  int nearest = -1;
  for (int k = 0; k < m; ++k) {
    if (t[k] < tmin || (t[k] == tmin && plane[k] < plane[nearest])) {
      tmin = t[k];
      nearest = k;
    }
    if (weightOf(k) > 0) tminWeighted = std::min(tminWeighted, t[k]);
  }
  if (std::isinf(p) || std::isinf(tminWeighted)) return fv[nearest];
  double sw = 0, swf = 0;
  if (tminWeighted == 0) {  // on a plane: f = f_i there (Property 3); on several, their mean
    for (int k = 0; k < m; ++k)
      if (t[k] == 0 && weightOf(k) > 0) {
        sw += 1;
        swf += fv[k];
      }
    return swf / sw;
  }
  for (int k = 0; k < m; ++k) {
    const double w = weightRatio(tminWeighted, t[k], p) * weightOf(k);
    sw += w;
    swf += w * fv[k];
  }
  return swf / sw;
}

/// Plane p's observed piece when it is not whole (nullptr: whole, or no pieces given).
const ObservedPiece* partialPiece(const ShepardData& data, int p) {
  if (!data.pieces) return nullptr;
  const ObservedPiece& piece = (*data.pieces)[std::size_t(p)];
  return piece.whole ? nullptr : &piece;
}

/// Whether the segment [x, y], whose ends plane Q separates (sx = s_Q(x), sy = s_Q(y), sx sy < 0),
/// crosses Q in its piece (nullptr: Q whole).
bool crossesInPiece(const ObservedPiece* piece, const Plane& Q, const Vec3& x, const Vec3& y, double sx, double sy) {
  if (!piece) return true;
  if (piece->empty) return false;
  const Vec2 z = Q.toPlane(x + (sx / (sx - sy)) * (y - x));
  return piece->holds(z.x(), z.y());
}

/// Throws unless `data` has one distance function and (if any) one finite, non-negative weight
/// factor per plane.
void checkData(const ShepardData& data) {
  const auto& planes = *data.planes;
  if (data.near->size() != planes.size() || data.f->size() != planes.size())
    throw std::invalid_argument("Shepard: one distance function per plane is required");
  if (data.pieces && data.pieces->size() != planes.size())
    throw std::invalid_argument("Shepard: one observed piece per plane is required");
  if (data.weight_factor &&
      (data.weight_factor->size() != planes.size() ||
       std::any_of(data.weight_factor->begin(), data.weight_factor->end(),
                   [](double v) { return !(v >= 0 && std::isfinite(v)); })))
    throw std::invalid_argument("Shepard: one finite, non-negative weight factor per plane is required");
}

using Row = PlaneRow;

struct Entry {
  int plane;
  bool candidate;       ///< may be seen from some voxel of the box (else kept only as a blocker)
  bool covered = true;  ///< its piece holds the box's projections (x_i is the projection there)
};

struct Scratch {
  std::vector<Entry> lists[4];
  std::vector<std::uint8_t> covered;       ///< per entry: x_i is the projection all over the box
  std::vector<const ObservedPiece*> piece;  ///< per entry: its partial piece (nullptr: whole)
  std::vector<double> sc, r, lo, hi, s0, dsx, dsy, dsz, cm, tv, fv, sv;
  std::vector<int> order, cand, vp;
  std::vector<std::uint8_t> keep, isCand;
  std::vector<std::pair<double, int>> sortKey;
};

constexpr double kEps = 1e-9;  // mm: slack on the box-level sign bounds (kept conservative)

/// Per plane of `from` over the box of centre c and half-extents e: its signed distance at c
/// (w.sc) and its reach over the box (w.r), the least and greatest distance from the box to its
/// foot point x_i (w.lo, w.hi; on a partial piece not covering the box's projection, x_i may lie
/// off the projection: t_i <= sqrt(s² + o²) over the box), whether the piece covers that
/// projection (w.covered: x_i is then the projection, t_i = |s_i| as on a whole plane), and the
/// planes that do not cross the box (w.order).
void boxBounds(const ShepardData& data, const std::vector<Row>& rows, const std::vector<Entry>& from, const Vec3& c,
               const Vec3& e, Scratch& w) {
  const std::size_t m = from.size();
  const double rho = e.norm();
  w.covered.assign(m, 1);
  w.sc.resize(m);
  w.r.resize(m);
  w.lo.resize(m);
  w.hi.resize(m);
  w.order.clear();
  for (std::size_t k = 0; k < m; ++k) {
    const Row& p = rows[from[k].plane];
    w.sc[k] = p.s(c);
    w.r[k] = p.ax * e.x() + p.ay * e.y() + p.az * e.z();
    w.lo[k] = std::max(0.0, std::abs(w.sc[k]) - w.r[k]);
    w.hi[k] = std::abs(w.sc[k]) + w.r[k];
    if (const ObservedPiece* piece = partialPiece(data, from[k].plane)) {
      const double a = p.ux * c.x() + p.uy * c.y() + p.uz * c.z() - p.uo;
      const double b = p.vx * c.x() + p.vy * c.y() + p.vz * c.z() - p.vo;
      w.covered[k] = covers(*piece, a, b, rho);
      if (!w.covered[k]) {
        double olo, ohi;
        piece->bounds(a, b, rho, &olo, &ohi);
        w.hi[k] = std::sqrt(w.hi[k] * w.hi[k] + ohi * ohi);
      }
    }
    if (std::abs(w.sc[k]) > w.r[k] + kEps) w.order.push_back(int(k));  // does not cross the box
  }
}

/// Planes of `from` that may be seen from a voxel of the box [c - e, c + e], and the planes that
/// may hide one of them there (see the file comment of shepard_interpolant.h), sorted by lower
/// distance bound.
void cullBox(const ShepardData& data, const std::vector<Row>& rows, const std::vector<Entry>& from, const Vec3& c,
             const Vec3& e, std::vector<Entry>& out, Scratch& w) {
  const std::size_t m = from.size();
  const double rho = e.norm();
  boxBounds(data, rows, from, c, e, w);
  // Whether q's piece holds every point where a segment from the box to x_i crosses P_q (q
  // separating the box from x_i everywhere; see shepard_interpolant.h).
  const auto holdsCrossings = [&](std::size_t q, std::size_t i) {
    // x = c + d crosses P_q at z(x) = x - (s_q(x) / c_qi) n_i; with d = d⊥ + α n_i,
    // |z(x) - z(c)|² = |d⊥|² + (n_q·d⊥)² / c_qi² <= |d⊥|² / c_qi²: within ρ / |c_qi| of z(c).
    const ObservedPiece* piece = partialPiece(data, from[q].plane);
    if (!piece) return true;
    const Row &Q = rows[from[q].plane], &I = rows[from[i].plane];
    const double cqi = Q.dot(I);
    if (!(std::abs(cqi) > 1e-6)) return false;
    const Vec3 ci = c - w.sc[i] * Vec3(I.nx, I.ny, I.nz);
    const double sci = Q.s(ci);
    const Vec3 z = c + (w.sc[q] / (w.sc[q] - sci)) * (ci - c);
    const double a = Q.ux * z.x() + Q.uy * z.y() + Q.uz * z.z() - Q.uo;
    const double b = Q.vx * z.x() + Q.vy * z.y() + Q.vz * z.z() - Q.vo;
    return covers(*piece, a, b, rho / std::abs(cqi));
  };
  // g(x) = σ_q (s_q(x) - (n_q·n_i) s_i(x)) = σ_q s_q(x_i): q separates x from x_i where g < 0.
  const auto gRange = [&](std::size_t q, std::size_t i, double* gmin, double* gmax) {
    const Row &Q = rows[from[q].plane], &I = rows[from[i].plane];
    const double cqi = Q.dot(I), sigma = w.sc[q] > 0 ? 1.0 : -1.0;
    const double g0 = sigma * (w.sc[q] - cqi * w.sc[i]);
    const double rad = std::abs(Q.nx - cqi * I.nx) * e.x() + std::abs(Q.ny - cqi * I.ny) * e.y() +
                       std::abs(Q.nz - cqi * I.nz) * e.z();
    *gmin = g0 - rad;
    *gmax = g0 + rad;
  };
  constexpr std::size_t kBlockers = 10;  // nearest non-crossing planes tried as box-wide blockers
  const std::size_t nb = std::min(kBlockers, w.order.size());
  std::partial_sort(w.order.begin(), w.order.begin() + nb, w.order.end(), [&](int a, int b) {
    return w.hi[a] < w.hi[b] || (w.hi[a] == w.hi[b] && from[a].plane < from[b].plane);
  });
  w.isCand.assign(m, 0);
  w.cand.clear();
  for (std::size_t i = 0; i < m; ++i) {
    if (!from[i].candidate) continue;
    bool seen = true;
    for (std::size_t b = 0; b < nb && seen; ++b) {
      const std::size_t q = std::size_t(w.order[b]);
      if (q == i) continue;
      double gmin, gmax;
      gRange(q, i, &gmin, &gmax);
      if (gmax < -kEps && w.covered[i] && holdsCrossings(q, i)) seen = false;  // q hides x_i from every voxel of the box
    }
    if (seen) {
      w.isCand[i] = 1;
      w.cand.push_back(int(i));
    }
  }
  w.keep.assign(m, 0);
  for (std::size_t q = 0; q < m; ++q) {
    if (w.isCand[q]) {
      w.keep[q] = 1;
      continue;
    }
    const bool crossing = !(std::abs(w.sc[q]) > w.r[q] + kEps);
    for (const int i : w.cand) {
      if (!(w.lo[q] < w.hi[i] + kEps)) continue;  // q is farther than x_i everywhere
      if (crossing || !w.covered[std::size_t(i)]) {  // x_i off the projection: any plane this near may cut
        w.keep[q] = 1;
        break;
      }
      double gmin, gmax;
      gRange(q, std::size_t(i), &gmin, &gmax);
      if (gmin < kEps) {  // q may separate x from x_i somewhere in the box
        w.keep[q] = 1;
        break;
      }
    }
  }
  w.sortKey.clear();
  for (std::size_t k = 0; k < m; ++k)
    if (w.keep[k]) w.sortKey.emplace_back(w.lo[k], int(k));
  std::sort(w.sortKey.begin(), w.sortKey.end(), [&](const auto& a, const auto& b) {
    return a.first < b.first || (a.first == b.first && from[a.second].plane < from[b.second].plane);
  });
  out.clear();
  for (const auto& [l, k] : w.sortKey) out.push_back({from[k].plane, bool(w.isCand[k]), bool(w.covered[k])});
}

}  // namespace

std::vector<double> endPlaneWeightFactors(const std::vector<CuttingPlane>& planes,
                                          std::size_t first_end_plane) {
  std::vector<double> factor(planes.size(), 1.0);
  for (std::size_t e = first_end_plane; e < planes.size(); ++e) {
    double m = 0;
    for (std::size_t i = 0; i < first_end_plane && i < planes.size(); ++i)
      if (!planes[i].sections.empty()) {
        const double c = planes[i].plane.normal.dot(planes[e].plane.normal);
        m = std::max(m, c * c);
      }
    factor[e] = m;
  }
  return factor;
}

double shepardValue(const ShepardData& data, const Vec3& x, double exponent, int* visible) {
  checkData(data);
  const auto& planes = *data.planes;
  const std::size_t k = planes.size();
  std::vector<double> s(k);
  for (std::size_t i = 0; i < k; ++i) s[i] = planes[i].plane.signedDistance(x);
  std::vector<int> idx;
  std::vector<double> t, fv;
  for (std::size_t i = 0; i < k; ++i) {
    const Plane& P = planes[i].plane;
    const ObservedPiece* piece = partialPiece(data, int(i));
    if (piece && piece->empty) continue;
    Vec3 xi = x - s[i] * P.normal;
    Vec2 ab = P.toPlane(x);
    double ti = std::abs(s[i]);
    if (piece) {  // the nearest point of the piece
      double na, nb;
      const double o = piece->distance(ab.x(), ab.y(), &na, &nb);
      if (o > 0) {
        ab = Vec2(na, nb);
        xi = P.toWorld(ab);
        ti = std::sqrt(s[i] * s[i] + o * o);
      }
    }
    bool seen = true;
    for (std::size_t q = 0; q < k && seen; ++q) {
      if (q == i) continue;
      const double sq = planes[q].plane.signedDistance(xi);
      if (s[q] * sq < 0 && crossesInPiece(partialPiece(data, int(q)), planes[q].plane, x, xi, s[q], sq)) seen = false;
    }
    if (!seen) continue;
    idx.push_back(int(i));
    t.push_back(ti);
    fv.push_back(planeDistanceValue((*data.near)[i], (*data.f)[i], ab.x(), ab.y()));
  }
  if (visible) *visible = int(idx.size());
  if (idx.empty()) throw std::logic_error("Shepard: no plane sees the point");  // the nearest always does
  return combine(idx.data(), t.data(), fv.data(), int(idx.size()), exponent, data.weight_factor);
}

namespace {

/// Shepard's interpolant on a grid, block by block: the planes each 32³ super-box may see, culled
/// again down an octree of boxes inside each 8³ block, then per voxel the planes it sees (their
/// pieces) and their values combined.
class ShepardScan {
 public:
  static constexpr int kSuper = 32, kBlock = 8;

  ShepardScan(const ShepardData& data, const GridSpec& grid, double exponent, const std::vector<Entry>& all,
              ShepardField& out)
      : data_(data), planes_(*data.planes), grid_(grid), exponent_(exponent), rows_(planeRows(*data.planes)),
        h_(grid.voxel), out_(out) {
    const auto& D = grid.dims;
    sx_ = (D[0] + kSuper - 1) / kSuper, sy_ = (D[1] + kSuper - 1) / kSuper;
    const int sz = (D[2] + kSuper - 1) / kSuper;
    superList_.resize(std::size_t(sx_) * sy_ * sz);
    tbb::parallel_for(0, int(superList_.size()), [&](int s) {
      const int i0 = (s % sx_) * kSuper, j0 = ((s / sx_) % sy_) * kSuper, k0 = (s / (sx_ * sy_)) * kSuper;
      Vec3 c, e;
      box(i0, j0, k0, std::min(D[0], i0 + kSuper), std::min(D[1], j0 + kSuper), std::min(D[2], k0 + kSuper), &c, &e);
      Scratch w;
      cullBox(data_, rows_, all, c, e, superList_[std::size_t(s)], w);
    });
  }

  /// Every block, in chunks (progress after each); the visible planes counted into out.
  void run(const std::function<void(std::int64_t, std::int64_t)>& progress) {
    const auto& D = grid_.dims;
    std::atomic<std::int64_t> visibleTotal{0};
    std::atomic<int> visibleMax{0};
    const int bx = (D[0] + kBlock - 1) / kBlock, by = (D[1] + kBlock - 1) / kBlock,
              bz = (D[2] + kBlock - 1) / kBlock;
    const int blocks = bx * by * bz;
    const int chunk = std::max(256, blocks / 16);
    for (int first = 0; first < blocks; first += chunk) {
      const int last = std::min(blocks, first + chunk);
      tbb::parallel_for(tbb::blocked_range<int>(first, last, 16), [&](const tbb::blocked_range<int>& r) {
        Scratch w;
        std::int64_t vis = 0;
        int vmax = 0;
        for (int b = r.begin(); b != r.end(); ++b) {
          const int ib = (b % bx) * kBlock, jb = ((b / bx) % by) * kBlock, kb = (b / (bx * by)) * kBlock;
          const int s = (ib / kSuper) + sx_ * ((jb / kSuper) + sy_ * (kb / kSuper));
          visit(ib, jb, kb, kBlock, 0, superList_[std::size_t(s)], w, vis, vmax);
        }
        visibleTotal += vis;
        int prev = visibleMax.load();
        while (vmax > prev && !visibleMax.compare_exchange_weak(prev, vmax)) {
        }
      });
      if (progress) progress(last, blocks);
    }
    out_.visible_planes = visibleTotal.load();
    out_.max_visible_planes = visibleMax.load();
  }

 private:
  void box(int i0, int j0, int k0, int i1, int j1, int k1, Vec3* c, Vec3* e) const {
    const Vec3 a = grid_.centre(i0, j0, k0), b = grid_.centre(i1 - 1, j1 - 1, k1 - 1);
    *c = 0.5 * (a + b);
    *e = 0.5 * (b - a);
  }

  /// Box of `size` voxels at (i0, j0, k0), entries `from`; level 0 = 8³.
  void visit(int i0, int j0, int k0, int size, int level, const std::vector<Entry>& from, Scratch& w,
             std::int64_t& vis, int& vmax) const {
    const auto& D = grid_.dims;
    const int i1 = std::min(D[0], i0 + size), j1 = std::min(D[1], j0 + size),
              k1 = std::min(D[2], k0 + size);
    if (i0 >= i1 || j0 >= j1 || k0 >= k1) return;
    Vec3 c, e;
    box(i0, j0, k0, i1, j1, k1, &c, &e);
    std::vector<Entry>& list = w.lists[level];
    cullBox(data_, rows_, from, c, e, list, w);
    if (size <= 2 || list.size() <= 3) {
      evalVoxels(i0, j0, k0, i1, j1, k1, list, w, vis, vmax);
      return;
    }
    const int half = size / 2;
    for (int dz = 0; dz < 2; ++dz)
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx)
          visit(i0 + dx * half, j0 + dy * half, k0 + dz * half, half, level + 1, list, w, vis, vmax);
  }

  /// The voxels of a box from its entries `list`: the entries' distances and products prepared
  /// once, then each voxel's visible planes and value.
  void evalVoxels(int i0, int j0, int k0, int i1, int j1, int k1, const std::vector<Entry>& list, Scratch& w,
                  std::int64_t& vis, int& vmax) const {
    const std::size_t m = list.size();
    const Vec3 x0 = grid_.centre(i0, j0, k0);
    w.s0.resize(m);
    w.dsx.resize(m);
    w.dsy.resize(m);
    w.dsz.resize(m);
    w.cand.clear();
    for (std::size_t q = 0; q < m; ++q) {
      const Row& r = rows_[list[q].plane];
      w.s0[q] = r.s(x0);
      w.dsx[q] = r.nx * h_;
      w.dsy[q] = r.ny * h_;
      w.dsz[q] = r.nz * h_;
      if (list[q].candidate) w.cand.push_back(int(q));
    }
    const std::size_t nc = w.cand.size();
    w.cm.resize(m * nc);  // n_q . n_i for every entry q and candidate i
    for (std::size_t q = 0; q < m; ++q)
      for (std::size_t a = 0; a < nc; ++a)
        w.cm[q * nc + a] = rows_[list[q].plane].dot(rows_[list[std::size_t(w.cand[a])].plane]);
    w.piece.resize(m);
    for (std::size_t q = 0; q < m; ++q) w.piece[q] = partialPiece(data_, list[q].plane);
    w.sv.resize(m);
    w.tv.resize(nc);
    w.fv.resize(nc);
    w.vp.resize(nc);
    for (int k = k0; k < k1; ++k)
      for (int j = j0; j < j1; ++j)
        for (int i = i0; i < i1; ++i) {
          const double di = i - i0, dj = j - j0, dk = k - k0;
          for (std::size_t q = 0; q < m; ++q) w.sv[q] = w.s0[q] + w.dsx[q] * di + w.dsy[q] * dj + w.dsz[q] * dk;
          const int nv = visiblePlanes(list, w, x0 + h_ * Vec3(di, dj, dk));
          vis += nv;
          vmax = std::max(vmax, nv);
          out_.value.values[std::size_t(grid_.index(i, j, k))] =
              float(combine(w.vp.data(), w.tv.data(), w.fv.data(), nv, exponent_, data_.weight_factor));
        }
  }

  /// The candidate planes voxel x sees (no other plane crosses the segment to its plane's nearest
  /// observed point, within that plane's piece): their planes, distances and values in w.vp, w.tv,
  /// w.fv; returns how many. w.sv holds the entries' signed distances at x.
  int visiblePlanes(const std::vector<Entry>& list, Scratch& w, const Vec3& x) const {
    const std::size_t m = list.size(), nc = w.cand.size();
    int nv = 0;
    for (std::size_t a = 0; a < nc; ++a) {
      const std::size_t ia = std::size_t(w.cand[a]);
      const int p = list[ia].plane;
      const Row& r = rows_[p];
      const double si = w.sv[ia];
      double t = std::abs(si);
      double ua = r.ux * x.x() + r.uy * x.y() + r.uz * x.z() - r.uo;
      double vb = r.vx * x.x() + r.vy * x.y() + r.vz * x.z() - r.vo;
      // x_i: the piece's nearest point when the projection is off the piece (`moved`); the
      // projection is formed only where a partial piece's crossing must be located.
      Vec3 xi;
      bool moved = false;
      if (const ObservedPiece* piece = list[ia].covered ? nullptr : w.piece[ia]) {
        double na, nb;
        const double o = piece->distance(ua, vb, &na, &nb);
        if (o > 0) {
          moved = true;
          ua = na;
          vb = nb;
          xi = planes_[std::size_t(p)].plane.toWorld(Vec2(na, nb));
          t = std::sqrt(si * si + o * o);
        }
      }
      bool seen = true;
      for (std::size_t q = 0; q < m && seen; ++q) {
        if (q == ia) continue;
        const double sq = w.sv[q];
        if (!(std::abs(sq) < t)) continue;
        const double sqi = moved ? rows_[list[q].plane].s(xi) : sq - w.cm[q * nc + a] * si;
        if (!(sq * sqi < 0)) continue;
        if (!w.piece[q]) {
          seen = false;
        } else {
          const Vec3 end = moved ? xi : Vec3(x - si * Vec3(r.nx, r.ny, r.nz));
          seen = !crossesInPiece(w.piece[q], planes_[std::size_t(list[q].plane)].plane, x, end, sq, sqi);
        }
      }
      if (!seen) continue;
      w.vp[nv] = p;
      w.tv[nv] = t;
      w.fv[nv] = planeDistanceValue((*data_.near)[p], (*data_.f)[p], ua, vb);
      ++nv;
    }
    return nv;
  }

  const ShepardData& data_;
  const std::vector<CuttingPlane>& planes_;
  const GridSpec& grid_;
  const double exponent_;
  const std::vector<Row> rows_;
  const double h_;
  ShepardField& out_;
  int sx_ = 0, sy_ = 0;  ///< super-boxes along x and y
  std::vector<std::vector<Entry>> superList_;
};

}  // namespace

ShepardField shepardInterpolant(const ShepardData& data, const GridSpec& grid, double exponent,
                                const std::function<void(std::int64_t, std::int64_t)>& progress) {
  const auto& planes = *data.planes;
  if (planes.empty()) throw std::invalid_argument("Shepard: no cutting plane");
  checkData(data);
  if (!(exponent > 0)) throw std::invalid_argument("Shepard: the exponent must be positive");
  if (!(grid.voxel > 0)) throw std::invalid_argument("Shepard: voxel size must be positive");
  std::vector<Entry> all;  // an empty piece neither sees nor hides
  for (std::size_t i = 0; i < planes.size(); ++i)
    if (!data.pieces || !(*data.pieces)[i].empty) all.push_back({int(i), true});
  if (all.empty()) throw std::invalid_argument("Shepard: every observed piece is empty");

  ShepardField out;
  out.value.grid = grid;
  out.value.values.resize(std::size_t(grid.count()));
  ShepardScan(data, grid, exponent, all, out).run(progress);
  return out;
}

}  // namespace xsect

// Sign vectors of section points and the cells they bound (see section_arrangement.h).
// Cells are keyed by a 128-bit Zobrist hash of the sign vector (two independent 64-bit tables):
// storing the vectors themselves would take points × planes bytes; a collision between two of the
// few million vectors met has probability below 1e-25.
#include "geometry/arrangement/section_arrangement.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <random>
#include <stdexcept>
#include <utility>

#include "geometry/core/polygon.h"

namespace xsect {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Key = std::pair<std::uint64_t, std::uint64_t>;

struct Zobrist {
  std::vector<std::array<std::uint64_t, 3>> a, b;  // per plane, per sign (-1, 0, +1)
  explicit Zobrist(std::size_t n) : a(n), b(n) {
    std::mt19937_64 rng(0x5ec7);
    for (std::size_t i = 0; i < n; ++i)
      for (int s = 0; s < 3; ++s) {
        a[i][s] = rng();
        b[i][s] = rng();
      }
  }
};

/// Exact sign of a.x + b.y + c.z + d for the double coefficients and coordinates: a static
/// floating-point filter (the evaluation's rounding error is below 8 ulp of the magnitudes summed)
/// and CGAL's exact predicate when the value is within that bound of zero.
int sign(const K::Plane_3& P, const Vec3& x) {
  // GMP raises SIGFPE on converting a non-finite number: a defect upstream, reported as one.
  if (!x.allFinite()) throw std::logic_error("a non-finite point reached the arrangement's exact predicate");
  const double a = P.a(), b = P.b(), c = P.c(), d = P.d();
  const double v = a * x.x() + b * x.y() + c * x.z() + d;
  const double mag = std::abs(a * x.x()) + std::abs(b * x.y()) + std::abs(c * x.z()) + std::abs(d);
  const double bound = 8.0 * std::numeric_limits<double>::epsilon() * mag;
  if (v > bound) return 1;
  if (v < -bound) return -1;
  const CGAL::Oriented_side s = P.oriented_side(K::Point_3(x.x(), x.y(), x.z()));
  return s == CGAL::ON_POSITIVE_SIDE ? 1 : (s == CGAL::ON_NEGATIVE_SIDE ? -1 : 0);
}

struct PointKeys {
  Key minus, plus;  // cell keys on the two sides of the own plane
  Key minusAlt, plusAlt;  // trace points: the same, on the negative side of their trace's plane
};

/// Trace points on a third plane of the same pencil (SectionArrangement::pencil_crossings).
struct PencilCrossings {
  int count = 0;
  std::array<int, 3> example{-1, -1, -1};
};

/// Whether trace point w of plane i on plane t's trace also lies on a third plane j of the pencil
/// through their common line: |d_j(w)| within 1e-9 of the section's size plus w's coordinates (the
/// rounding of a trace point is about 1e-15 of them; a contour crossing that near a third plane by
/// chance is as unlikely), and the three normals coplanar (1e-9 of the sine between i and t: planes through one line; planes
/// meeting in a point, such as the three axes' planes on a pixel grid, are not a pencil), j not
/// parallel to i or t (a plane listed twice is a coincidence, not a pencil).
void notePencilCrossing(const std::vector<CuttingPlane>& planes, std::size_t i, std::size_t t,
                        const std::vector<std::size_t>& crossing, const Vec3& w, double sectionRadius,
                        PencilCrossings& out) {
  const Vec3 ni = planes[i].plane.normal, nt = planes[t].plane.normal, line = ni.cross(nt);
  const double tol = 1e-9 * (sectionRadius + w.cwiseAbs().maxCoeff());
  for (const std::size_t j : crossing) {
    if (j == t) continue;
    const Vec3 nj = planes[j].plane.normal;
    if (std::abs(planes[j].plane.signedDistance(w)) > tol || std::abs(line.dot(nj)) > 1e-9 * line.norm()) continue;
    if (nj.cross(ni).norm() <= 1e-6 || nj.cross(nt).norm() <= 1e-6) continue;
    if (out.count++ == 0) out.example = {int(i), int(t), int(j)};
    return;
  }
}

struct KeyHash {
  std::size_t operator()(const Key& k) const { return std::size_t(k.first); }  // already random bits
};

}  // namespace

struct ArrangementKeys {
  explicit ArrangementKeys(std::size_t n) : z(n) {}
  Zobrist z;
  std::vector<K::Plane_3> eq;
  std::unordered_map<Key, int, KeyHash> cellOf;
  std::vector<Key> keyOf;  // by cell id
};

/// A section's place among the other planes: those that may cross it (nearer to its bounding
/// disk's centre than its radius, with a margin far above rounding), and the key over all the
/// others, whose sign is the same at every point of the section (the sign at the centre). Each
/// point then tests only the crossing planes: the cost follows the sub-sections' boundaries, not
/// points x planes.
struct SectionSpan {
  std::vector<std::size_t> crossing;
  Key base{0, 0};
  double radius = 0;
  Vec2 lo, hi;  ///< bounds of every ring (a hole is not trusted to lie inside its outer ring: .csl)
};

SectionSpan spanOf(const std::vector<CuttingPlane>& planes, const std::vector<K::Plane_3>& eq, const Zobrist& z,
                   std::size_t i, const Section& sec) {
  const CuttingPlane& cp = planes[i];
  SectionSpan span;
  Eigen::AlignedBox2d box = ringBounds(sec.outer);
  for (const Ring& hole : sec.holes) box.extend(ringBounds(hole));
  span.lo = box.min(), span.hi = box.max();
  const Vec3 centre = cp.plane.toWorld(box.center());
  span.radius = 0.5 * box.diagonal().norm() * (1 + 1e-9) + 1e-9;
  for (std::size_t j = 0; j < planes.size(); ++j) {
    if (j == i) continue;
    if (std::abs(planes[j].plane.signedDistance(centre)) <= span.radius) {
      span.crossing.push_back(j);
      continue;
    }
    const int sj = sign(eq[j], centre);
    span.base.first ^= z.a[j][std::size_t(sj + 1)];
    span.base.second ^= z.b[j][std::size_t(sj + 1)];
  }
  return span;
}

/// Ring r (ringId: 0 the outer ring, h + 1 hole h) of section s of plane i: its vertices about one
/// spacing apart, and its crossings with the traces of the planes that cross the section.
void addContourPoints(const std::vector<CuttingPlane>& planes, const std::vector<K::Plane_3>& eq, std::size_t i,
                      std::size_t s, const Ring& r, int ringId, const std::vector<std::size_t>& crossing,
                      double spacing, std::vector<SectionPoint>& P) {
  const CuttingPlane& cp = planes[i];
    double run = spacing;  // contour vertices kept about one spacing apart
    for (std::size_t v = 0; v < r.size(); ++v) {
      if (run >= spacing) {
        P.push_back({int(i), int(s), r[v], SectionPoint::vertex, {-1, -1}});
        P.back().ring = ringId;
        P.back().along = double(v);
        run = 0;
      }
      run += (r[(v + 1) % r.size()] - r[v]).norm();
      // Contour points on the traces of other planes crossed by edge (v, v+1).
      const Vec3 a = cp.plane.toWorld(r[v]), b = cp.plane.toWorld(r[(v + 1) % r.size()]);
      const auto addTrace = [&](std::size_t j, double t) {  // at r[v] + t (r[v + 1] - r[v])
        P.push_back({int(i), int(s), t == 0 ? r[v] : Vec2(r[v] + t * (r[(v + 1) % r.size()] - r[v])),
                     SectionPoint::trace, {-1, -1}, int(j)});
        P.back().ring = ringId;
        P.back().along = double(v) + t;
      };
      for (const std::size_t j : crossing) {
        const int sa = sign(eq[j], a), sb = sign(eq[j], b);
        if (sa == 0) {
          // The contour meets plane j at vertex v itself (pixel contours and planes on the
          // pixel grid): the crossing is that vertex, a trace point like any other, bounding
          // the cells on both sides of j. Otherwise no point would mark the crossing (the
          // edges on either side have sign products 0) and the vertex, if sampled, would bound
          // the cells on j's positive side only.
          addTrace(j, 0.0);
          continue;
        }
        if (sa * sb >= 0) continue;
        // The exact signs say the edge crosses plane j; the rounded distances may not (both
        // about 0 when the planes nearly coincide, e.g. a frame listed twice): the crossing is
        // then taken at the edge's midpoint, never at 0/0.
        const double da = planes[j].plane.signedDistance(a), db = planes[j].plane.signedDistance(b);
        const double q = da / (da - db);
        const double t = std::isfinite(q) ? std::clamp(q, 0.0, 1.0) : 0.5;
        addTrace(j, t);
      }
    }
}

/// Lattice points inside the section, row by row: between pairs of sorted crossings of the
/// row with the rings (even-odd rule, half-open in y as in ringContains).
void addLatticeSamples(std::size_t i, std::size_t s, const Section& sec, const SectionSpan& span, double spacing,
                       std::vector<SectionPoint>& P) {
  const Vec2 lo = span.lo, hi = span.hi;
  std::vector<double> xs;
  for (double y = std::floor(lo.y() / spacing) * spacing + 0.5 * spacing; y < hi.y(); y += spacing) {
    xs.clear();
    const auto cross = [&](const Ring& r) {
      for (std::size_t v = 0; v < r.size(); ++v) {
        const Vec2& a = r[v];
        const Vec2& b = r[(v + 1) % r.size()];
        if ((a.y() > y) != (b.y() > y)) xs.push_back(a.x() + (y - a.y()) / (b.y() - a.y()) * (b.x() - a.x()));
      }
    };
    cross(sec.outer);
    for (const Ring& h : sec.holes) cross(h);
    std::sort(xs.begin(), xs.end());
    const double x0 = std::floor(lo.x() / spacing) * spacing + 0.5 * spacing;
    for (std::size_t q = 0; q + 1 < xs.size(); q += 2) {
      const double first = x0 + std::ceil((xs[q] - x0) / spacing) * spacing;
      for (double x = first; x < xs[q + 1]; x += spacing)
        if (x > xs[q]) P.push_back({int(i), int(s), Vec2(x, y), SectionPoint::sample, {-1, -1}});
    }
  }
}

/// Each point's keys: the sign vector of the cell on each side of its plane (and, for a trace
/// point, on each side of the trace's plane), hashed (Zobrist) from its section's base key and its
/// signs against the crossing planes.
std::vector<PointKeys> pointKeys(const std::vector<CuttingPlane>& planes, const std::vector<K::Plane_3>& eq,
                                 const Zobrist& z, std::size_t i, const std::vector<SectionPoint>& P,
                                 const std::vector<SectionSpan>& spans, PencilCrossings& pencil) {
  const CuttingPlane& cp = planes[i];
  std::vector<PointKeys> KK;
  KK.resize(P.size());
  for (std::size_t q = 0; q < P.size(); ++q) {
    const Vec3 w = cp.plane.toWorld(P[q].p);
    const std::size_t sec = std::size_t(P[q].section);
    std::uint64_t ha = spans[sec].base.first, hb = spans[sec].base.second;
    if (P[q].trace_plane >= 0)
      notePencilCrossing(planes, i, std::size_t(P[q].trace_plane), spans[sec].crossing, w, spans[sec].radius,
                         pencil);
    for (const std::size_t j : spans[sec].crossing) {
      // On another plane (trace points by construction, or vertices lying exactly on it): the
      // point bounds the cells on both sides; keys are made for the positive side (and, for a
      // trace point, below for the negative one too).
      int sj = int(j) == P[q].trace_plane ? 1 : sign(eq[j], w);
      if (sj == 0) sj = 1;
      ha ^= z.a[j][std::size_t(sj + 1)];
      hb ^= z.b[j][std::size_t(sj + 1)];
    }
    KK[q].minus = {ha ^ z.a[i][0], hb ^ z.b[i][0]};
    KK[q].plus = {ha ^ z.a[i][2], hb ^ z.b[i][2]};
    if (P[q].trace_plane >= 0) {  // swap the trace plane's sign from + to -
      const std::size_t t = std::size_t(P[q].trace_plane);
      const std::uint64_t da = z.a[t][2] ^ z.a[t][0], db = z.b[t][2] ^ z.b[t][0];
      KK[q].minusAlt = {KK[q].minus.first ^ da, KK[q].minus.second ^ db};
      KK[q].plusAlt = {KK[q].plus.first ^ da, KK[q].plus.second ^ db};
    }
  }
  return KK;
}

/// The cells numbered in the order the points meet them (hash maps: lookups do not grow with the
/// cells met), the points given their cells, and the sub-sections counted.
SectionArrangement numberCells(const std::vector<std::vector<SectionPoint>>& pts,
                               const std::vector<std::vector<PointKeys>>& keys, const std::vector<PencilCrossings>& pencils,
                               std::shared_ptr<ArrangementKeys> cellKeys, double spacing) {
  const std::size_t k = pts.size();
  SectionArrangement out;
  out.sample_spacing_mm = spacing;
  struct SubHash {
    std::size_t operator()(const std::array<int, 4>& a) const {
      std::uint64_t h = 0x9e3779b97f4a7c15ULL;
      for (const int v : a) h = (h ^ std::uint64_t(std::uint32_t(v))) * 0xff51afd7ed558ccdULL;
      return std::size_t(h ^ (h >> 29));
    }
  };
  std::unordered_map<Key, int, KeyHash>& cellOf = cellKeys->cellOf;
  std::unordered_map<std::array<int, 4>, int, SubHash> subOf;  // (plane, section, side, cell) -> sub-section
  for (std::size_t i = 0; i < k; ++i)
    for (std::size_t q = 0; q < pts[i].size(); ++q) {
      SectionPoint sp = pts[i][q];
      out.trace_points += sp.kind == SectionPoint::trace;
      for (int variant = 0; variant < (sp.trace_plane >= 0 ? 4 : 2); ++variant) {
        const int side = variant % 2;
        const PointKeys& pk = keys[i][q];
        const Key key = variant == 0 ? pk.minus : variant == 1 ? pk.plus : variant == 2 ? pk.minusAlt : pk.plusAlt;
        const auto it = cellOf.emplace(key, int(cellOf.size())).first;
        (variant < 2 ? sp.cell : sp.cell_alt)[std::size_t(side)] = it->second;
        const std::array<int, 4> sk{sp.plane, sp.section, side == 0 ? -1 : 1, it->second};
        const auto sit = subOf.find(sk);
        if (sit == subOf.end()) {
          subOf.emplace(sk, int(out.sub_sections.size()));
          out.sub_sections.push_back({sp.plane, sp.section, sk[2], it->second, 1});
        } else {
          ++out.sub_sections[std::size_t(sit->second)].points;
        }
      }
      out.points.push_back(sp);
    }
  for (const PencilCrossings& pc : pencils) {  // in plane order: the example does not depend on threads
    if (out.pencil_crossings == 0 && pc.count > 0) out.pencil_planes = pc.example;
    out.pencil_crossings += pc.count;
  }
  out.cells = int(cellOf.size());
  cellKeys->keyOf.resize(cellOf.size());
  for (const auto& [key, id] : cellOf) cellKeys->keyOf[std::size_t(id)] = key;
  out.keys = std::move(cellKeys);
  return out;
}

SectionArrangement arrangeSections(const std::vector<CuttingPlane>& planes, double spacing) {
  if (!(spacing > 0)) throw std::invalid_argument("arrangement: sample spacing must be positive");
  const std::size_t k = planes.size();
  std::vector<K::Plane_3> eq(k);
  for (std::size_t i = 0; i < k; ++i) {
    const Vec3 n = planes[i].plane.normal;
    eq[i] = K::Plane_3(n.x(), n.y(), n.z(), -n.dot(planes[i].plane.origin));
  }
  auto cellKeys = std::make_shared<ArrangementKeys>(k);
  cellKeys->eq = eq;
  const Zobrist& z = cellKeys->z;

  // Points of each plane's sections, and their keys, computed per plane in parallel.
  std::vector<std::vector<SectionPoint>> pts(k);
  std::vector<std::vector<PointKeys>> keys(k);
  std::vector<PencilCrossings> pencils(k);
  tbb::parallel_for(std::size_t(0), k, [&](std::size_t i) {
    const CuttingPlane& cp = planes[i];
    std::vector<SectionSpan> spans;
    spans.reserve(cp.sections.size());
    for (std::size_t s = 0; s < cp.sections.size(); ++s) {
      const Section& sec = cp.sections[s];
      spans.push_back(spanOf(planes, eq, z, i, sec));
      addContourPoints(planes, eq, i, s, sec.outer, 0, spans.back().crossing, spacing, pts[i]);
      for (std::size_t h = 0; h < sec.holes.size(); ++h)
        addContourPoints(planes, eq, i, s, sec.holes[h], int(h) + 1, spans.back().crossing, spacing, pts[i]);
      addLatticeSamples(i, s, sec, spans.back(), spacing, pts[i]);
    }
    keys[i] = pointKeys(planes, eq, z, i, pts[i], spans, pencils[i]);
  });
  return numberCells(pts, keys, pencils, std::move(cellKeys), spacing);
}

CellKey cellKey(const SectionArrangement& arr, int cell) {
  if (!arr.keys || cell < 0 || cell >= arr.cells) throw std::invalid_argument("cellKey: no such cell");
  const Key& k = arr.keys->keyOf[std::size_t(cell)];
  return {k.first, k.second};
}

CellKey keyAcross(const SectionArrangement& arr, const CellKey& key, int plane) {
  if (!arr.keys || plane < 0 || std::size_t(plane) >= arr.keys->z.a.size())
    throw std::invalid_argument("keyAcross: no such plane");
  const Zobrist& z = arr.keys->z;
  const std::size_t j = std::size_t(plane);
  return {key[0] ^ z.a[j][0] ^ z.a[j][2], key[1] ^ z.b[j][0] ^ z.b[j][2]};
}

int cellOfKey(const SectionArrangement& arr, const CellKey& key) {
  if (!arr.keys) return -1;
  const auto it = arr.keys->cellOf.find({key[0], key[1]});
  return it == arr.keys->cellOf.end() ? -1 : it->second;
}

CellsAround cellsAround(const SectionArrangement& arr, const std::vector<CuttingPlane>& planes, const Vec3& x,
                        const std::vector<int>& on) {
  if (!arr.keys || on.empty() || on.size() > 3) throw std::invalid_argument("cellsAround: 1 to 3 planes");
  const ArrangementKeys& ck = *arr.keys;
  std::uint64_t ha = 0, hb = 0;
  for (std::size_t j = 0; j < planes.size(); ++j) {
    if (std::find(on.begin(), on.end(), int(j)) != on.end()) continue;
    int sj = sign(ck.eq[j], x);
    if (sj == 0) sj = 1;  // as the arrangement's points do
    ha ^= ck.z.a[j][std::size_t(sj + 1)];
    hb ^= ck.z.b[j][std::size_t(sj + 1)];
  }
  CellsAround out;
  out.cells.assign(std::size_t(1) << on.size(), -1);
  out.keys.resize(out.cells.size());
  for (std::size_t m = 0; m < out.cells.size(); ++m) {
    std::uint64_t a = ha, b = hb;
    for (std::size_t q = 0; q < on.size(); ++q) {
      const std::size_t sgn = (m >> q & 1) ? 2 : 0;
      a ^= ck.z.a[std::size_t(on[q])][sgn];
      b ^= ck.z.b[std::size_t(on[q])][sgn];
    }
    out.keys[m] = {a, b};
    const auto it = ck.cellOf.find({a, b});
    if (it != ck.cellOf.end()) out.cells[m] = it->second;
  }
  return out;
}

CellKey cellKeyAt(const SectionArrangement& arr, const std::vector<CuttingPlane>& planes, const Vec3& x) {
  if (!arr.keys) throw std::invalid_argument("cellKeyAt: an arrangement without keys");
  const ArrangementKeys& ck = *arr.keys;
  std::uint64_t a = 0, b = 0;
  for (std::size_t j = 0; j < planes.size(); ++j) {
    int sj = sign(ck.eq[j], x);
    if (sj == 0) sj = 1;
    a ^= ck.z.a[j][std::size_t(sj + 1)];
    b ^= ck.z.b[j][std::size_t(sj + 1)];
  }
  return {a, b};
}

}  // namespace xsect

// Splitting the mesh along the cutting planes and moving the cut onto the contours
// (see conformal_cut.h).
#include "geometry/meshing/conformal_cut.h"

#include <tbb/parallel_for.h>

#include <array>
#include <cmath>
#include <limits>
#include <new>
#include <unordered_map>

namespace xsect {

namespace {

constexpr int kMaxPlanesPerVertex = 3;

struct PlaneTags {
  std::array<int, kMaxPlanesPerVertex> id{-1, -1, -1};
  int count = 0;
  void add(int p) {
    for (int k = 0; k < count; ++k)
      if (id[k] == p) return;
    if (count < kMaxPlanesPerVertex) id[count++] = p;
    else count = kMaxPlanesPerVertex + 1;  // on too many planes: never moved
  }
};

/// Newton steps on g(t) = f_P(x + t d) for a unit direction d, with the bilinear interpolant's own
/// derivative; returns the new point or false.
bool newtonAlong(const CuttingPlane& cp, const SectionDistanceField& f, Vec3 x, const Vec3& d,
                 double maxMove, Vec3* out) {
  const Plane& P = cp.plane;
  const Vec2 start = P.toPlane(x), along(d.dot(P.u), d.dot(P.v));  // d within the plane's frame
  double t = 0;
  for (int it = 0; it < 6; ++it) {
    const Vec2 q = start + t * along;
    Vec2 grad;
    const double v = f.sampleWithGradient(q.x(), q.y(), &grad);
    if (std::abs(v) >= f.band) return false;
    const double g = grad.dot(along);
    if (std::abs(g) < 1e-3) return false;
    t -= v / g;
    if (std::abs(t) > maxMove) return false;
  }
  const Vec2 q = start + t * along;
  if (std::abs(f.sample(q.x(), q.y())) > 1e-3 * f.step) return false;
  *out = x + t * d;
  return true;
}

/// Newton steps within the plane, with the bilinear interpolant's own gradient.
bool newtonInPlane(const CuttingPlane& cp, const SectionDistanceField& f, const Vec3& x,
                   double maxMove, Vec3* out) {
  const Plane& P = cp.plane;
  const Vec2 start = P.toPlane(x);
  Vec2 q = start;
  for (int it = 0; it < 6; ++it) {
    Vec2 g;
    const double v = f.sampleWithGradient(q.x(), q.y(), &g);
    if (std::abs(v) >= f.band) return false;
    const double g2 = g.squaredNorm();
    if (g2 < 1e-6) return false;
    q -= v * g / g2;
  }
  if ((q - start).norm() > maxMove || std::abs(f.sample(q.x(), q.y())) > 1e-3 * f.step) return false;
  *out = x + (q.x() - start.x()) * P.u + (q.y() - start.y()) * P.v;
  return true;
}

/// The mesh being cut: vertices in double precision, triangles, and the planes each vertex lies
/// on.
struct CutMesh {
  std::vector<Vec3> V;
  std::vector<std::array<std::uint32_t, 3>> T;
  std::vector<PlaneTags> tags;
};

// Triangles bucketed by centroid in cells of 8 voxels (a split triangle's pieces stay in its
// cell). For a plane P only the cells whose centre is within `reach` of P can hold a triangle
// that touches P: reach = half the cell diagonal + the largest centroid-to-vertex distance.
// This keeps the cost per plane proportional to the mesh near it, not to the whole mesh.
// Each entry also holds the triangle's bounding sphere, relative to its cell's centre, so that a
// plane skips the triangles of a cell it does not meet with one distance instead of three
// (issue 17: 6.5 M triangles and 2000 planes). The sphere is kept in 16-bit units, 12 bytes an
// entry instead of 20 (issue 17: the entries were a quarter of the peak memory of a 4000-frame
// sweep): a centroid lies within half a cell plus lmax of its cell's centre along each axis (a
// piece of a split triangle lies in the original, whose centroid is in the cell), a radius below
// 2 lmax (the original's diameter), lmax the longest centroid-to-vertex distance of the
// original triangles; the offsets are rounded to the nearest unit, the radii up, and the skip test
// below widens by the rounding.
struct TriangleBuckets {
  struct Entry {
    std::uint32_t t;
    std::int16_t cx, cy, cz;
    std::uint16_t r;
  };
  Vec3 lo;
  double cell = 0, lmax = 0, unitC = 0, unitR = 0;
  std::array<int, 3> dims{1, 1, 1};
  std::vector<std::vector<Entry>> lists;

  Vec3 centre(int cx, int cy, int cz) const { return lo + cell * Vec3(cx + 0.5, cy + 0.5, cz + 0.5); }
  Vec3 centre(std::size_t b) const {
    const std::size_t cx = b % std::size_t(dims[0]), cy = (b / std::size_t(dims[0])) % std::size_t(dims[1]),
                      cz = b / (std::size_t(dims[0]) * std::size_t(dims[1]));
    return Vec3(lo + cell * Vec3(double(cx) + 0.5, double(cy) + 0.5, double(cz) + 0.5));
  }
  /// Triangle t's entry in the bucket of centre `centre`.
  Entry entry(const CutMesh& m, std::uint32_t t, const Vec3& centre) const {
    const Vec3 c = (m.V[m.T[t][0]] + m.V[m.T[t][1]] + m.V[m.T[t][2]]) / 3.0;
    double r = 0;
    for (const auto v : m.T[t]) r = std::max(r, (m.V[v] - c).norm());
    const Vec3 d = (c - centre) / unitC;
    const auto unit = [](double x) { return std::int16_t(std::clamp(std::lround(x), -32767L, 32767L)); };
    return Entry{t, unit(d.x()), unit(d.y()), unit(d.z()), std::uint16_t(std::min(65535.0, std::ceil(r / unitR)))};
  }
};

TriangleBuckets bucketTriangles(const CutMesh& m, double voxel) {
  TriangleBuckets B;
  const std::vector<Vec3>& V = m.V;
  const auto& T = m.T;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& v : V) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  B.lo = lo;
  B.cell = 8 * voxel;
  if (!V.empty())
    for (int a = 0; a < 3; ++a) B.dims[a] = int((hi[a] - lo[a]) / B.cell) + 1;
  for (std::uint32_t t = 0; t < T.size(); ++t) {
    const Vec3 c = (V[T[t][0]] + V[T[t][1]] + V[T[t][2]]) / 3.0;
    for (const auto v : T[t]) B.lmax = std::max(B.lmax, (V[v] - c).norm());
  }
  B.unitC = (B.cell + 2 * B.lmax) / 32767.0;
  B.unitR = (B.cell + 2 * B.lmax) / 65535.0;
  B.lists.resize(std::size_t(B.dims[0]) * B.dims[1] * B.dims[2]);
  for (std::uint32_t t = 0; t < T.size(); ++t) {
    const Vec3 c = (V[T[t][0]] + V[T[t][1]] + V[T[t][2]]) / 3.0;
    std::array<int, 3> q;
    for (int a = 0; a < 3; ++a) q[a] = std::min(B.dims[a] - 1, int((c[a] - lo[a]) / B.cell));
    const std::size_t b = (std::size_t(q[2]) * B.dims[1] + q[1]) * B.dims[0] + q[0];
    B.lists[b].push_back(B.entry(m, t, B.centre(b)));
  }
  return B;
}

/// What the walk over the planes keeps per vertex (the signed distance to the current plane,
/// its sign, the plane it was computed for) and per plane (the vertex made on each cut edge).
struct PlaneWalk {
  std::vector<double> s;
  std::vector<signed char> sign;  // -1, 0 (on P), +1: a byte a vertex
  std::vector<int> stamp;
  std::unordered_map<std::uint64_t, std::uint32_t> edgeVertex;
};

/// Splits the triangles that cross plane p (those of the buckets within reach) and snaps the
/// vertices within eps of it onto it, tagging them with p. Returns whether a triangle crossed.
bool cutByPlane(std::size_t p, const CuttingPlane& cp, double eps, double reach, double skip, CutMesh& m,
                TriangleBuckets& B, PlaneWalk& w, ConformalCutStats& stats) {
  std::vector<Vec3>& V = m.V;
  auto& T = m.T;
  std::vector<PlaneTags>& tags = m.tags;
  std::vector<double>& s = w.s;
  std::vector<signed char>& sign = w.sign;
  std::vector<int>& stamp = w.stamp;
  auto& edgeVertex = w.edgeVertex;
  const Vec3& lo = B.lo;
  const double cell = B.cell, unitC = B.unitC, unitR = B.unitR;
  const std::array<int, 3>& dims = B.dims;
  const Plane& P = cp.plane;
  const auto prepare = [&](std::uint32_t i) {  // signed distance to P, once per plane
    if (stamp[i] == int(p)) return;
    stamp[i] = int(p);
    s[i] = P.signedDistance(V[i]);
    if (std::abs(s[i]) < eps) {
      if (tags[i].count == 0) V[i] -= s[i] * P.normal;  // put it on the plane
      tags[i].add(int(p));
      s[i] = 0;
      sign[i] = 0;
    } else {
      sign[i] = s[i] > 0 ? 1 : -1;
    }
  };
  edgeVertex.clear();
  const auto cut = [&](std::uint32_t a, std::uint32_t b) -> std::uint32_t {
    const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
    const auto it = edgeVertex.find(key);
    if (it != edgeVertex.end()) return it->second;
    Vec3 x = V[a] + s[a] / (s[a] - s[b]) * (V[b] - V[a]);
    x -= P.signedDistance(x) * P.normal;
    const std::uint32_t id = std::uint32_t(V.size());
    V.push_back(x);
    tags.emplace_back();
    tags.back().add(int(p));
    s.push_back(0);
    sign.push_back(0);
    stamp.push_back(int(p));
    edgeVertex.emplace(key, id);
    ++stats.vertices_added;
    return id;
  };
  bool crosses = false;
  const double step = cell * P.normal.x();  // change of the distance from one cell to the next along x
  for (int cz = 0; cz < dims[2]; ++cz)
    for (int cy = 0; cy < dims[1]; ++cy) {
      // The cells of the row within reach lie in one run of cx (the distance is linear in cx):
      // that run, widened by a cell against rounding, is tested cell by cell below.
      double first = 0, last = dims[0] - 1;  // clamped as doubles: the run may lie far off the row
      const double s0 = P.signedDistance(lo + cell * Vec3(0.5, cy + 0.5, cz + 0.5));
      if (std::abs(step) > 1e-12 * cell) {
        const double u = (-reach - s0) / step, w = (reach - s0) / step;
        first = std::max(first, std::floor(std::min(u, w)) - 1);
        last = std::min(last, std::ceil(std::max(u, w)) + 1);
      }
      if (first > last) continue;  // no cell of the row within reach (both now on the row)
      for (int cx = int(first); cx <= int(last); ++cx) {
        const std::size_t b = (std::size_t(cz) * dims[1] + cy) * dims[0] + cx;
        const Vec3 centre = lo + cell * Vec3(cx + 0.5, cy + 0.5, cz + 0.5);
        const double sc = P.signedDistance(centre);
        if (std::abs(sc) > reach) continue;
        auto& list = B.lists[b];
        const std::size_t n = list.size();  // pieces added below are already split by P
        const Vec3 nu = unitC * P.normal;  // the normal in the entries' units
        for (std::size_t k = 0; k < n; ++k) {
          const TriangleBuckets::Entry& en = list[k];
          if (std::abs(sc + nu.x() * en.cx + nu.y() * en.cy + nu.z() * en.cz) > unitR * en.r + skip) continue;
          const std::uint32_t t = en.t;
          const auto tri = T[t];
          for (const auto v : tri) prepare(v);
          const int sg[3] = {sign[tri[0]], sign[tri[1]], sign[tri[2]]};
          const int zeros = (sg[0] == 0) + (sg[1] == 0) + (sg[2] == 0);
          if (zeros == 0) {
            // one vertex alone on its side: three triangles
            int lone = -1;
            for (int q = 0; q < 3; ++q)
              if (sg[q] != sg[(q + 1) % 3] && sg[q] != sg[(q + 2) % 3]) lone = q;
            if (lone < 0) continue;
            const std::uint32_t a = tri[lone], b = tri[(lone + 1) % 3], c = tri[(lone + 2) % 3];
            const std::uint32_t pab = cut(a, b), pac = cut(a, c);
            T[t] = {a, pab, pac};
            list[k] = B.entry(m, t, centre);
            T.push_back({pab, b, c});
            list.push_back(B.entry(m, std::uint32_t(T.size() - 1), centre));
            T.push_back({pab, c, pac});
            list.push_back(B.entry(m, std::uint32_t(T.size() - 1), centre));
            crosses = true;
          } else if (zeros == 1) {
            int z = 0;
            while (sg[z] != 0) ++z;
            const std::uint32_t a = tri[z], b = tri[(z + 1) % 3], c = tri[(z + 2) % 3];
            if (sign[b] == sign[c]) continue;
            const std::uint32_t pbc = cut(b, c);
            T[t] = {a, b, pbc};
            list[k] = B.entry(m, t, centre);
            T.push_back({a, pbc, c});
            list.push_back(B.entry(m, std::uint32_t(T.size() - 1), centre));
            crosses = true;
          }
        }
      }
    }
  return crosses;
}

/// Triangles around each vertex, in compressed rows: those of vertex v are incident[first[v] ..
/// first[v + 1]).
struct VertexTriangles {
  std::vector<std::uint32_t> first, incident;
};

VertexTriangles vertexTriangles(const CutMesh& m) {
  VertexTriangles a;
  a.first.assign(m.V.size() + 1, 0);
  a.incident.resize(3 * m.T.size());
  for (const auto& t : m.T)
    for (const auto v : t) ++a.first[v + 1];
  for (std::size_t v = 0; v < m.V.size(); ++v) a.first[v + 1] += a.first[v];
  std::vector<std::uint32_t> fill(a.first.begin(), a.first.end() - 1);
  for (std::uint32_t t = 0; t < m.T.size(); ++t)
    for (const auto v : m.T[t]) a.incident[fill[v]++] = t;
  return a;
}

/// Each vertex's move onto the contours, and its status (1 = move, -1 = on a plane, no contour in
/// reach, 0 = none).
struct ContourMoves {
  std::vector<Vec3> move;
  std::vector<signed char> status;
};

ContourMoves contourMoves(const CutMesh& m, const VertexTriangles& a, const std::vector<CuttingPlane>& planes,
                          const std::vector<SectionDistanceField>& fields, double voxel) {
  const std::vector<Vec3>& V = m.V;
  const auto& T = m.T;
  const std::vector<PlaneTags>& tags = m.tags;
  const std::vector<std::uint32_t>& first = a.first;
  const std::vector<std::uint32_t>& incident = a.incident;
  ContourMoves out;
  std::vector<Vec3>& move = out.move;
  std::vector<signed char>& status = out.status;
// Displacements, computed in parallel from the unmoved mesh. A vertex on one plane moves within
// it onto the contour; on two planes, along their common line. A vertex off the planes but
// within a voxel of a plane that one of its neighbours (two rings) lies on moves within that
// plane by the same contour displacement scaled by (1 - t / voxel), t its distance to the plane:
// the neighbourhood of the cut follows it smoothly instead of folding under it.
move.assign(V.size(), Vec3::Zero());
status.assign(V.size(), 0);
tbb::parallel_for(std::size_t(0), V.size(), [&](std::size_t i) {
  const PlaneTags& g = tags[i];
  Vec3 y;
  if (g.count == 1 || g.count == 2) {
    bool ok = false;
    if (g.count == 1) {
      ok = newtonInPlane(planes[g.id[0]], fields[g.id[0]], V[i], voxel, &y);
    } else {
      const Vec3 d = planes[g.id[0]].plane.normal.cross(planes[g.id[1]].plane.normal);
      if (d.norm() > 1e-6)
        ok = newtonAlong(planes[g.id[0]], fields[g.id[0]], V[i], d.normalized(), voxel, &y);
    }
    status[i] = ok ? 1 : -1;
    if (ok) move[i] = y - V[i];
    return;
  }
  if (g.count != 0) return;
  int best = -1;
  double bestT = voxel;
  const auto consider = [&](std::uint32_t v) {
    if (tags[v].count != 1) return;
    const int p = tags[v].id[0];
    const double t = std::abs(planes[p].plane.signedDistance(V[i]));
    if (t < bestT) bestT = t, best = p;
  };
  for (std::uint32_t k = first[i]; k < first[i + 1]; ++k)
    for (const auto v1 : T[incident[k]]) {
      consider(v1);
      for (std::uint32_t k2 = first[v1]; k2 < first[v1 + 1]; ++k2)
        for (const auto v2 : T[incident[k2]]) consider(v2);
    }
  if (best < 0) return;
  const Plane& P = planes[best].plane;
  const Vec3 foot = V[i] - P.signedDistance(V[i]) * P.normal;
  if (!newtonInPlane(planes[best], fields[best], foot, voxel, &y)) return;
  move[i] = (1.0 - bestT / voxel) * (y - foot);
  status[i] = 1;
});
  return out;
}

/// Applies the moves and counts them into `stats`.
void applyMoves(CutMesh& m, const VertexTriangles& a, const ContourMoves& moves, ConformalCutStats& stats) {
  std::vector<Vec3>& V = m.V;
  const auto& T = m.T;
  const std::vector<PlaneTags>& tags = m.tags;
  const std::vector<std::uint32_t>& first = a.first;
  const std::vector<std::uint32_t>& incident = a.incident;
  const std::vector<Vec3>& move = moves.move;
  const std::vector<signed char>& status = moves.status;
// Moves applied in order, off-plane vertices first, then plane vertices (deterministic); each
// move is shortened (halved up to 4 times, else dropped) when it would turn an incident triangle
// against its original orientation: the surface stays free of folds.
const auto normal = [&](const std::array<std::uint32_t, 3>& t) {
  return (V[t[1]] - V[t[0]]).cross(V[t[2]] - V[t[0]]);
};
std::vector<Eigen::Vector3f> originalNormal(T.size());  // float: only the sign of a product is asked
tbb::parallel_for(std::size_t(0), T.size(), [&](std::size_t t) { originalNormal[t] = normal(T[t]).cast<float>(); });
const auto apply = [&](std::size_t i) -> int {  // halvings used, or -1 if no move fits
  const Vec3 from = V[i];
  for (int halving = 0; halving <= 4; ++halving) {
    V[i] = from + std::ldexp(1.0, -halving) * move[i];
    bool ok = true;
    for (std::uint32_t k = first[i]; k < first[i + 1] && ok; ++k) {
      const std::uint32_t t = incident[k];
      const Vec3 n0 = originalNormal[t].cast<double>();
      ok = normal(T[t]).dot(n0) > 0.1 * n0.squaredNorm();
    }
    if (ok) return halving;
  }
  V[i] = from;
  return -1;
};
for (std::size_t i = 0; i < V.size(); ++i)
  if (status[i] == 1 && tags[i].count == 0) apply(i);
for (std::size_t i = 0; i < V.size(); ++i) {
  if (tags[i].count == 0) continue;
  if (status[i] != 1) {
    ++stats.vertices_unsnapped;
    continue;
  }
  const int halvings = apply(i);
  if (halvings < 0) {
    ++stats.vertices_unsnapped;
    continue;
  }
  ++(halvings == 0 ? stats.vertices_snapped : stats.vertices_shortened);
  stats.max_move_mm = std::max(stats.max_move_mm, std::ldexp(1.0, -halvings) * move[i].norm());
}
}

}  // namespace

ConformalCutStats cutAlongSections(TriangleMesh& mesh, const std::vector<CuttingPlane>& planes,
                                   const std::vector<SectionDistanceField>& fields, double voxel) {
  ConformalCutStats stats;
  CutMesh m;
  m.V.resize(mesh.vertices.size());
  for (std::size_t i = 0; i < m.V.size(); ++i) m.V[i] = mesh.vertices[i].cast<double>();
  m.T = std::move(mesh.triangles);
  m.tags.resize(m.V.size());
  const double eps = 0.02 * voxel;
  TriangleBuckets B = bucketTriangles(m, voxel);
  const double reach = 0.5 * std::sqrt(3.0) * B.cell + B.lmax + 2 * eps;
  // A triangle whose centre is farther from P than its radius plus 2 eps has no vertex within eps
  // of P (where vertices are snapped onto it, each once, by less than eps) and no vertex on the
  // other side: it is neither cut nor snapped, and is skipped. The rounding of the entry's centre
  // (half a unit along each axis: at most sqrt(3)/2 units along P's normal) widens the margin, with
  // a third eps for the rounding of the arithmetic.
  const double skip = 3 * eps + std::sqrt(3.0) * 0.5 * B.unitC;

  PlaneWalk w;
  w.s.resize(m.V.size());
  w.sign.resize(m.V.size());
  w.stamp.assign(m.V.size(), -1);
  // The walk grows the vertex and triangle arrays several fold (a dense sweep: 6 to 9 times).
  // Growing by reallocation holds the old and the new copy at once, and the last doubling of the
  // triangles set the run's peak on a 4000-frame sweep (issue 17): room for 16 times the start is
  // reserved instead. Reserved pages that are never written are never resident (large blocks
  // come from mmap), so the room costs address space, not memory; past it, vectors grow as usual.
  // Address space the system refuses (an allocation beyond what it would ever commit) only loses
  // the room: the vectors then grow as usual.
  constexpr std::size_t kRoom = 16;
  try {
    m.V.reserve(kRoom * m.V.size());
    m.tags.reserve(kRoom * m.tags.size());
    w.s.reserve(kRoom * w.s.size());
    w.sign.reserve(kRoom * w.sign.size());
    w.stamp.reserve(kRoom * w.stamp.size());
    m.T.reserve(kRoom * m.T.size());
  } catch (const std::bad_alloc&) {
  }
  for (std::size_t p = 0; p < planes.size(); ++p)
    if (!planes[p].sections.empty()) stats.planes_cut += cutByPlane(p, planes[p], eps, reach, skip, m, B, w, stats);

  // What the plane walk needed is given back before the moves' arrays are made (issue 17: the
  // mesh stage holds the run's peak memory).
  decltype(B.lists)().swap(B.lists);
  std::vector<double>().swap(w.s);
  std::vector<signed char>().swap(w.sign);
  std::vector<int>().swap(w.stamp);

  const VertexTriangles adjacency = vertexTriangles(m);
  applyMoves(m, adjacency, contourMoves(m, adjacency, planes, fields, voxel), stats);
  mesh.triangles = std::move(m.T);
  mesh.vertices.resize(m.V.size());
  for (std::size_t i = 0; i < m.V.size(); ++i) mesh.vertices[i] = m.V[i].cast<float>();
  return stats;
}

}  // namespace xsect

// Ω-cells on the scan's lattice (see observed_cells.h).
#include "geometry/sampling/observed_cells.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_map>
#include <utility>

#include "geometry/core/disjoint_sets.h"

namespace xsect {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// A lattice row's signed distances to the planes, s_j(i) = a_j + b_j·i, i the point's index along
/// the row (as the scan takes them), and per point the planes within `spacing` of it (those whose
/// |s_j| ≤ spacing on an interval of i: the only planes an edge from the point can cross).
struct RowDistances {
  std::vector<double> a, b;
  Eigen::ArrayXf af, bf;               ///< the same in floats, for the nearest plane
  std::vector<std::size_t> near_start; ///< per point i: its near planes are near[near_start[i] ..]
  std::vector<std::size_t> near;
  RowDistances(const std::vector<Plane>& planes, const Vec3& start, double spacing, int nx)
      : a(planes.size()), b(planes.size()), af(Eigen::Index(planes.size())), bf(Eigen::Index(planes.size())),
        near_start(std::size_t(nx) + 1, 0) {
    std::vector<std::array<int, 2>> span(planes.size(), {0, -1});
    for (std::size_t j = 0; j < planes.size(); ++j) {
      a[j] = planes[j].signedDistance(start);
      b[j] = planes[j].normal.x() * spacing;
      af[Eigen::Index(j)] = float(a[j]);
      bf[Eigen::Index(j)] = float(b[j]);
      // |a + b·i| ≤ spacing (with room for rounding) for i in [i0, i1].
      const double reach = spacing * (1 + 1e-6);
      double lo = -kInf, hi = kInf;
      if (std::abs(b[j]) > 1e-12 * spacing) {
        lo = (-reach - a[j]) / b[j];
        hi = (reach - a[j]) / b[j];
        if (lo > hi) std::swap(lo, hi);
      } else if (std::abs(a[j]) > reach) {
        continue;
      }
      // Clamped before rounding (a plane nearly parallel to the row puts its ends far off).
      const int i0 = int(std::ceil(std::clamp(lo, 0.0, double(nx))));
      const int i1 = int(std::floor(std::clamp(hi, -1.0, double(nx - 1))));
      if (i0 > i1) continue;
      span[j] = {i0, i1};
      for (int i = i0; i <= i1; ++i) ++near_start[std::size_t(i) + 1];
    }
    for (int i = 0; i < nx; ++i) near_start[std::size_t(i) + 1] += near_start[std::size_t(i)];
    near.resize(near_start.back());
    std::vector<std::size_t> fill(near_start.begin(), near_start.end() - 1);
    for (std::size_t j = 0; j < planes.size(); ++j)
      for (int i = span[j][0]; i <= span[j][1]; ++i) near[fill[std::size_t(i)]++] = j;
  }
  double at(std::size_t j, int i) const { return a[j] + b[j] * double(i); }
};

/// D_Ω(x) for the row's point i, given an upper bound of it (+inf: none), and in *lower a lower
/// bound (a field of view's distances are upper bounds: observed_piece.h, ObservedPiece::bounds).
/// Where the nearest plane's piece holds x's projection, D_Ω is that plane's distance (D_Ω ≥ the
/// distance to every plane); otherwise planes farther than the best so far cannot hold the nearest
/// point and are skipped (the plane that does is within the true D_Ω ≤ both bounds, so neither
/// misses it). `room`: space for the point's distances (floats, as the scan's: the nearest plane is
/// the one the scan's rounding finds).
double distanceToPieces(const Vec3& x, const RowDistances& row, int i, double bound, const std::vector<Plane>& planes,
                        const std::vector<ObservedPiece>& pieces, Eigen::ArrayXf& room, double* lower) {
  const std::size_t P = planes.size();
  room = (row.af + row.bf * float(i)).abs();  // vectorised, as the scan's loop
  const float nearest = room.minCoeff();
  std::size_t at = 0;
  while (room[Eigen::Index(at)] != nearest) ++at;
  double low = std::numeric_limits<double>::infinity();
  const auto pieceDistance = [&](std::size_t j) {
    const double s = row.at(j, i);
    if (pieces[j].whole) {
      low = std::min(low, std::abs(s));
      return std::abs(s);
    }
    const Vec2 p = planes[j].toPlane(x);
    double lo, hi;
    pieces[j].bounds(p.x(), p.y(), 0.0, &lo, &hi);
    low = std::min(low, planeNorm(s, lo));
    double na, nb;
    return planeNorm(s, pieces[j].distance(p.x(), p.y(), &na, &nb));
  };
  double best = pieceDistance(at);
  if (best == std::abs(row.at(at, i))) {  // the piece holds x's projection: exact
    *lower = best;
    return best;
  }
  for (std::size_t j = 0; j < P; ++j) {
    if (j == at || std::abs(row.at(j, i)) > std::min(best, bound)) continue;
    best = std::min(best, pieceDistance(j));
  }
  *lower = std::min(low, best);
  return best;
}

/// Whether the segment from the row's lattice point i, p, to its neighbour q = p + spacing·e_axis
/// crosses a piece: some plane it crosses holds the crossing point in its piece (the signs as the
/// scan takes them: positive strictly on the normal's side). `step`: each plane's change of signed
/// distance from p to q. `only`: the one plane the segment crosses, where the cells' keys say so
/// (−1: every plane near p is tried; no other can be crossed).
bool crossesPiece(const Vec3& p, const Vec3& q, const RowDistances& row, int i, const std::vector<double>& step,
                  int only, const std::vector<Plane>& planes, const std::vector<ObservedPiece>& pieces) {
  const auto crossesAt = [&](std::size_t j) {  // the segment crosses plane j
    const double sp = row.at(j, i), sq = sp + step[j];
    if (pieces[j].whole) return true;
    const Vec2 a = planes[j].toPlane(p + sp / (sp - sq) * (q - p));
    return pieces[j].holds(a.x(), a.y());
  };
  if (only >= 0) {
    const double sp = row.at(std::size_t(only), i);
    if ((sp > 0) != (sp + step[std::size_t(only)] > 0)) return crossesAt(std::size_t(only));
  }
  bool crossed = false;
  for (std::size_t k = row.near_start[std::size_t(i)]; k < row.near_start[std::size_t(i) + 1]; ++k) {
    const std::size_t j = row.near[k];
    const double sp = row.at(j, i);
    if ((sp > 0) == (sp + step[j] > 0)) continue;
    crossed = true;
    if (crossesAt(j)) return true;
  }
  // The scan's float signs put p and q in different cells but no plane changes sign in doubles:
  // rounding decided the sides at a point on a plane; the segment is taken as closed there.
  return !crossed;
}

/// Points of plane P just beyond the rectangle of its piece Ω_P, about `spacing` apart (plane
/// coordinates, mm): the rectangle's sides pushed out by a millionth of the spacing.
std::vector<Vec2> beyondRectangle(const PlaneRect& rect, double spacing) {
  std::vector<Vec2> out;
  const double eps = 1e-6 * spacing;
  const Vec2 lo = rect.min - Vec2::Constant(eps), hi = rect.max + Vec2::Constant(eps);
  const int nu = std::max(1, int(std::ceil((hi.x() - lo.x()) / spacing)));
  const int nv = std::max(1, int(std::ceil((hi.y() - lo.y()) / spacing)));
  for (int i = 0; i <= nu; ++i) {
    const double u = lo.x() + (hi.x() - lo.x()) * i / nu;
    out.emplace_back(u, lo.y());
    out.emplace_back(u, hi.y());
  }
  for (int j = 1; j < nv; ++j) {
    const double v = lo.y() + (hi.y() - lo.y()) * j / nv;
    out.emplace_back(lo.x(), v);
    out.emplace_back(hi.x(), v);
  }
  return out;
}

/// The field of view's unobserved raster nodes next to an observed one (those on every k-th row or
/// column, k nodes about `spacing`): points just beyond the piece it bounds.
std::vector<Vec2> beyondFieldOfView(const FieldOfViewRaster& f, double spacing) {
  std::vector<Vec2> out;
  const int k = std::max(1, int(spacing / f.step));
  const auto observed = [&](int i, int j) {
    const std::size_t n = std::size_t(j) * std::size_t(f.nu) + std::size_t(i);
    return f.nearest[n] == std::int32_t(n);
  };
  for (int j = 0; j < f.nv; ++j)
    for (int i = 0; i < f.nu; ++i) {
      if ((i % k != 0 && j % k != 0) || observed(i, j)) continue;
      if ((i > 0 && observed(i - 1, j)) || (i + 1 < f.nu && observed(i + 1, j)) || (j > 0 && observed(i, j - 1)) ||
          (j + 1 < f.nv && observed(i, j + 1)))
        out.push_back(f.point(std::size_t(j) * std::size_t(f.nu) + std::size_t(i)));
    }
  return out;
}


/// Per lattice point, its distance to the union of the pieces (D_Ω, and a lower bound), and per
/// lattice row the pairs of scanned cells a lattice edge from the row joins outside every piece
/// (sorted, unique), with how many edges did.
struct LatticeJoins {
  std::vector<double> distance, lower_distance;
  std::vector<std::vector<std::pair<int, int>>> joins;
  std::vector<std::int64_t> crossings;
};

LatticeJoins latticeJoins(const CellScan& scan, const std::vector<Plane>& planes, const CellKeys& keys,
                          const std::vector<ObservedPiece>& pieces) {
  const GridSpec& L = scan.lattice;
  const int nx = L.dims[0], ny = L.dims[1], nz = L.dims[2];
  const std::size_t n = std::size_t(L.count());
  const double spacing = L.voxel * (1 + 1e-9);  // D_Ω is 1-Lipschitz: a row's neighbour bounds it
  // Two cells whose keys differ by one plane's key lie on either side of that plane alone (but for
  // a collision of 64-bit keys, which the fallback to every plane covers).
  std::unordered_map<std::uint64_t, int> planeOfKey;
  for (std::size_t j = 0; j < planes.size(); ++j) planeOfKey.emplace(keys.key(j), int(j));
  // Per axis, each plane's change of signed distance from a lattice point to its next neighbour.
  std::array<std::vector<double>, 3> steps;
  for (int axis = 0; axis < 3; ++axis)
    for (const Plane& plane : planes) steps[std::size_t(axis)].push_back(plane.normal[axis] * L.voxel);
  LatticeJoins r;
  std::vector<double>& distance = r.distance;
  std::vector<double>& lowerDistance = r.lower_distance;
  distance.assign(n, -1.0);
  lowerDistance.assign(n, 0.0);
  // Per row: the pairs of scanned cells that a lattice edge from the row joins (sorted, unique),
  // and how many edges did.
  std::vector<std::vector<std::pair<int, int>>>& joins = r.joins;
  joins.resize(std::size_t(ny) * std::size_t(nz));
  std::vector<std::int64_t>& crossings = r.crossings;
  crossings.assign(joins.size(), 0);
  tbb::parallel_for(0, ny * nz, [&](int row) {
    const int j = row % ny, k = row / ny;
    const RowDistances distances(planes, L.centre(0, j, k), L.voxel, nx);
    Eigen::ArrayXf room(Eigen::Index(planes.size()));
    double previous = -1;  // D_Ω of the row's previous lattice point (−1: outside the box)
    std::vector<std::pair<int, int>>& found = joins[std::size_t(row)];
    for (int i = 0; i < nx; ++i) {
      const std::size_t q = std::size_t(L.index(i, j, k));
      const int cell = scan.cell_of_point[q];
      if (cell < 0) {
        previous = -1;
        continue;
      }
      const Vec3 x = L.centre(i, j, k);
      distance[q] = distanceToPieces(x, distances, i, previous >= 0 ? previous + spacing : kInf, planes, pieces, room,
                                     &lowerDistance[q]);
      previous = distance[q];
      const std::array<std::array<int, 3>, 3> ahead{{{i + 1, j, k}, {i, j + 1, k}, {i, j, k + 1}}};
      for (int axis = 0; axis < 3; ++axis) {
        const auto& [a, b, c] = ahead[std::size_t(axis)];
        if (a >= nx || b >= ny || c >= nz) continue;
        const int other = scan.cell_of_point[std::size_t(L.index(a, b, c))];
        if (other < 0 || other == cell) continue;
        const std::pair<int, int> pair{std::min(cell, other), std::max(cell, other)};
        const auto single = planeOfKey.find(scan.cells[std::size_t(cell)].key ^ scan.cells[std::size_t(other)].key);
        const int only = single == planeOfKey.end() ? -1 : single->second;
        if (crossesPiece(x, L.centre(a, b, c), distances, i, steps[std::size_t(axis)], only, planes, pieces))
          continue;
        ++crossings[std::size_t(row)];
        found.push_back(pair);
      }
    }
    std::sort(found.begin(), found.end());
    found.erase(std::unique(found.begin(), found.end()), found.end());
  });
  return r;
}

/// Passages narrower than the lattice run along a piece's edge (between it and a plane that
/// crosses its plane nearby): the two cells at each point just beyond the edge are joined through
/// it (the segment across P there crosses P alone, outside Ω_P), sampled at a quarter spacing.
/// The cells there are kept by their keys: a cell the lattice does not meet may join two that it
/// does.
/// A field of view's samples once for the planes that share its raster (a probe's sector).
/// Per plane, the pairs of cell keys joined there.
std::vector<std::vector<std::pair<std::uint64_t, std::uint64_t>>> edgeJoins(const CellScan& scan,
                                                                            const std::vector<Plane>& planes,
                                                                            const CellKeys& keys,
                                                                            const std::vector<ObservedPiece>& pieces) {
  const GridSpec& L = scan.lattice;
  const double along = 0.25 * L.voxel;
  std::vector<const FieldOfViewRaster*> rasters;
  for (const ObservedPiece& piece : pieces)
    if (!piece.whole && !piece.empty && piece.fov && std::find(rasters.begin(), rasters.end(), piece.fov.get()) == rasters.end())
      rasters.push_back(piece.fov.get());
  std::vector<std::vector<Vec2>> rasterSamples(rasters.size());
  tbb::parallel_for(std::size_t(0), rasters.size(), [&](std::size_t r) { rasterSamples[r] = beyondFieldOfView(*rasters[r], along); });
  std::vector<std::vector<std::pair<std::uint64_t, std::uint64_t>>> joined(planes.size());
  tbb::parallel_for(std::size_t(0), planes.size(), [&](std::size_t j) {
    const ObservedPiece& piece = pieces[j];
    if (piece.whole || piece.empty) return;
    auto& found = joined[j];
    std::vector<Vec2> samples = beyondRectangle(piece.rect, along);
    if (piece.fov) {
      const auto& more = rasterSamples[std::size_t(std::find(rasters.begin(), rasters.end(), piece.fov.get()) - rasters.begin())];
      samples.insert(samples.end(), more.begin(), more.end());
    }
    for (const Vec2& a : samples) {
      const Vec3 y = planes[j].toWorld(a);
      if (!((y - scan.lo).array() >= 0).all() || !((scan.hi - y).array() >= 0).all() || piece.holds(a.x(), a.y()))
        continue;
      const std::uint64_t above = keys.of(y, int(j), 1);
      found.emplace_back(above, above ^ keys.key(j));
    }
    std::sort(found.begin(), found.end());
    found.erase(std::unique(found.begin(), found.end()), found.end());
  });
  return joined;
}

}  // namespace

ObservedCells observedCells(const CellScan& scan, const std::vector<Plane>& planes, const CellKeys& keys,
                            const std::vector<ObservedPiece>& pieces, const std::vector<std::uint64_t>& extra) {
  if (pieces.size() != planes.size()) throw std::invalid_argument("observedCells: one piece per plane");
  const GridSpec& L = scan.lattice;
  const int nx = L.dims[0], ny = L.dims[1], nz = L.dims[2];
  const std::size_t n = std::size_t(L.count());
  if (scan.cell_of_point.size() != n) throw std::invalid_argument("observedCells: the scan's lattice and cells differ");
  LatticeJoins lattice = latticeJoins(scan, planes, keys, pieces);
  const auto& joins = lattice.joins;
  const auto& crossings = lattice.crossings;
  const std::vector<double>& lowerDistance = lattice.lower_distance;
  std::vector<double>& distance = lattice.distance;  // moved into the result at the end
  const auto edgeJoined = edgeJoins(scan, planes, keys, pieces);
  // Ids of the cells met only there, after the scanned cells' (in plane, then key order).
  // The cells given (`extra`) first, so that they are numbered after the scanned ones.
  std::unordered_map<std::uint64_t, std::size_t> unscanned;
  const auto idOf = [&](std::uint64_t key) {
    const int scanned = scan.find(key);
    if (scanned >= 0) return std::size_t(scanned);
    return unscanned.emplace(key, scan.cells.size() + unscanned.size()).first->second;
  };
  std::vector<std::size_t> extraIds;
  for (const std::uint64_t key : extra) extraIds.push_back(idOf(key));
  std::vector<std::pair<std::size_t, std::size_t>> edgePairs;
  for (const auto& found : edgeJoined)
    for (const auto& [a, b] : found) edgePairs.emplace_back(idOf(a), idOf(b));

  ObservedCells out;
  const std::size_t cells = scan.cells.size();
  DisjointSets sets(cells + unscanned.size());
  for (std::size_t row = 0; row < joins.size(); ++row) {
    out.unobserved_crossings += crossings[row];
    for (const auto& [a, b] : joins[row]) sets.unite(std::size_t(a), std::size_t(b));
  }
  for (const auto& [a, b] : edgePairs) sets.unite(a, b);
  const std::size_t ids = cells + unscanned.size();
  std::vector<int> size(ids, 0);  // per set representative: the cells it joins, met by the lattice or not
  for (std::size_t c = 0; c < ids; ++c) ++size[sets.find(c)];
  out.cell_of_scanned.assign(cells, -1);
  // Ω-cells numbered at their first scanned cell, then at their first cell given.
  std::vector<int> number(ids, -1);
  const auto numberOf = [&](std::size_t c) {
    const std::size_t root = sets.find(c);
    if (number[root] < 0) {
      number[root] = out.count++;
      out.members.push_back(size[root]);
    }
    return number[root];
  };
  for (std::size_t c = 0; c < cells; ++c) out.cell_of_scanned[c] = numberOf(c);
  for (const std::size_t id : extraIds) out.cell_of_extra.push_back(numberOf(id));
  // Heights in scan order (the first lattice point reaching the max, as cell_scan.h).
  out.max_distance_mm.assign(cells, -1.0);
  out.max_distance_lo_mm.assign(cells, 0.0);
  out.farthest.assign(cells, Vec3::Zero());
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const std::size_t q = std::size_t(L.index(i, j, k));
        const int cell = scan.cell_of_point[q];
        if (cell < 0) continue;
        out.max_distance_lo_mm[std::size_t(cell)] = std::max(out.max_distance_lo_mm[std::size_t(cell)], lowerDistance[q]);
        if (!(distance[q] > out.max_distance_mm[std::size_t(cell)])) continue;
        out.max_distance_mm[std::size_t(cell)] = distance[q];
        out.farthest[std::size_t(cell)] = L.centre(i, j, k);
      }
  out.distance_mm = std::move(distance);
  return out;
}

}  // namespace xsect

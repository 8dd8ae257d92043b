// Every label's voxels well-composed at once, a partition of the union (see well_composed_labels.h).
#include "geometry/reconstruction/well_composed_labels.h"

#include <array>
#include <functional>

#include "geometry/core/disjoint_sets.h"

namespace xsect {

bool isSimpleCube(const std::array<bool, 27>& set) {
  const auto at = [&](int dx, int dy, int dz) {
    return (dx | dy | dz) != 0 && set[std::size_t((dx + 1) + 3 * (dy + 1) + 9 * (dz + 1))];
  };
  // K's corners: the cube's corner at signs s in {-1, 1}^3 (bit 0: x, 1: y, 2: z set when +1) is
  // in K when one of the seven voxels around it is in the set.
  const auto sign = [](int corner, int bit) { return (corner >> bit & 1) ? 1 : -1; };
  std::array<bool, 8> vertex{};
  int V = 0;
  for (int q = 0; q < 8; ++q) {
    bool any = false;
    for (int m = 1; m < 8 && !any; ++m) any = at(m & 1 ? sign(q, 0) : 0, m & 2 ? sign(q, 1) : 0, m & 4 ? sign(q, 2) : 0);
    vertex[std::size_t(q)] = any;
    V += any;
  }
  if (V == 0) return false;  // K empty: the voxel is a component of its own
  int F = 0;  // faces: their face neighbours
  for (int axis = 0; axis < 3; ++axis)
    for (const int s : {-1, 1}) F += at(axis == 0 ? s : 0, axis == 1 ? s : 0, axis == 2 ? s : 0);
  if (F == 6) return false;  // K the whole sphere: the voxel fills a cavity
  // Edges: along `axis`, at signs (s1, s2) on the two other axes u, w; in K when one of the three
  // voxels around it is. K's corners joined by its edges: its components.
  int E = 0;
  DisjointSets corners(8);
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, w = (axis + 2) % 3;
    for (const int s1 : {-1, 1})
      for (const int s2 : {-1, 1}) {
        int d1[3] = {0, 0, 0}, d2[3] = {0, 0, 0}, d3[3] = {0, 0, 0};
        d1[u] = s1;
        d2[w] = s2;
        d3[u] = s1, d3[w] = s2;
        if (!(at(d1[0], d1[1], d1[2]) || at(d2[0], d2[1], d2[2]) || at(d3[0], d3[1], d3[2]))) continue;
        ++E;
        const int q0 = (s1 > 0) << u | (s2 > 0) << w;
        corners.unite(std::size_t(q0), std::size_t(q0 | 1 << axis));
      }
  }
  int components = 0;
  for (int q = 0; q < 8; ++q) components += vertex[std::size_t(q)] && corners.find(std::size_t(q)) == std::size_t(q);
  return components == 1 && V - E + F == 1;
}

namespace {

using Cube = std::array<std::uint16_t, 8>;  // corner q: voxel (i + (q & 1), j + (q >> 1 & 1), k + (q >> 2))

/// The three 2x2 squares in the axis planes through corner 0: corners a = 0, b, e, d = b + e
/// (diagonals a-d and b-e), as digital_topology.cpp scans them.
constexpr int kSquares[3][2] = {{1, 2}, {1, 4}, {2, 4}};

/// One change that removes a critical configuration of the cube: corner `at` takes `label`.
struct Change {
  int at = -1;
  std::uint16_t label = 0;
};

/// isSimpleCube on voxel (i, j, k) and the voxels of a set (inSet(label): a label, or the union)
/// around it; beyond the grid: not in the set.
template <typename InSet>
bool keepsTopology(const std::vector<std::uint16_t>& labels, const GridSpec& g, int i, int j, int k,
                   const InSet& inSet) {
  std::array<bool, 27> in{};
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int a = i + dx, b = j + dy, c = k + dz;
        const bool inside = a >= 0 && b >= 0 && c >= 0 && a < g.dims[0] && b < g.dims[1] && c < g.dims[2];
        in[std::size_t((dx + 1) + 3 * (dy + 1) + 9 * (dz + 1))] =
            inside && inSet(labels[std::size_t(g.index(a, b, c))]);
      }
  return isSimpleCube(in);
}

/// The changes that remove a critical configuration of the union (non-zero voxels) by adding a
/// voxel next to it, as makeWellComposed does, each taking the label of the union's voxel it is
/// next to, in the order they are tried. Empty: none.
std::vector<Change> unionChanges(const Cube& c) {
  for (const auto& s : kSquares) {
    const int a = 0, b = s[0], e = s[1], d = s[0] + s[1];
    const bool ua = c[a] != 0, ub = c[b] != 0;
    if (ua == (c[d] != 0) && ub == (c[e] != 0) && ua != ub)
      return ua ? std::vector<Change>{{b, c[a]}, {e, c[a]}} : std::vector<Change>{{a, c[b]}, {d, c[b]}};
  }
  int ones = 0;
  for (const std::uint16_t v : c) ones += v != 0;
  if (ones != 2 && ones != 6) return {};
  for (int q = 0; q < 4; ++q) {
    const int r = 7 - q;
    if (ones == 2 && c[q] != 0 && c[r] != 0)
      return {{q ^ 1, c[q]}, {q ^ 2, c[q]}, {q ^ 4, c[q]}, {r ^ 1, c[r]}, {r ^ 2, c[r]}, {r ^ 4, c[r]}};
    if (ones == 6 && c[q] == 0 && c[r] == 0) return {{q, c[q ^ 1]}, {r, c[r ^ 1]}};
  }
  return {};
}

/// The changes that remove a critical configuration of label M, in the order they are tried: the
/// corners that are not M and would remove it by joining M (`others`), then M's corners next to
/// (face neighbours of) them taking their label (`nextTo`, splitting M's pair). Empty: none, or
/// the configuration is the union's too (its other corners are outside: unionChanges first).
std::vector<Change> labelChanges(const Cube& c, std::uint16_t M) {
  std::vector<Change> out;
  const auto collect = [&](const int* others, const int* nextTo, int n) {
    for (int t = 0; t < n; ++t)
      if (c[std::size_t(others[t])] != 0) out.push_back({others[t], M});
    for (int t = 0; t < n; ++t)
      if (c[std::size_t(others[t])] != 0) out.push_back({nextTo[t], c[std::size_t(others[t])]});
  };
  for (const auto& s : kSquares) {
    const int a = 0, b = s[0], e = s[1], d = s[0] + s[1];
    const bool ma = c[a] == M, mb = c[b] == M;
    if (ma == (c[d] == M) && mb == (c[e] == M) && ma != mb) {
      // M at one diagonal; each corner of the other is next to both of M's.
      const int others[2] = {ma ? b : a, ma ? e : d}, nextTo[2] = {ma ? a : b, ma ? d : e};
      collect(others, nextTo, 2);
      return out;
    }
  }
  int ones = 0;
  for (const std::uint16_t v : c) ones += v == M;
  if (ones != 2 && ones != 6) return out;
  for (int q = 0; q < 4; ++q) {
    const int r = 7 - q;
    if (ones == 2 && c[q] == M && c[r] == M) {
      const int others[6] = {q ^ 1, q ^ 2, q ^ 4, r ^ 1, r ^ 2, r ^ 4}, nextTo[6] = {q, q, q, r, r, r};
      collect(others, nextTo, 6);
      return out;
    }
    if (ones == 6 && c[q] != M && c[r] != M) {
      const int others[2] = {q, r}, nextTo[2] = {q ^ 1, r ^ 1};
      collect(others, nextTo, 2);
      return out;
    }
  }
  return out;
}

/// Where a cube of the labels lies, and what choosing its changes reads.
struct CubeAt {
  const std::vector<std::uint16_t>& labels;
  const GridSpec& grid;
  const std::vector<std::uint8_t>& changed_once;  ///< per voxel: its label was changed
  std::array<std::int64_t, 8> offset;             ///< of each corner from corner 0, in the array
  int i = 0, j = 0, k = 0;

  std::int64_t index(int corner) const { return grid.index(i, j, k) + offset[std::size_t(corner)]; }
  /// Whether the corner's voxel added to or taken from {label == L} (L = 0: the union) keeps its
  /// topology.
  bool keeps(int corner, std::uint16_t L) const {
    const int x = i + (corner & 1), y = j + (corner >> 1 & 1), z = k + (corner >> 2);
    return L == 0 ? keepsTopology(labels, grid, x, y, z, [](std::uint16_t l) { return l != 0; })
                  : keepsTopology(labels, grid, x, y, z, [L](std::uint16_t l) { return l == L; });
  }
};

Change firstOf(const std::vector<Change>& options, const std::function<bool(const Change&)>& pick) {
  for (const Change& o : options)
    if (pick(o)) return o;
  return {};
}

/// The next change of cube `c`, or none (at < 0) when it holds no critical configuration; `grows`
/// tells whether it adds a voxel to the union. The union's configurations first: the first
/// addition that keeps the union's and its label's topology, else the first. Then each label's
/// (in the order of the corners): the first change that keeps both labels' topology, on a voxel
/// never changed before or lowering its label; else the first that lowers a label.
Change nextChange(const Cube& c, const CubeAt& at, bool& grows) {
  const std::vector<Change> grow = unionChanges(c);
  grows = !grow.empty();
  if (grows) {
    const Change ch = firstOf(grow, [&](const Change& o) { return at.keeps(o.at, 0) && at.keeps(o.at, o.label); });
    return ch.at >= 0 ? ch : grow.front();
  }
  const auto lowers = [&](const Change& o) { return o.label < c[std::size_t(o.at)]; };
  const auto fresh = [&](const Change& o) { return !at.changed_once[std::size_t(at.index(o.at))]; };
  for (int q = 0; q < 8; ++q) {
    const std::uint16_t M = c[std::size_t(q)];
    bool seen = M == 0;
    for (int p = 0; p < q && !seen; ++p) seen = c[std::size_t(p)] == M;
    if (seen) continue;
    const std::vector<Change> options = labelChanges(c, M);
    if (options.empty()) continue;
    const Change ch = firstOf(options, [&](const Change& o) {
      return (fresh(o) || lowers(o)) && at.keeps(o.at, c[std::size_t(o.at)]) && at.keeps(o.at, o.label);
    });
    return ch.at >= 0 ? ch : firstOf(options, lowers);
  }
  return {};
}

}  // namespace

LabelComposition makeLabelsWellComposed(std::vector<std::uint16_t>& labels, const GridSpec& grid) {
  const int nx = grid.dims[0], ny = grid.dims[1], nz = grid.dims[2];
  std::vector<std::uint8_t> changedOnce(labels.size(), 0);
  CubeAt at{labels, grid, changedOnce, {}};
  for (int q = 0; q < 8; ++q)
    at.offset[std::size_t(q)] = grid.index(q & 1, q >> 1 & 1, q >> 2) - grid.index(0, 0, 0);
  LabelComposition result;
  for (bool changed = true; changed;) {
    changed = false;
    for (at.k = 0; at.k + 1 < nz; ++at.k)
      for (at.j = 0; at.j + 1 < ny; ++at.j)
        for (at.i = 0; at.i + 1 < nx; ++at.i) {
          Cube c;
          for (int q = 0; q < 8; ++q) c[std::size_t(q)] = labels[std::size_t(at.index(q))];
          bool uniform = true;
          for (int q = 1; q < 8 && uniform; ++q) uniform = c[std::size_t(q)] == c[0];
          if (uniform) continue;
          // Until the cube holds no configuration. Each change adds a voxel to the union, or
          // changes a voxel never changed before, or lowers a label: so this ends.
          bool grows = false;
          for (Change ch = nextChange(c, at, grows); ch.at >= 0; ch = nextChange(c, at, grows)) {
            const std::size_t v = std::size_t(at.index(ch.at));
            if (grows) ++result.voxels_added;
            else result.voxels_relabelled += !changedOnce[v];
            c[std::size_t(ch.at)] = ch.label;
            labels[v] = ch.label;
            changedOnce[v] = 1;
            changed = true;
          }
        }
  }
  return result;
}

}  // namespace xsect

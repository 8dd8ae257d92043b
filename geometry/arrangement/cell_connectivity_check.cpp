// Per-cell comparison of a voxel solid with the connectivity graph (see cell_connectivity_check.h).
#include "geometry/arrangement/cell_connectivity_check.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <unordered_map>
#include <numeric>

#include "geometry/core/disjoint_sets.h"
#include "geometry/core/polygon.h"
#include "geometry/core/section_ids.h"

namespace xsect {
namespace {

struct Seed {
  int node = -1;             ///< section id (offset of its plane + section index)
  std::int64_t voxel = -1;   ///< a voxel of the solid in the cell, beside the section
};

struct CellWork {
  std::vector<std::int8_t> signs;  ///< the cell's sign vector against every plane (empty: none)
  std::vector<Seed> seeds;
  std::vector<int> nodes;          ///< the sections bounding the cell
  bool unresolved = false;
};

/// The planes around blocks of kBlock³ voxels of a grid. A point belongs to the block of the voxel
/// nearest to it, so it lies within half a diagonal of B voxels (B = kBlock) of the block's
/// centre. Per block prepared: the planes passing within `reach` of some point of it (within reach
/// plus that half-diagonal of its centre, with a margin far above rounding), in increasing index;
/// and, when asked, every plane's side of the centre. A plane not listed has every point of the
/// block, and every point within `reach` of one, on the side it has the centre on, never on it:
/// a test at such points reads the block's planes, not all of them, and costs what the planes
/// crossing the neighbourhood cost, not points x planes.
class PlaneBlocks {
 public:
  static constexpr int kBlock = 8;
  PlaneBlocks(const std::vector<CuttingPlane>& planes, const GridSpec& grid, double reach, bool withSides)
      : grid_(grid), withSides_(withSides), planeCount_(planes.size()) {
    for (int a = 0; a < 3; ++a) dims_[std::size_t(a)] = (grid.dims[a] + kBlock - 1) / kBlock;
    slot_.assign(std::size_t(dims_[0]) * std::size_t(dims_[1]) * std::size_t(dims_[2]), -1);
    within_ = (reach + 0.5 * std::sqrt(3.0) * kBlock * grid.voxel) * (1 + 1e-9) + 1e-9;
    planes_ = &planes;
  }
  /// Marks the block of voxel (i, j, k) (inside the grid) to be prepared.
  void want(int i, int j, int k) { mark(blockOf(i, j, k)); }
  /// The block of the voxel nearest to x, or -1 off the grid.
  std::int64_t blockAt(const Vec3& x) const {
    int v[3];
    for (int a = 0; a < 3; ++a) {
      const double u = std::round((x[a] - grid_.origin[a]) / grid_.voxel);
      if (!(u >= 0 && u < grid_.dims[a])) return -1;  // off the grid (and never cast out of range)
      v[a] = int(u);
    }
    return std::int64_t(blockOf(v[0], v[1], v[2]));
  }
  /// Marks the block of the voxel nearest to x, if x is on the grid.
  void want(const Vec3& x) {
    const std::int64_t b = blockAt(x);
    if (b >= 0) mark(std::size_t(b));
  }
  /// Computes the marked blocks' planes (parallel over blocks).
  void prepare() {
    const std::vector<CuttingPlane>& planes = *planes_;
    near_.resize(blocks_.size());
    if (withSides_) sides_.resize(blocks_.size() * planeCount_);
    tbb::parallel_for(std::size_t(0), blocks_.size(), [&](std::size_t n) {
      const Vec3 c = centre(blocks_[n]);
      for (std::size_t p = 0; p < planes.size(); ++p) {
        const double d = planes[p].plane.signedDistance(c);
        if (withSides_) sides_[n * planeCount_ + p] = d > 0 ? 1 : (d < 0 ? -1 : 0);
        if (std::abs(d) <= within_) near_[n].push_back(p);
      }
    });
  }
  /// The prepared slot of a block (-1: not prepared).
  int slot(std::int64_t block) const { return block < 0 ? -1 : slot_[std::size_t(block)]; }
  int slotOfVoxel(int i, int j, int k) const { return slot_[blockOf(i, j, k)]; }
  /// The listed planes of a prepared block (slot >= 0).
  const std::vector<std::size_t>& near(int slot) const { return near_.at(std::size_t(slot)); }
  /// Every plane's side of the block's centre (withSides).
  const std::int8_t* sides(int slot) const { return &sides_[std::size_t(slot) * planeCount_]; }

 private:
  void mark(std::size_t b) {
    if (slot_[b] < 0) {
      slot_[b] = int(blocks_.size());
      blocks_.push_back(b);
    }
  }
  std::size_t blockOf(int i, int j, int k) const {
    return (std::size_t(k / kBlock) * std::size_t(dims_[1]) + std::size_t(j / kBlock)) * std::size_t(dims_[0]) +
           std::size_t(i / kBlock);
  }
  Vec3 centre(std::size_t b) const {
    const int bi = int(b % std::size_t(dims_[0])), bj = int((b / std::size_t(dims_[0])) % std::size_t(dims_[1])),
              bk = int(b / (std::size_t(dims_[0]) * std::size_t(dims_[1])));
    return grid_.centre(bi * kBlock, bj * kBlock, bk * kBlock) + Vec3::Constant(0.5 * (kBlock - 1) * grid_.voxel);
  }
  GridSpec grid_;
  bool withSides_ = false;
  std::size_t planeCount_ = 0;
  const std::vector<CuttingPlane>* planes_ = nullptr;
  double within_ = 0;
  std::array<int, 3> dims_{0, 0, 0};
  std::vector<int> slot_;
  std::vector<std::size_t> blocks_;
  std::vector<std::vector<std::size_t>> near_;
  std::vector<std::int8_t> sides_;
};

/// A voxel set read voxel by voxel: dense bytes, or blocks (block_grid.h).
struct DenseSolid {
  const std::vector<std::uint8_t>& in;
  const GridSpec& grid;
  bool at(int i, int j, int k) const { return in[std::size_t(grid.index(i, j, k))]; }
  template <typename F>
  void forEachIn(const F& f) const {
    const auto& D = grid.dims;
    std::size_t q = 0;
    for (int k = 0; k < D[2]; ++k)
      for (int j = 0; j < D[1]; ++j)
        for (int i = 0; i < D[0]; ++i, ++q)
          if (in[q]) f(i, j, k);
  }
};

struct BlockSolid {
  const BlockGrid<std::uint8_t>& in;
  bool at(int i, int j, int k) const { return in.at(i, j, k); }
  template <typename F>
  void forEachIn(const F& f) const {
    const auto& D = in.grid().dims;
    for (std::int64_t b = 0; b < in.blockCount(); ++b) {
      if (!in.isLeaf(b) && !in.tile(b)) continue;
      const auto o = in.blockOrigin(b);
      for (int k = o[2]; k < std::min(D[2], o[2] + 8); ++k)
        for (int j = o[1]; j < std::min(D[1], o[1] + 8); ++j)
          for (int i = o[0]; i < std::min(D[0], o[0] + 8); ++i)
            if (in.at(i, j, k)) f(i, j, k);
    }
  }
};

/// What the steps of compareCells read: the scene's planes and rasters, the arrangement, the grid,
/// the cells asked for, the seeds' depth `hs` and the sample points' reach.
struct CellCheck {
  const std::vector<CuttingPlane>& planes;
  const std::vector<SectionDistanceField>& fields;
  const SectionArrangement& arr;
  const GridSpec& grid;
  const std::vector<int>& only_cells;
  double h = 0, hs = 0, reach = 0;
  SectionIds ids;

  bool wanted(int cell) const {
    return cell >= 0 && (only_cells.empty() || std::binary_search(only_cells.begin(), only_cells.end(), cell));
  }
  std::int8_t signOf(std::size_t j, const Vec3& x) const {
    const double s = planes[j].plane.signedDistance(x);
    return s > 0 ? 1 : (s < 0 ? -1 : 0);
  }
};

/// Per sub-section (plane, section, cell): its deepest sample point, and every sample point at
/// least a seed's depth deep (seeds all over it: a sub-section may touch several components).
struct SubSectionPoints {
  float depth = 0;
  const SectionPoint* deepest = nullptr;
  std::vector<const SectionPoint*> deep;
};
struct SubSectionHash {
  std::size_t operator()(const std::array<int, 3>& a) const {
    std::uint64_t k = 0x9e3779b97f4a7c15ULL;
    for (const int v : a) k = (k ^ std::uint64_t(std::uint32_t(v))) * 0xff51afd7ed558ccdULL;
    return std::size_t(k ^ (k >> 29));
  }
};
using PointsBySubSection = std::unordered_map<std::array<int, 3>, SubSectionPoints, SubSectionHash>;

PointsBySubSection subSectionPoints(const CellCheck& cc, const PlaneBlocks& around) {
  const std::vector<CuttingPlane>& planes = cc.planes;
  const std::vector<SectionDistanceField>& fields = cc.fields;
  const std::size_t P = planes.size();
  const double hs = cc.hs, reach = cc.reach;
  const auto wanted = [&](int cell) { return cc.wanted(cell); };
  /// Depth of a section point in its sub-section: into the section and away from the other
  /// planes (whose traces bound the sub-section); negative inside, mm. Where the point's block is
  /// prepared, only its listed planes are read and values below -reach are returned as -reach (a
  /// plane not listed is farther than reach): such a point is a seed (-reach < -hs) either way,
  /// and the deepest point is only read in sub-sections without seeds.
  const auto depthOf = [&](const SectionPoint& sp, float contour) {
    float f = contour;
    const Vec3 x = planes[std::size_t(sp.plane)].plane.toWorld(sp.p);
    const int slot = around.slot(around.blockAt(x));
    if (slot >= 0) {
      for (const std::size_t j : around.near(slot))
        if (j != std::size_t(sp.plane)) f = std::max(f, -float(std::abs(planes[j].plane.signedDistance(x))));
      return std::max(f, -float(reach));
    }
    for (std::size_t j = 0; j < P; ++j)
      if (j != std::size_t(sp.plane)) f = std::max(f, -float(std::abs(planes[j].plane.signedDistance(x))));
    return f;
  };

  PointsBySubSection points;
  for (const SectionPoint& sp : cc.arr.points) {
    if (sp.kind != SectionPoint::sample || std::size_t(sp.plane) >= fields.size()) continue;
    if (!wanted(sp.cell[0]) && !wanted(sp.cell[1])) continue;
    const float contour = fields[std::size_t(sp.plane)].sample(sp.p.x(), sp.p.y());
    bool better = contour <= -hs;  // a candidate seed; else only a candidate deepest point
    for (const int cell : sp.cell) {
      if (!wanted(cell)) continue;
      const auto it = points.find({sp.plane, sp.section, cell});
      better = better || it == points.end() || contour < it->second.depth;
    }
    if (!better) continue;
    const float f = depthOf(sp, contour);
    for (const int cell : sp.cell) {
      if (!wanted(cell)) continue;
      SubSectionPoints& p = points[{sp.plane, sp.section, cell}];
      if (!p.deepest || f < p.depth) p.depth = f, p.deepest = &sp;
      if (f <= -hs) p.deep.push_back(&sp);
    }
  }

  return points;
}

/// Per cell: the sections bounding it, its sign vector against every plane, and a seed voxel of
/// the solid beside each of its sub-sections' deep points (or deepest); unresolved where a
/// sub-section has no sample point, a point lies on a trace, or the solid misses the section.
template <typename Solid>
std::vector<CellWork> seedCells(const CellCheck& cc, const PlaneBlocks& around, const PointsBySubSection& points,
                                const Solid& inside) {
  const std::vector<CuttingPlane>& planes = cc.planes;
  const std::size_t P = planes.size();
  const GridSpec& grid = cc.grid;
  const double h = cc.h, hs = cc.hs;
  const SectionArrangement& arr = cc.arr;
  const SectionIds& ids = cc.ids;
  const auto wanted = [&](int cell) { return cc.wanted(cell); };
  const auto signOf = [&](std::size_t j, const Vec3& x) { return cc.signOf(j, x); };
  std::vector<CellWork> cells(std::size_t(std::max(arr.cells, 0)));
  std::vector<std::int8_t> signs(P);
  for (const SubSection& ss : arr.sub_sections) {
    if (!wanted(ss.cell) || std::size_t(ss.cell) >= cells.size()) continue;
    CellWork& c = cells[std::size_t(ss.cell)];
    const int node = ids.of(ss.plane, ss.section);
    c.nodes.push_back(node);
    const auto found = points.find({ss.plane, ss.section, ss.cell});
    if (found == points.end()) {
      c.unresolved = true;  // no sample point: a sliver of a section
      continue;
    }
    const CuttingPlane& own = planes[std::size_t(ss.plane)];
    std::vector<const SectionPoint*> from = found->second.deep;
    if (from.empty()) from.push_back(found->second.deepest);
    for (const SectionPoint* sp : from) {
      const Vec3 x0 = own.plane.toWorld(sp->p);
      // The planes that can pass through x0 or between it and its seed voxel: the block's, or
      // all of them off the prepared blocks; every other plane has both on the block centre's side.
      const int slot = around.slot(around.blockAt(x0));
      const std::vector<std::size_t>* near = slot >= 0 ? &around.near(slot) : nullptr;
      const auto forNear = [&](const auto& visit) {
        if (near)
          for (const std::size_t j : *near) visit(j);
        else
          for (std::size_t j = 0; j < P; ++j) visit(j);
      };
      // The point's side of every other plane, its own plane's side the sub-section's.
      if (slot >= 0) std::copy(around.sides(slot), around.sides(slot) + P, signs.begin());
      bool onTrace = false;
      forNear([&](std::size_t j) {
        signs[j] = j == std::size_t(ss.plane) ? std::int8_t(ss.side) : signOf(j, x0);
        onTrace = onTrace || signs[j] == 0;
      });
      if (onTrace) {
        c.unresolved = true;
        break;
      }
      if (c.signs.empty()) c.signs = signs;
      // The planes the block does not list keep the point's side at its seed voxel: the voxel is
      // in the cell when those agree with the cell (counted over all planes, less the listed
      // ones) and the listed ones do at the voxel's centre.
      bool farAgree = true;
      if (near) {
        std::size_t differ = 0;
        for (std::size_t j = 0; j < P; ++j) differ += signs[j] != c.signs[j];
        for (const std::size_t j : *near) differ -= signs[j] != c.signs[j];
        farAgree = differ == 0;
      }
      const auto inThisCell = [&](const Vec3& y) {
        bool in = farAgree;
        forNear([&](std::size_t j) { in = in && signOf(j, y) == c.signs[j]; });
        return in;
      };
      // A voxel of the solid, in the cell, just off the section on the cell's side.
      std::int64_t voxel = -1;
      for (const double t : {0.6, 1.0}) {
        const Vec3 g = (x0 + double(ss.side) * t * hs * own.plane.normal - grid.origin) / h;
        const int i = int(std::lround(g.x())), j = int(std::lround(g.y())), k = int(std::lround(g.z()));
        if (i < 0 || j < 0 || k < 0 || i >= grid.dims[0] || j >= grid.dims[1] || k >= grid.dims[2]) continue;
        const std::int64_t v = grid.index(i, j, k);
        if (!inside.at(i, j, k) || !inThisCell(grid.centre(i, j, k))) continue;
        voxel = v;
        break;
      }
      if (voxel < 0) {  // the solid misses the section here, or the cell is thinner than a voxel
        c.unresolved = true;
        break;
      }
      c.seeds.push_back({node, voxel});
    }
  }

  return cells;
}

/// The outcome of one cell's comparison: whether it was compared, and the pairs of its sections
/// joined by the graph only and by the solid only.
struct CellResult {
  bool compared = false;
  int graphOnly = 0, voxelsOnly = 0;
};

/// Components of the solid inside cell c (6-connected), from its seeds, written into `component`
/// (a fill only enters voxels of its own cell: a neighbour one voxel away can be on the other side
/// only of the planes within a voxel of the current centre, with a margin for rounding, and those
/// are tested exactly, so no two cells touch the same label); then the classes of the cell's
/// sections, the solid's (sections touching one component together) against the graph's (its
/// edges in the cell).
template <typename Solid>
CellResult compareCell(const CellCheck& cc, CellWork& c, const std::vector<const GraphEdge*>& cellEdges,
                       const Solid& inside, const PlaneBlocks& stepping, double step, BlockGrid<int>& component) {
  const std::vector<CuttingPlane>& planes = cc.planes;
  const GridSpec& grid = cc.grid;
  const SectionIds& ids = cc.ids;
  const auto signOf = [&](std::size_t j, const Vec3& x) { return cc.signOf(j, x); };
  std::sort(c.nodes.begin(), c.nodes.end());
  c.nodes.erase(std::unique(c.nodes.begin(), c.nodes.end()), c.nodes.end());
  if (c.nodes.size() < 2 || c.unresolved || c.signs.empty()) return {};
  std::vector<std::int64_t> queue;
  std::vector<std::size_t> near;
  for (std::size_t s = 0; s < c.seeds.size(); ++s) {
    const std::int64_t start = c.seeds[s].voxel;
    const auto voxelOf = [&](std::int64_t v) {
      return std::array<int, 3>{int(v % grid.dims[0]), int((v / grid.dims[0]) % grid.dims[1]),
                                int(v / (std::int64_t(grid.dims[0]) * grid.dims[1]))};
    };
    const auto sv = voxelOf(start);
    if (component.at(sv[0], sv[1], sv[2]) >= 0) continue;
    component.set(sv[0], sv[1], sv[2], int(s));
    queue.assign(1, start);
    while (!queue.empty()) {
      const std::int64_t v = queue.back();
      queue.pop_back();
      const int i = int(v % grid.dims[0]), j = int((v / grid.dims[0]) % grid.dims[1]),
                k = int(v / (std::int64_t(grid.dims[0]) * grid.dims[1]));
      const Vec3 x = grid.centre(i, j, k);
      near.clear();
      for (const std::size_t p : stepping.near(stepping.slotOfVoxel(i, j, k)))
        if (std::abs(planes[p].plane.signedDistance(x)) <= step) near.push_back(p);
      const std::array<std::array<int, 3>, 6> steps{{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}}};
      for (const auto& d : steps) {
        const int a = i + d[0], b = j + d[1], e = k + d[2];
        if (a < 0 || b < 0 || e < 0 || a >= grid.dims[0] || b >= grid.dims[1] || e >= grid.dims[2]) continue;
        if (!inside.at(a, b, e)) continue;
        const Vec3 y = grid.centre(a, b, e);
        bool same = true;
        for (const std::size_t p : near) same = same && signOf(p, y) == c.signs[p];
        if (!same || component.at(a, b, e) >= 0) continue;
        component.set(a, b, e, int(s));
        queue.push_back(grid.index(a, b, e));
      }
    }
  }
  // The classes of the cell's sections (by their place in c.nodes, sorted and unique): the
  // solid's, sections touching one component together; the graph's, from its edges in the cell.
  const auto place = [&](int node) {
    return std::size_t(std::lower_bound(c.nodes.begin(), c.nodes.end(), node) - c.nodes.begin());
  };
  DisjointSets solid(c.nodes.size());
  std::map<int, int> ownerOf;  // component -> a section touching it
  for (const Seed& s : c.seeds) {
    const std::int64_t v = s.voxel;
    const int cv = component.at(int(v % grid.dims[0]), int((v / grid.dims[0]) % grid.dims[1]),
                                int(v / (std::int64_t(grid.dims[0]) * grid.dims[1])));
    const auto [it, fresh] = ownerOf.try_emplace(cv, s.node);
    if (!fresh) solid.unite(place(s.node), place(it->second));
  }
  // With observed pieces a lift can enter the cell through an unobserved part of a face: a
  // section beyond the cell then joins two of its sections inside it (edges of the cell with an
  // end off the cell's faces), as its region joins their components.
  std::vector<int> foreign;
  for (const GraphEdge* e : cellEdges)
    for (const int s : {ids.of(e->plane_a, e->section_a), ids.of(e->plane_b, e->section_b)})
      if (!std::binary_search(c.nodes.begin(), c.nodes.end(), s)) foreign.push_back(s);
  std::sort(foreign.begin(), foreign.end());
  foreign.erase(std::unique(foreign.begin(), foreign.end()), foreign.end());
  DisjointSets graph(c.nodes.size() + foreign.size());
  const auto anyPlace = [&](int s) {
    const auto it = std::lower_bound(c.nodes.begin(), c.nodes.end(), s);
    if (it != c.nodes.end() && *it == s) return std::size_t(it - c.nodes.begin());
    return c.nodes.size() + std::size_t(std::lower_bound(foreign.begin(), foreign.end(), s) - foreign.begin());
  };
  for (const GraphEdge* e : cellEdges)
    graph.unite(anyPlace(ids.of(e->plane_a, e->section_a)), anyPlace(ids.of(e->plane_b, e->section_b)));
  CellResult r;
  r.compared = true;
  for (std::size_t x = 0; x < c.nodes.size(); ++x)
    for (std::size_t y = x + 1; y < c.nodes.size(); ++y) {
      const bool g = graph.find(x) == graph.find(y);
      const bool v = solid.find(x) == solid.find(y);
      r.graphOnly += g && !v;
      r.voxelsOnly += v && !g;
    }
  return r;
}

template <typename Solid>
CellConnectivityCheck compareCells(const std::vector<GraphEdge>& edges, const SectionScene& scene,
                                   const SectionArrangement& arr, const Solid& inside, const GridSpec& grid,
                                   const std::vector<int>& only_cells, double seed_mm) {
  const double h = grid.voxel;
  const double hs = seed_mm > 0 ? seed_mm : h;  // seeds: how deep, and how far off the section
  // Around the sample points: the planes within `reach` of them (a seed's voxel centre lies at
  // most hs + √3/2 h from its point), and every plane's side (PlaneBlocks).
  const CellCheck cc{scene.planes, scene.fields, arr, grid, only_cells, h, hs, hs + h, scene.ids()};
  PlaneBlocks around(cc.planes, grid, cc.reach, true);
  for (const SectionPoint& sp : arr.points)
    if (sp.kind == SectionPoint::sample && (cc.wanted(sp.cell[0]) || cc.wanted(sp.cell[1])))
      around.want(cc.planes[std::size_t(sp.plane)].plane.toWorld(sp.p));
  around.prepare();
  std::vector<CellWork> cells = seedCells(cc, around, subSectionPoints(cc, around), inside);

  // Components of the solid inside each cell (6-connected), from the seeds; parallel over cells.
  // A voxel belongs to one cell, and a fill only enters voxels of its own cell: a neighbour one
  // voxel away can be on the other side only of the planes within a voxel of the current centre
  // (with a margin for rounding), and those are tested exactly. So no two cells touch the same
  // label.
  // A component per voxel of the solid, by blocks: the leaves are made here, before the fills
  // write them from several threads.
  BlockGrid<int> component(grid, -1);
  const double step = h * (1 + 1e-6) + 1e-9;  // a neighbour's centre is h away
  PlaneBlocks stepping(cc.planes, grid, step, false);
  inside.forEachIn([&](int i, int j, int k) {
    stepping.want(i, j, k);
    component.leafForWriting(component.block(i >> 3, j >> 3, k >> 3));
  });
  stepping.prepare();
  std::vector<CellResult> results(cells.size());
  std::vector<std::vector<const GraphEdge*>> edgesOf(cells.size());
  for (const GraphEdge& e : edges)
    if (e.cell >= 0 && std::size_t(e.cell) < cells.size()) edgesOf[std::size_t(e.cell)].push_back(&e);
  tbb::parallel_for(std::size_t(0), cells.size(), [&](std::size_t ci) {
    results[ci] = compareCell(cc, cells[ci], edgesOf[ci], inside, stepping, step, component);
  });
  CellConnectivityCheck out;
  out.pairs_by_cell.assign(cells.size(), -1);
  for (std::size_t ci = 0; ci < cells.size(); ++ci) {
    const CellResult& r = results[ci];
    if (!r.compared) {
      out.cells_unresolved += cells[ci].nodes.size() >= 2;
      continue;
    }
    ++out.cells_compared;
    out.pairs_by_cell[ci] = r.graphOnly + r.voxelsOnly;
    out.pairs_joined_by_graph_only += r.graphOnly;
    out.pairs_joined_by_voxels_only += r.voxelsOnly;
    if (r.graphOnly + r.voxelsOnly > 0) {
      ++out.cells_differing;
      if (out.differing_cells.size() < 20) out.differing_cells.push_back(int(ci));
    }
  }
  return out;
}

}  // namespace

CellConnectivityCheck compareCellsWithVoxels(const std::vector<GraphEdge>& edges, const SectionScene& scene,
                                             const SectionArrangement& arrangement,
                                             const std::vector<std::uint8_t>& inside, const GridSpec& grid,
                                             const std::vector<int>& only_cells, double seed_mm) {
  return compareCells(edges, scene, arrangement, DenseSolid{inside, grid}, grid, only_cells, seed_mm);
}

CellConnectivityCheck compareCellsWithVoxels(const std::vector<GraphEdge>& edges, const SectionScene& scene,
                                             const SectionArrangement& arrangement,
                                             const BlockGrid<std::uint8_t>& inside, const std::vector<int>& only_cells,
                                             double seed_mm) {
  return compareCells(edges, scene, arrangement, BlockSolid{inside}, inside.grid(), only_cells, seed_mm);
}

std::vector<int> cellsDifferingMore(const CellConnectivityCheck& solid, const CellConnectivityCheck& reference) {
  std::vector<int> out;
  const std::size_t n = std::min(solid.pairs_by_cell.size(), reference.pairs_by_cell.size());
  for (std::size_t c = 0; c < n; ++c)
    if (solid.pairs_by_cell[c] >= 0 && reference.pairs_by_cell[c] >= 0 &&
        solid.pairs_by_cell[c] > reference.pairs_by_cell[c])
      out.push_back(int(c));
  return out;
}

bool keepsCellConnectivity(const CellConnectivityCheck& solid, const CellConnectivityCheck& reference) {
  return cellsDifferingMore(solid, reference).empty();
}

}  // namespace xsect

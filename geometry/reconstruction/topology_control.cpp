// Topology control by cutting and adding joins cell by cell (see topology_control.h).
#include "geometry/reconstruction/topology_control.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <tuple>
#include <unordered_map>

#include "geometry/core/disjoint_sets.h"
#include "geometry/core/section_ids.h"
#include "geometry/core/solid_box.h"
#include "geometry/reconstruction/cell_mends.h"

namespace xsect {

namespace {

/// The largest ball of the mends (cell_mends.h), voxels: gaps up to 10 voxels wide are filled,
/// necks up to 10 thick cut. Measured on the mug of the contour literature (5 planes): its four
/// gaps between the walls lifted from two parallel planes need a ball of 5 voxels (3 and 4 leave
/// b1 = 5, 6 does no better than 5).
constexpr int kMendRadius = 5;

void outOfBox(const std::vector<std::uint8_t>& box, const SolidBox& b, std::vector<std::uint8_t>& values, const GridSpec& g) {
  std::fill(values.begin(), values.end(), std::uint8_t(0));
  for (int k = 0; k < b.grid.dims[2]; ++k)
    for (int j = 0; j < b.grid.dims[1]; ++j)
      for (int i = 0; i < b.grid.dims[0]; ++i) {
        if (!box[std::size_t(b.grid.index(i, j, k))]) continue;
        const int gi = i + b.lo[0], gj = j + b.lo[1], gk = k + b.lo[2];
        if (gi < 0 || gj < 0 || gk < 0 || gi >= g.dims[0] || gj >= g.dims[1] || gk >= g.dims[2])
          throw std::logic_error("controlTopology: the solid grew beyond its grid");
        values[std::size_t(g.index(gi, gj, gk))] = 1;
      }
}

/// A join: one contact patch of two sections' lifts inside one cell.
struct Patch {
  CellKey key{0, 0};
  int cell = -1;
  int a = 0, b = 0;                     ///< 1 + flat section ids, a < b
  std::vector<std::int64_t> voxels;     ///< box indices, sorted
  std::vector<std::int64_t> removable;  ///< of them, those the planes let go (planesAllow)
  /// Half of a patch (the side of a plane through its centre across its longest axis): cutting
  /// it leaves the join and breaks a ring-shaped contact, a tunnel the join graph does not see.
  bool partial = false;
};

/// For each patch of at least 8 voxels, its half on the positive side of the plane through its
/// centre normal to its longest axis (the principal direction of its voxels' centres).
std::vector<Patch> halfPatches(const std::vector<Patch>& patches, const GridSpec& g) {
  std::vector<Patch> halves;
  for (const Patch& p : patches) {
    if (p.voxels.size() < 8 || p.removable.empty()) continue;
    Vec3 mean = Vec3::Zero();
    for (const std::int64_t v : p.voxels) mean += g.centre(v);
    mean /= double(p.voxels.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const std::int64_t v : p.voxels) cov += (g.centre(v) - mean) * (g.centre(v) - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    const Vec3 axis = eig.eigenvectors().col(2);  // eigenvalues ascending: the longest axis
    Patch h = p;
    h.partial = true;
    h.voxels.clear();
    h.removable.clear();
    for (const std::int64_t v : p.voxels)
      if (axis.dot(g.centre(v) - mean) >= 0) h.voxels.push_back(v);
    for (const std::int64_t v : p.removable)
      if (axis.dot(g.centre(v) - mean) >= 0) h.removable.push_back(v);
    if (!h.removable.empty() && h.voxels.size() < p.voxels.size()) halves.push_back(std::move(h));
  }
  return halves;
}

/// Every contact of two sections' lifts inside one cell, split into 26-connected patches.
std::vector<Patch> contactPatches(const std::vector<std::uint8_t>& in, const std::vector<std::uint16_t>& src,
                                  const GridSpec& g, const std::vector<CuttingPlane>& planes,
                                  std::size_t realPlanes, const std::vector<SectionDistanceField>& fields,
                                  const SectionArrangement& arrangement) {
  std::unordered_map<std::int64_t, CellKey> keyOf;
  const auto keyAt = [&](std::int64_t v, int i, int j, int k) -> const CellKey& {
    auto it = keyOf.find(v);
    if (it == keyOf.end()) it = keyOf.emplace(v, cellKeyAt(arrangement, planes, g.centre(i, j, k))).first;
    return it->second;
  };
  // (key, a, b) -> the voxels of either side of the contact.
  std::map<std::tuple<CellKey, int, int>, std::vector<std::int64_t>> contacts;
  for (int k = 1; k + 1 < g.dims[2]; ++k)
    for (int j = 1; j + 1 < g.dims[1]; ++j)
      for (int i = 1; i + 1 < g.dims[0]; ++i) {
        const std::int64_t v = g.index(i, j, k);
        if (!in[std::size_t(v)] || !src[std::size_t(v)]) continue;
        for (int dk = -1; dk <= 1; ++dk)
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
              // Each unordered pair once: the neighbours after v in index order.
              if (dk < 0 || (dk == 0 && (dj < 0 || (dj == 0 && di <= 0)))) continue;
              const std::int64_t w = g.index(i + di, j + dj, k + dk);
              if (!in[std::size_t(w)] || !src[std::size_t(w)] || src[std::size_t(w)] == src[std::size_t(v)]) continue;
              const CellKey kv = keyAt(v, i, j, k);
              if (kv != keyAt(w, i + di, j + dj, k + dk)) continue;  // across a plane: the sections' own cut
              const int a = std::min(src[std::size_t(v)], src[std::size_t(w)]);
              const int b = std::max(src[std::size_t(v)], src[std::size_t(w)]);
              auto& list = contacts[{kv, a, b}];
              list.push_back(v);
              list.push_back(w);
            }
      }
  std::vector<Patch> patches;
  for (auto& [key, list] : contacts) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    std::unordered_map<std::int64_t, int> patchOf;
    for (const std::int64_t v : list) patchOf[v] = -1;
    for (const std::int64_t seed : list) {
      if (patchOf[seed] >= 0) continue;
      Patch p;
      p.key = std::get<0>(key);
      p.cell = cellOfKey(arrangement, p.key);
      p.a = std::get<1>(key);
      p.b = std::get<2>(key);
      std::vector<std::int64_t> queue{seed};
      patchOf[seed] = int(patches.size());
      for (std::size_t at = 0; at < queue.size(); ++at) {
        const std::array<int, 3> c = g.coordinates(queue[at]);
        for (int dk = -1; dk <= 1; ++dk)
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
              const std::int64_t w = g.index(c[0] + di, c[1] + dj, c[2] + dk);
              const auto it = patchOf.find(w);
              if (it == patchOf.end() || it->second >= 0) continue;
              it->second = int(patches.size());
              queue.push_back(w);
            }
      }
      std::sort(queue.begin(), queue.end());
      p.voxels = queue;
      for (const std::int64_t v : queue) {
        const std::array<int, 3> c = g.coordinates(v);
        if (planesAllow(g.centre(c[0], c[1], c[2]), false, planes, realPlanes, fields, g.voxel)) p.removable.push_back(v);
      }
      patches.push_back(std::move(p));
    }
  }
  return patches;
}

/// Whether edge e of the multigraph (nodes: sections; edges: joins not cut) is a bridge.
std::vector<char> bridges(int nodes, const std::vector<std::array<int, 2>>& edges, const std::vector<char>& alive) {
  std::vector<std::vector<std::pair<int, int>>> adj(static_cast<std::size_t>(nodes));
  for (std::size_t e = 0; e < edges.size(); ++e)
    if (alive[e]) {
      adj[std::size_t(edges[e][0])].push_back({edges[e][1], int(e)});
      adj[std::size_t(edges[e][1])].push_back({edges[e][0], int(e)});
    }
  std::vector<int> order(static_cast<std::size_t>(nodes), -1), low(static_cast<std::size_t>(nodes), 0);
  std::vector<char> bridge(edges.size(), 0);
  int time = 0;
  struct Frame {
    int node, parentEdge;
    std::size_t next;
  };
  for (int root = 0; root < nodes; ++root) {
    if (order[std::size_t(root)] >= 0) continue;
    std::vector<Frame> stack{{root, -1, 0}};
    order[std::size_t(root)] = low[std::size_t(root)] = time++;
    while (!stack.empty()) {
      Frame& f = stack.back();
      if (f.next < adj[std::size_t(f.node)].size()) {
        const auto [to, e] = adj[std::size_t(f.node)][f.next++];
        if (e == f.parentEdge) continue;  // parallel edges have their own ids
        if (order[std::size_t(to)] >= 0) {
          low[std::size_t(f.node)] = std::min(low[std::size_t(f.node)], order[std::size_t(to)]);
        } else {
          order[std::size_t(to)] = low[std::size_t(to)] = time++;
          stack.push_back({to, e, 0});
        }
      } else {
        const Frame done = f;
        stack.pop_back();
        if (!stack.empty()) {
          const int parent = stack.back().node;
          low[std::size_t(parent)] = std::min(low[std::size_t(parent)], low[std::size_t(done.node)]);
          if (low[std::size_t(done.node)] > order[std::size_t(parent)]) bridge[std::size_t(done.parentEdge)] = 1;
        }
      }
    }
  }
  return bridge;
}

/// A join to add: a tube in cell `cell` between the deepest points of two sections on its faces.
struct Tube {
  CellKey key{0, 0};
  int cell = -1;
  int a = 0, b = 0;  ///< 1 + flat section ids, a < b
  Vec3 from = Vec3::Zero(), to = Vec3::Zero();
  double radius = 0;
  double cost = 0;   ///< its volume in voxels
};

/// Every pair of sections on different faces of one cell (joined there or not: a tube between two
/// joined sections may fill the tunnel between two of their contacts).
std::vector<Tube> joinCandidates(const std::vector<CuttingPlane>& planes,
                                 const std::vector<SectionDistanceField>& fields, const SectionArrangement& arrangement,
                                 double voxel) {
  const SectionIds ids(planes);
  struct Deepest {
    Vec3 x = Vec3::Zero();
    double depth = -1;
    int plane = 0;
  };
  // (cell, 1 + section id) -> its deepest sample point (contour vertices: depth 0).
  std::map<std::pair<int, int>, Deepest> faces;
  for (const SectionPoint& sp : arrangement.points) {
    if (sp.kind == SectionPoint::trace) continue;
    const double depth = std::max(0.0, -double(fields[std::size_t(sp.plane)].sample(sp.p.x(), sp.p.y())));
    for (const int cell : sp.cell) {
      if (cell < 0) continue;
      Deepest& d = faces[{cell, ids.of(sp.plane, sp.section) + 1}];
      if (depth > d.depth) d = {planes[std::size_t(sp.plane)].plane.toWorld(sp.p), depth, sp.plane};
    }
  }
  std::vector<Tube> tubes;
  for (auto i = faces.begin(); i != faces.end(); ++i)
    for (auto j = std::next(i); j != faces.end() && j->first.first == i->first.first; ++j) {
      const Deepest &da = i->second, &db = j->second;
      const int cell = i->first.first;
      if (da.plane == db.plane) continue;
      Tube t;
      t.key = cellKey(arrangement, cell);
      t.cell = cell;
      t.a = i->first.second;
      t.b = j->first.second;
      t.from = da.x;
      t.to = db.x;
      t.radius = std::max(1.5 * voxel, 0.5 * std::min(da.depth, db.depth));
      t.cost = M_PI * t.radius * t.radius * (t.to - t.from).norm() / (voxel * voxel * voxel);
      tubes.push_back(t);
    }
  return tubes;
}

/// The voxels of the box a tube adds: centres within its radius of its segment, in its cell,
/// that the planes let in (planesAllow), not in the solid yet.
std::vector<std::int64_t> tubeVoxels(const Tube& t, const std::vector<std::uint8_t>& in, const GridSpec& g,
                                     const std::vector<CuttingPlane>& planes, std::size_t realPlanes,
                                     const std::vector<SectionDistanceField>& fields,
                                     const SectionArrangement& arrangement) {
  std::vector<std::int64_t> out;
  const Vec3 lo = t.from.cwiseMin(t.to) - Vec3::Constant(t.radius), hi = t.from.cwiseMax(t.to) + Vec3::Constant(t.radius);
  std::array<int, 3> i0{}, i1{};
  for (int a = 0; a < 3; ++a) {
    i0[std::size_t(a)] = std::max(0, int(std::floor((lo[a] - g.origin[a]) / g.voxel)));
    i1[std::size_t(a)] = std::min(g.dims[std::size_t(a)] - 1, int(std::ceil((hi[a] - g.origin[a]) / g.voxel)));
  }
  const Vec3 d = t.to - t.from;
  const double l2 = d.squaredNorm();
  for (int k = i0[2]; k <= i1[2]; ++k)
    for (int j = i0[1]; j <= i1[1]; ++j)
      for (int i = i0[0]; i <= i1[0]; ++i) {
        const std::int64_t v = g.index(i, j, k);
        if (in[std::size_t(v)]) continue;
        const Vec3 x = g.centre(i, j, k);
        const double u = l2 > 0 ? std::clamp((x - t.from).dot(d) / l2, 0.0, 1.0) : 0.0;
        if ((t.from + u * d - x).norm() > t.radius) continue;
        if (!planesAllow(x, true, planes, realPlanes, fields, g.voxel) || cellKeyAt(arrangement, planes, x) != t.key)
          continue;
        out.push_back(v);
      }
  return out;
}

int distance(const Betti& b, const Betti& t) {
  return std::abs(b[0] - t[0]) + std::abs(b[1] - t[1]) + std::abs(b[2] - t[2]);
}

/// Whether a change that takes the solid from `now` to `next` is kept (see topology_control.h).
/// `strict` (target): every Betti number moves toward its target without passing it, so that no
/// change overshoots where another would not (a cut that removed three tunnels where one was
/// asked for left a target no added join could reach).
bool moves(const TopologyGoal& goal, const Betti& now, const Betti& next, bool strict) {
  if (goal.mode == TopologyMode::target) {
    if (!(distance(next, goal.target) < distance(now, goal.target))) return false;
    for (int i = 0; i < 3 && strict; ++i) {
      const int toward = goal.target[std::size_t(i)] - now[std::size_t(i)], step = next[std::size_t(i)] - now[std::size_t(i)];
      if (step * toward < 0 || std::abs(step) > std::abs(toward)) return false;
    }
    return true;
  }
  return next[0] <= now[0] && next[1] <= now[1] && next[2] <= now[2] &&
         next[0] + next[1] + next[2] < now[0] + now[1] + now[2];
}

Vec3 centreOf(const std::vector<std::int64_t>& voxels, const GridSpec& g) {
  Vec3 sum = Vec3::Zero();
  for (const std::int64_t v : voxels)
    sum += g.centre(v);
  return voxels.empty() ? sum : Vec3(sum / double(voxels.size()));
}

/// The join graph's edges and what a change can do to it (see topology_control.h).
struct JoinGraph {
  int nodes = 0;
  std::vector<std::array<int, 2>> edges;  ///< patches first, then tubes
  std::vector<char> alive;                ///< the joins the solid makes now
};

/// The graph edges (section, section, cell) whose last patch was cut (or whose voxels necks cut
/// removed), and those tubes and gaps filled added.
void graphEdges(const std::vector<Patch>& patches, const std::vector<Tube>& tubes, const JoinGraph& graph,
                const std::vector<std::array<int, 3>>& filled, const std::vector<std::uint8_t>& in,
                const std::vector<CuttingPlane>& planes, TopologyControl& out) {
  const SectionIds ids(planes);  // the end planes hold no section: the real planes' ids
  const auto edge = [&](int a1, int b1, int cell) {
    GraphEdge e;
    e.plane_a = ids.planeOf(a1 - 1);
    e.section_a = a1 - 1 - ids.first(e.plane_a);
    e.plane_b = ids.planeOf(b1 - 1);
    e.section_b = b1 - 1 - ids.first(e.plane_b);
    e.cell = cell;
    return e;
  };
  std::map<std::tuple<int, int, int>, int> left;
  for (std::size_t p = 0; p < patches.size(); ++p)
    if (!patches[p].partial) {
      const auto held = [&](std::int64_t v) { return in[std::size_t(v)] != 0; };
      left[{patches[p].a, patches[p].b, patches[p].cell}] +=
          graph.alive[p] && std::any_of(patches[p].voxels.begin(), patches[p].voxels.end(), held);
    }
  for (const auto& [k, n] : left)
    if (n == 0 && std::get<2>(k) >= 0) out.edges_cut.push_back(edge(std::get<0>(k), std::get<1>(k), std::get<2>(k)));
  for (std::size_t t = 0; t < tubes.size(); ++t)
    if (graph.alive[patches.size() + t]) out.edges_added.push_back(edge(tubes[t].a, tubes[t].b, tubes[t].cell));
  for (const auto& [a, b, cell] : filled)
    if (cell >= 0) out.edges_added.push_back(edge(a, b, cell));
  std::sort(out.edges_cut.begin(), out.edges_cut.end());
  std::sort(out.edges_added.begin(), out.edges_added.end());
  out.edges_added.erase(std::unique(out.edges_added.begin(), out.edges_added.end()), out.edges_added.end());
}

/// The greedy search over the changes of the cells (see topology_control.h) on the solid's box:
/// candidates `c` index the patches, then the tubes, then the mends.
class Search {
 public:
  Search(std::vector<Patch> patches, std::vector<Tube> tubes, std::vector<CellMend> mends, std::vector<std::uint8_t>& in,
         const GridSpec& g, const std::vector<CuttingPlane>& planes, std::size_t realPlanes,
         const std::vector<SectionDistanceField>& fields, const SectionArrangement& arrangement,
         const TopologyGoal& goal, TopologyControl& out)
      : patches_(std::move(patches)), tubes_(std::move(tubes)), mends_(std::move(mends)), in_(in), g_(g),
        planes_(planes), realPlanes_(realPlanes), fields_(fields), arrangement_(arrangement), goal_(goal), out_(out) {
    graph_.nodes = SectionIds(planes).count() + 1;
    for (const Patch& p : patches_) graph_.edges.push_back({p.a, p.b});
    for (const Tube& t : tubes_) graph_.edges.push_back({t.a, t.b});
    graph_.alive.assign(graph_.edges.size(), 0);
    for (std::size_t p = 0; p < patches_.size(); ++p) graph_.alive[p] = !patches_[p].partial;
    // The order tried: cheapest first (voxels removed or added), else as listed (deterministic).
    const auto cost = [&](std::size_t c) {
      return isMend(c) ? double(mend(c).voxels.size()) : isCut(c) ? double(patches_[c].voxels.size()) : tube(c).cost;
    };
    order_.resize(graph_.edges.size() + mends_.size());
    for (std::size_t c = 0; c < order_.size(); ++c) order_[c] = c;
    std::stable_sort(order_.begin(), order_.end(), [&](std::size_t x, std::size_t y) { return cost(x) < cost(y); });
    tried_.assign(order_.size(), 0);
    visited_.insert(out_.after);
  }

  void run(const std::function<void(std::int64_t, std::int64_t)>& progress) {
    while (out_.evaluated < goal_.max_evaluations && !reached() && pass())
      if (progress) progress(out_.evaluated, goal_.max_evaluations);
    if (progress) progress(out_.evaluated, out_.evaluated);  // the count the stage's line ends with
    graphEdges(patches_, tubes_, graph_, filled_, in_, planes_, out_);
  }

 private:
  bool isCut(std::size_t c) const { return c < patches_.size(); }
  bool isMend(std::size_t c) const { return c >= patches_.size() + tubes_.size(); }
  const Tube& tube(std::size_t c) const { return tubes_[c - patches_.size()]; }
  const CellMend& mend(std::size_t c) const { return mends_[c - patches_.size() - tubes_.size()]; }
  bool reached() const { return goal_.mode == TopologyMode::target && out_.after == goal_.target; }
  double width(std::size_t c) const {
    if (isMend(c)) return 2 * mend(c).radius * g_.voxel;
    return isCut(c) ? std::sqrt(double(patches_[c].voxels.size()) / 2.0) * g_.voxel : 2 * tube(c).radius;
  }

  /// Whether the goal wants what change c can do to the join graph (its bridges and components now).
  bool wanted(std::size_t c, const std::vector<char>& bridge, DisjointSets& parts) const {
    const Betti& b = out_.after;
    const Betti t = goal_.mode == TopologyMode::target ? goal_.target : Betti{1, 0, 0};
    if (isMend(c)) {  // a mend removes tunnels and cavities only (see keepsMend)
      if (goal_.mode == TopologyMode::simplest && goal_.min_feature_mm > 0 && width(c) > goal_.min_feature_mm)
        return false;
      return b[1] > t[1] || b[2] > t[2];
    }
    if (isCut(c)) {
      const Patch& p = patches_[c];
      if (p.removable.empty()) return false;
      if (goal_.mode == TopologyMode::simplest && goal_.min_feature_mm > 0 && width(c) > goal_.min_feature_mm)
        return false;
      return bridge[c] && !p.partial ? b[0] < t[0] : b[1] + b[2] > t[1] + t[2];
    }
    const bool merges = parts.find(std::size_t(graph_.edges[c][0])) != parts.find(std::size_t(graph_.edges[c][1]));
    return merges ? b[0] > t[0] : b[1] != t[1];
  }

  bool removes(std::size_t c) const { return isMend(c) ? !mend(c).fill : isCut(c); }

  /// Whether a mend that leads to Betti numbers `next` may be kept: it changes no component (the
  /// joins' business) and makes no tunnel or cavity. A mend that makes one makes it about its own
  /// size: on the genus-2 families a 2-voxel gap filled or a 5-voxel neck cut "made" the missing
  /// hole as a pinhole; only a join (a tube) may make a tunnel.
  bool keepsMend(const Betti& next) const {
    const Betti& b = out_.after;
    return next[0] == b[0] && next[1] <= b[1] && next[2] <= b[2];
  }

  /// The voxels change c would change now (a mend found on the first solid may be partly done
  /// since; a tube is clipped to what the planes allow).
  std::vector<std::int64_t> changeOf(std::size_t c) const {
    std::vector<std::int64_t> change = isMend(c) ? mend(c).voxels
                                       : isCut(c) ? patches_[c].removable
                                                  : tubeVoxels(tube(c), in_, g_, planes_, realPlanes_, fields_, arrangement_);
    const bool value = !removes(c);
    change.erase(std::remove_if(change.begin(), change.end(),
                                [&](std::int64_t v) { return bool(in_[std::size_t(v)]) == value; }),
                 change.end());
    return change;
  }

  /// Whether the change's neighbourhood alone shows that change c cannot move the solid toward the
  /// goal, so that no Betti computation of the box is spent on it. With no cavity now nor wanted
  /// and b0 as wanted (a mend that changes b0 is not kept, nor, in strict steps, any change):
  /// a removal that encloses a cavity moves b2 away; otherwise b1 changes by minus the change of
  /// the Euler characteristic (eulerCharacteristicChange) plus the cavities made, so it can only
  /// come down when chi goes up, and up when chi goes down.
  bool cannotMove(std::size_t c, const std::vector<std::int64_t>& change) const {
    const Betti& b = out_.after;
    const Betti t = goal_.mode == TopologyMode::target ? goal_.target : Betti{1, 0, 0};
    if (b[2] != 0 || t[2] != 0 || (!isMend(c) && b[0] != t[0])) return false;
    if (removes(c) && enclosesVoxels(change)) return true;  // a cavity made: b2 away from 0
    const long long chi = eulerCharacteristicChange(in_, g_, change, removes(c) ? 0 : 1);
    return b[1] > t[1] ? chi <= 0 : b[1] < t[1] ? chi >= 0 : true;
  }

  /// Whether removing `voxels` (sorted) from the solid leaves one of their 6-connected groups
  /// without a face-neighbour outside the solid: a cavity (before well-composing).
  bool enclosesVoxels(const std::vector<std::int64_t>& voxels) const {
    std::vector<char> seen(voxels.size(), 0);
    const auto indexOf = [&](std::int64_t v) {
      const auto it = std::lower_bound(voxels.begin(), voxels.end(), v);
      return it != voxels.end() && *it == v ? std::ptrdiff_t(it - voxels.begin()) : std::ptrdiff_t(-1);
    };
    const std::array<std::int64_t, 3> stride{1, g_.dims[0], std::int64_t(g_.dims[0]) * g_.dims[1]};
    for (std::size_t s = 0; s < voxels.size(); ++s) {
      if (seen[s]) continue;
      bool open = false;
      std::vector<std::size_t> queue{s};
      seen[s] = 1;
      for (std::size_t at = 0; at < queue.size(); ++at) {
        const std::int64_t v = voxels[queue[at]];
        const std::array<int, 3> x = g_.coordinates(v);
        for (int a = 0; a < 3; ++a)
          for (const int d : {-1, 1}) {
            const int y = x[std::size_t(a)] + d;
            if (y < 0 || y >= g_.dims[std::size_t(a)]) { open = true; continue; }
            const std::int64_t w = v + d * stride[std::size_t(a)];
            const std::ptrdiff_t i = indexOf(w);
            if (i < 0) open = open || !in_[std::size_t(w)];
            else if (!seen[std::size_t(i)]) seen[std::size_t(i)] = 1, queue.push_back(std::size_t(i));
          }
      }
      if (!open) return true;
    }
    return false;
  }

  /// `change` (changeOf(c)) applied to a copy of the solid, made well-composed: the copy and its
  /// Betti numbers.
  Betti apply(std::size_t c, const std::vector<std::int64_t>& change, std::vector<std::uint8_t>& next) {
    next = in_;
    for (const std::int64_t v : change) next[std::size_t(v)] = removes(c) ? 0 : 1;
    makeWellComposed(next, g_);
    ++out_.evaluated;
    return voxelBetti(next, g_);
  }

  void keep(std::size_t c, const std::vector<std::int64_t>& change, std::vector<std::uint8_t>& next, const Betti& nb) {
    const bool cut = isCut(c);
    in_ = std::move(next);
    out_.after = nb;
    visited_.insert(nb);
    CellChange ch;
    if (isMend(c)) {
      const CellMend& m = mend(c);
      ch.kind = m.fill ? CellChangeKind::gap_filled : CellChangeKind::neck_cut;
      for (const int s : m.sections) ch.sections.push_back(s - 1);
      ch.cell = cellOfKey(arrangement_, m.key);
      for (std::size_t i = 0; m.fill && i < m.sections.size(); ++i)
        for (std::size_t j = i + 1; j < m.sections.size(); ++j) {
          filled_.push_back({m.sections[i], m.sections[j], ch.cell});
          graph_.edges.push_back({m.sections[i], m.sections[j]});  // the join graph gains the joins
          graph_.alive.push_back(1);
        }
    } else {
      if (!cut || !patches_[c].partial) graph_.alive[c] = cut ? 0 : 1;
      ch.kind = !cut ? CellChangeKind::join_added
                     : patches_[c].partial ? CellChangeKind::join_halved : CellChangeKind::join_cut;
      ch.sections = {graph_.edges[c][0] - 1, graph_.edges[c][1] - 1};
      ch.cell = cut ? patches_[c].cell : tube(c).cell;
    }
    ch.at = centreOf(cut ? patches_[c].voxels : change, g_);
    ch.voxels = std::int64_t(change.size());
    ch.width_mm = width(c);
    ch.after = nb;
    out_.changes.push_back(ch);
  }

  /// Tries the changes in order until one is kept (the graph's bridges and components change with
  /// every change); false when none is.
  bool pass() {
    const std::vector<char> bridge = bridges(graph_.nodes, graph_.edges, graph_.alive);
    DisjointSets parts(std::size_t(graph_.nodes));
    for (std::size_t e = 0; e < graph_.edges.size(); ++e)
      if (graph_.alive[e]) parts.unite(std::size_t(graph_.edges[e][0]), std::size_t(graph_.edges[e][1]));
    std::optional<std::size_t> fallback;  // the first change that overshoots but comes nearer
    std::optional<std::size_t> sideways;  // else the first to Betti numbers as near, not met before
    for (const std::size_t c : order_) {
      const bool untied = isMend(c) || (isCut(c) && patches_[c].partial);  // not tied to one join's state
      if (tried_[c] || (!untied && graph_.alive[c] != char(isCut(c))) || !wanted(c, bridge, parts)) continue;
      if (out_.evaluated >= goal_.max_evaluations) break;
      tried_[c] = 1;
      const std::vector<std::int64_t> change = changeOf(c);
      if (change.empty() || cannotMove(c, change)) continue;
      std::vector<std::uint8_t> next;
      const Betti nb = apply(c, change, next);
      if (isMend(c) && !keepsMend(nb)) continue;
      if (moves(goal_, out_.after, nb, true)) {
        keep(c, change, next, nb);
        return true;
      }
      if (!fallback && moves(goal_, out_.after, nb, false)) fallback = c;
      if (!sideways && goal_.mode == TopologyMode::target && !visited_.count(nb) &&
          distance(nb, goal_.target) == distance(out_.after, goal_.target))
        sideways = c;
    }
    // No change comes nearer without overshooting: the first that comes nearer, else one to Betti
    // numbers as near but new (a cut that removed two tunnels where one was asked for, after which
    // an added join makes one back).
    if (!fallback && !sideways) return false;
    const std::size_t c = fallback ? *fallback : *sideways;
    const std::vector<std::int64_t> change = changeOf(c);
    std::vector<std::uint8_t> next;
    const Betti nb = apply(c, change, next);
    keep(c, change, next, nb);
    return true;
  }

  std::vector<Patch> patches_;
  std::vector<Tube> tubes_;
  std::vector<CellMend> mends_;
  std::vector<std::array<int, 3>> filled_;  ///< (1 + section, 1 + section, cell) joined by gaps filled
  std::vector<std::uint8_t>& in_;
  const GridSpec& g_;
  const std::vector<CuttingPlane>& planes_;
  std::size_t realPlanes_;
  const std::vector<SectionDistanceField>& fields_;
  const SectionArrangement& arrangement_;
  const TopologyGoal& goal_;
  TopologyControl& out_;
  JoinGraph graph_;
  std::vector<std::size_t> order_;
  std::vector<char> tried_;
  std::set<Betti> visited_;
};

}  // namespace

TopologyControl controlTopology(std::vector<std::uint8_t>& inside, const GridSpec& grid,
                                const std::vector<std::uint16_t>& source, const std::vector<CuttingPlane>& planes,
                                std::size_t real_planes, const std::vector<SectionDistanceField>& fields,
                                const SectionArrangement& arrangement, const TopologyGoal& goal,
                                const std::function<void(std::int64_t, std::int64_t)>& progress) {
  const auto start = std::chrono::steady_clock::now();
  if (inside.size() != std::size_t(grid.count()) || source.size() != inside.size() || fields.size() != planes.size())
    throw std::invalid_argument("controlTopology: the solid, its sources, the grid and the planes differ in size");
  TopologyControl out;
  const SolidBox box = solidBox(inside, grid, kMendRadius + 1);
  std::vector<std::uint8_t> in = intoBox(inside, grid, box);
  const GridSpec& g = box.grid;
  out.before = out.after = voxelBetti(in, g);
  const bool done = goal.mode == TopologyMode::free || (goal.mode == TopologyMode::target && out.after == goal.target);
  if (!done && g.count() > 0) {
    const std::vector<std::uint16_t> src = intoBox(source, grid, box);
    std::vector<Patch> patches = contactPatches(in, src, g, planes, real_planes, fields, arrangement);
    std::vector<Tube> tubes = joinCandidates(planes, fields, arrangement, g.voxel);
    out.joins = int(patches.size());
    for (const Patch& p : patches) out.joins_forced += p.removable.empty();
    out.joins_possible = int(tubes.size());
    std::vector<CellMend> mends = cellMends(in, src, g, planes, real_planes, fields, arrangement, kMendRadius);
    out.mends_possible = int(mends.size());
    for (Patch& h : halfPatches(patches, g)) patches.push_back(std::move(h));
    Search(std::move(patches), std::move(tubes), std::move(mends), in, g, planes, real_planes, fields, arrangement, goal,
           out)
        .run(progress);
    outOfBox(in, box, inside, grid);
  }
  out.reached = goal.mode != TopologyMode::target || out.after == goal.target;
  // The features on the solid's own box, with one voxel of margin (a tunnel's hole lies in the
  // hull of its loop): a third fewer voxels than the search's box.
  const SolidBox tight = solidBox(in, g, 1);
  out.features_voxels = tight.grid.count();
  if (out.after[1] == 0 && out.after[2] == 0) {
    out.features_computed = true;  // no tunnel, no cavity: nothing to size
  } else if (tight.grid.count() > 0 && tight.grid.count() <= kMaxFeatureVoxels) {
    out.features = topologyFeatures(intoBox(in, g, tight), tight.grid);
    out.features_computed = true;
    for (TopologyFeature& f : out.features) {
      f.born_in_cell = cellOfKey(arrangement, cellKeyAt(arrangement, planes, f.born_at));
      f.dies_in_cell = cellOfKey(arrangement, cellKeyAt(arrangement, planes, f.dies_at));
    }
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace xsect

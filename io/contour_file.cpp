// .contour reader (see contour_file.h): parse and validate, then per plane chain the edges bounding
// each material (and the union of the materials) into closed contours and build sections of them.
#include "io/contour_file.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <set>
#include <utility>

#include "geometry/core/polygon.h"
#include "io/contour_repair.h"
#include "geometry/core/ring_validity.h"
#include "io/contour_plane.h"
#include "io/input_error.h"
#include "io/text_tokens.h"

namespace xsect {

namespace {

/// An edge as the file gives it: vertices i -> j (indices of its plane), materials on each side.
struct Edge {
  long i = 0, j = 0;
  int left = 0, right = 0;
  int line = -1;  ///< line of the file, for messages
};

struct RawPlane {
  Vec3 n = Vec3::UnitZ();  ///< unit normal
  double d = 0;            ///< offset of the normalised equation, mm
  std::vector<Vec3> pts;   ///< vertices, world mm
  std::vector<Edge> edges;
  int line = -1;  ///< line where the plane starts
};

/// Reads plane `p` (0-based) from `tk`, widening the data bounds [lo, hi] (world mm) by its
/// vertices and adding its materials to `materials`.
RawPlane readPlane(Tokens& tk, long p, Vec3& lo, Vec3& hi, std::set<int>& materials) {
  const std::string key = "plane " + std::to_string(p + 1);
  RawPlane r;
  r.line = tk.line();
  for (int k = 0; k < 3; ++k) r.n[k] = tk.coordinate(key + " normal");
  r.d = tk.coordinate(key + " offset d");
  const double len = r.n.norm();
  if (len < 1e-12) throw InputError(tk.file, key + " normal", "plane normal (a, b, c) is zero", r.line);
  r.n /= len;
  r.d /= len;
  const long nv = tk.count(key + " vertex count", 0, 3);
  const long ne = tk.count(key + " edge count", 0, 4);
  if (3 * nv + 4 * ne > long(tk.items.size() - tk.at))
    throw InputError(tk.file, key, std::to_string(nv) + " vertices and " + std::to_string(ne) +
                                       " edges need " + std::to_string(3 * nv + 4 * ne) +
                                       " values, but the file holds only " +
                                       std::to_string(tk.items.size() - tk.at) + " more",
                     r.line);
  r.pts.resize(nv);
  for (long v = 0; v < nv; ++v) {
    for (int k = 0; k < 3; ++k) r.pts[v][k] = tk.coordinate(key + " vertex " + std::to_string(v));
    lo = lo.cwiseMin(r.pts[v]);
    hi = hi.cwiseMax(r.pts[v]);
  }
  std::set<std::pair<long, long>> seen;  // undirected vertex pairs, to refuse repeated edges
  r.edges.resize(ne);
  for (long e = 0; e < ne; ++e) {
    const std::string ekey = key + " edge " + std::to_string(e);
    Edge& E = r.edges[e];
    E.line = tk.line();
    E.i = tk.integer(ekey + " vertex", 0);
    E.j = tk.integer(ekey + " vertex", 0);
    for (long q : {E.i, E.j})
      if (q >= nv)
        throw InputError(tk.file, ekey, "vertex index " + std::to_string(q) + " out of range (the plane has " +
                                            std::to_string(nv) + " vertices)", E.line);
    if (E.i == E.j) throw InputError(tk.file, ekey, "an edge from a vertex to itself", E.line);
    if (!seen.emplace(std::min(E.i, E.j), std::max(E.i, E.j)).second)
      throw InputError(tk.file, ekey, "edge between vertices " + std::to_string(E.i) + " and " +
                                          std::to_string(E.j) + " listed twice", E.line);
    const long left = tk.integer(ekey + " left material", 0);
    const long right = tk.integer(ekey + " right material", 0);
    if (std::max(left, right) > std::numeric_limits<int>::max())
      throw InputError(tk.file, ekey, "material number too large", E.line);
    if (left == right)
      throw InputError(tk.file, ekey, "the same material " + std::to_string(left) + " on both sides", E.line);
    E.left = int(left);
    E.right = int(right);
    for (int m : {E.left, E.right})
      if (m > 0) materials.insert(m);
  }
  return r;
}

/// An edge turned so that the region is on its left.
struct Arc {
  long from, to;
  int line;
};

/// The edges with the region (materials where `inside` holds) on exactly one side, turned so that
/// it is on their left.
std::vector<Arc> boundaryArcs(const std::vector<Edge>& edges, const std::function<bool(int)>& inside) {
  std::vector<Arc> arcs;
  for (const Edge& e : edges) {
    const bool l = inside(e.left), r = inside(e.right);
    if (l && !r) arcs.push_back({e.i, e.j, e.line});
    if (r && !l) arcs.push_back({e.j, e.i, e.line});
  }
  return arcs;
}

/// Clockwise angle (radians, in (0, 2π]) from direction `a` to direction `b` (plane coordinates).
double clockwiseAngle(const Vec2& a, const Vec2& b) {
  const double ccw = std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
  const double cw = -ccw;
  return cw <= 0 ? cw + 2 * M_PI : cw;
}

/// The arcs (region on their left; `at`: the plane's vertices, plane mm) chained into closed
/// loops of vertex indices. Throws InputError(file, field, "edges of <what> do not form closed
/// contours ...") when some vertex has more arcs coming in than going out or the reverse. Where
/// several arcs leave a vertex, the loop takes the first one clockwise from the arc it came in by:
/// the tightest wedge of the region, so that regions touching at a vertex give separate loops.
/// Loops start at a vertex with one arc leaving where they have one.
std::vector<std::vector<long>> closedLoops(const std::vector<Arc>& arcs, const std::vector<Vec2>& at,
                                           const std::string& file, const std::string& field,
                                           const std::string& what) {
  const std::size_t nv = at.size();
  std::vector<std::vector<std::size_t>> out(nv);
  std::vector<long> balance(nv, 0);  // leaving minus arriving
  for (std::size_t a = 0; a < arcs.size(); ++a) {
    out[arcs[a].from].push_back(a);
    ++balance[arcs[a].from];
    --balance[arcs[a].to];
  }
  for (std::size_t a = 0; a < arcs.size(); ++a)
    for (long v : {arcs[a].from, arcs[a].to})
      if (balance[v] != 0) {
        const long leaving = long(out[v].size());
        throw InputError(file, field,
                         "edges of " + what + " do not form closed contours: vertex " + std::to_string(v) +
                             " has " + std::to_string(leaving - balance[v]) + " such edges coming in and " +
                             std::to_string(leaving) + " going out",
                         arcs[a].line);
      }
  std::vector<char> used(arcs.size(), 0);
  std::vector<std::size_t> order(arcs.size());  // starting arcs: those from simple vertices first
  for (std::size_t a = 0; a < arcs.size(); ++a) order[a] = a;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    return (out[arcs[x].from].size() == 1) > (out[arcs[y].from].size() == 1);
  });
  std::vector<std::vector<long>> loops;
  for (std::size_t first : order) {
    if (used[first]) continue;
    std::vector<long> loop;
    std::size_t a = first;
    for (;;) {
      used[a] = 1;
      loop.push_back(arcs[a].from);
      const long w = arcs[a].to;
      const Vec2 back = at[arcs[a].from] - at[w];
      std::size_t next = arcs.size();
      double best = 1e300;
      const auto consider = [&](std::size_t c) {
        const double angle = clockwiseAngle(back, at[arcs[c].to] - at[w]);
        if (angle < best) best = angle, next = c;
      };
      for (std::size_t c : out[w])
        if (!used[c]) consider(c);
      if (arcs[first].from == w) consider(first);
      // balanced degrees: an arc leaves every vertex entered, the first one's at the start
      if (next == first || next == arcs.size()) break;
      a = next;
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

/// Sections of the loops (vertex indices into `at`, plane mm) bounding one region with the region
/// on their left: counter-clockwise loops outer rings, clockwise ones holes. Rings are cleaned of
/// repeated vertices; rings with |area| <= `tinyArea` (mm²) are dropped with a warning;
/// self-intersecting rings and holes in no outer ring are InputErrors. `file`, `field`, `line`
/// name the place in messages.
std::vector<Section> sectionsOfLoops(const std::vector<std::vector<long>>& loops, const std::vector<Vec2>& at,
                                     double tinyArea, const std::string& file, const std::string& field,
                                     int line, bool repair, std::vector<std::string>* warnings) {
  std::vector<Ring> outers, holes;
  for (std::size_t k = 0; k < loops.size(); ++k) {
    Ring ring;
    for (long v : loops[k]) ring.push_back(at[v]);
    ring = withoutRepeatedVertices(ring);
    const std::string where = field + " contour " + std::to_string(k) + " (from vertex " +
                              std::to_string(loops[k].front()) + ")";
    const bool simple = ring.size() >= 3 && ringIsSimple(ring);
    if (!repair && ring.size() >= 3 && !simple)
      throw InputError(file, where,
                       "the contour crosses itself (a self-intersecting ring); input.repair_contours: true makes it "
                       "simple",
                       line);
    const double area = ring.size() < 3 ? 0.0 : signedArea(ring);
    // A ring crossing itself: the area of its lobes (a symmetric figure eight nets zero); its
    // role, outer or hole, is its net orientation's (outer when it nets zero).
    const double lobes = simple || !repair || ring.size() < 3 ? std::abs(area) : repairedOrRefused({ring}, {}, file, where, line).area_after;
    if (lobes <= tinyArea) {
      if (warnings) warnings->push_back(file + ": " + where + " has no area (a point or a segment): dropped");
      continue;
    }
    (area >= 0 ? outers : holes).push_back(std::move(ring));
  }
  if (repair) {
    RingRepair fixed = repairedOrRefused(outers, holes, file, field, line);
    if (fixed.changed && warnings) warnings->push_back(repairWarning(file + ": " + field, fixed));
    outers = std::move(fixed.outers);
    holes = std::move(fixed.holes);
  }
  const std::size_t nHoles = holes.size();
  std::vector<Section> sections = sectionsFromRings(std::move(outers), std::move(holes));
  std::size_t attached = 0;
  for (const Section& s : sections) attached += s.holes.size();
  if (attached != nHoles)
    throw InputError(file, field,
                     "a clockwise contour (its material on the left, outside it) lies in no counter-clockwise "
                     "one: the material would be unbounded (left and right swapped?)",
                     line);
  return sections;
}

}  // namespace

ContourFile readContourFile(const std::string& path, std::vector<std::string>* warnings, bool repair) {
  Tokens tk = readTokens(path);
  const long nPlanes = tk.count("plane count", 1, 6);  // a b c d nV nE
  std::vector<RawPlane> raw;
  Vec3 lo = Vec3::Constant(1e300), hi = -lo;
  std::set<int> materialSet;
  for (long p = 0; p < nPlanes; ++p) raw.push_back(readPlane(tk, p, lo, hi, materialSet));
  if (tk.at != tk.items.size())
    throw InputError(path, "", "unexpected content after the last plane", tk.items[tk.at].second);

  ContourFile cf;
  cf.materials.assign(materialSet.begin(), materialSet.end());
  const bool several = cf.materials.size() > 1;
  const double tinyArea = 1e-12 * std::max((hi - lo).squaredNorm(), 1e-300);
  cf.planes.resize(nPlanes);
  if (several) cf.labelled.resize(nPlanes);
  for (long p = 0; p < nPlanes; ++p) {
    const RawPlane& r = raw[p];
    CuttingPlane& cp = cf.planes[p];
    cp.slice = int(p);
    cp.name = "plane " + std::to_string(p + 1);
    cp.plane = contourPlane(r.n, r.d, r.pts, lo, hi, path, cp.name, r.line);
    std::vector<Vec2> at(r.pts.size());
    for (std::size_t v = 0; v < r.pts.size(); ++v) at[v] = cp.plane.toPlane(r.pts[v]);
    const auto sectionsOf = [&](const std::function<bool(int)>& inside, const std::string& field,
                                const std::string& what) {
      const auto loops = closedLoops(boundaryArcs(r.edges, inside), at, path, field, what);
      return sectionsOfLoops(loops, at, tinyArea, path, field, r.line, repair, warnings);
    };
    if (several) {
      for (int m : cf.materials) {
        const std::string mat = "material " + std::to_string(m);
        for (Section& s : sectionsOf([m](int x) { return x == m; }, cp.name + " " + mat, mat)) {
          s.label = m;
          cf.labelled[p].push_back(std::move(s));
        }
      }
    }
    const std::string solid = several ? "the solid (materials >= 1 against the background 0)"
                                      : "material " + std::to_string(cf.materials.empty() ? 1 : cf.materials[0]);
    cp.sections = sectionsOf([](int x) { return x != 0; }, several ? cp.name + " solid" : cp.name + " " + solid, solid);
    for (Section& s : cp.sections) s.label = 1;
    cp.observed_everywhere = true;  // a contour file gives all of O ∩ P on each plane
    cp.extent = sectionBounds(cp.sections);
  }
  return cf;
}

}  // namespace xsect

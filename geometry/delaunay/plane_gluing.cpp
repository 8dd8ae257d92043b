// The boundary of method 3 within one cutting plane (see plane_gluing.h).
#include "geometry/delaunay/plane_gluing.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "geometry/core/polygon.h"
#include "geometry/core/section_locator.h"

namespace xsect {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
struct VertexId {
  int value = 0;  ///< point id + 1; 0: a vertex made where constraints crossed
};
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VertexId, K>;
using Fb = CGAL::Triangulation_face_base_with_info_2<int, K, CGAL::Constrained_triangulation_face_base_2<K>>;  // index
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;

/// Triangles of one side, bucketed on a uniform grid for point location.
class TriangleIndex {
 public:
  explicit TriangleIndex(std::vector<std::array<Vec2, 3>> tris) : tris_(std::move(tris)) {
    if (tris_.empty()) return;
    Eigen::AlignedBox2d box;
    double size = 0;
    for (const auto& t : tris_) {
      for (const Vec2& p : t) box.extend(p);
      size += (t[1] - t[0]).norm() + (t[2] - t[1]).norm();
    }
    size = std::max(size / (2.0 * double(tris_.size())), 1e-12);
    lo_ = box.min();
    cell_ = std::max(size * 2, box.diagonal().maxCoeff() / 512.0);
    nx_ = int(std::ceil((box.max().x() - lo_.x()) / cell_)) + 1;
    ny_ = int(std::ceil((box.max().y() - lo_.y()) / cell_)) + 1;
    buckets_.resize(std::size_t(nx_) * std::size_t(ny_));
    for (std::size_t k = 0; k < tris_.size(); ++k) {
      Eigen::AlignedBox2d b;
      for (const Vec2& p : tris_[k]) b.extend(p);
      const int x0 = ix(b.min().x()), x1 = ix(b.max().x()), y0 = iy(b.min().y()), y1 = iy(b.max().y());
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) buckets_[std::size_t(y) * std::size_t(nx_) + std::size_t(x)].push_back(int(k));
    }
  }
  bool covers(const Vec2& q) const {
    if (tris_.empty()) return false;
    const int x = ix(q.x()), y = iy(q.y());
    for (const int k : buckets_[std::size_t(y) * std::size_t(nx_) + std::size_t(x)]) {
      const auto& t = tris_[std::size_t(k)];
      const auto cross = [](const Vec2& a, const Vec2& b, const Vec2& p) {
        return (b.x() - a.x()) * (p.y() - a.y()) - (b.y() - a.y()) * (p.x() - a.x());
      };
      const double s0 = cross(t[0], t[1], q), s1 = cross(t[1], t[2], q), s2 = cross(t[2], t[0], q);
      if ((s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0)) return true;
    }
    return false;
  }

 private:
  int ix(double x) const { return std::clamp(int((x - lo_.x()) / cell_), 0, nx_ - 1); }
  int iy(double y) const { return std::clamp(int((y - lo_.y()) / cell_), 0, ny_ - 1); }
  std::vector<std::array<Vec2, 3>> tris_;
  Vec2 lo_ = Vec2::Zero();
  double cell_ = 1;
  int nx_ = 1, ny_ = 1;
  std::vector<std::vector<int>> buckets_;
};

/// The edges the plane's triangulation must keep: the footprint's rims, and the boundary of each
/// side's covered region (its triangles' edges used once): where one cell's footprint ends at a
/// trace line and the neighbouring cell's does not continue it, no rim marks the change, and a
/// triangle of the plane straddling it would be misjudged. Sorted, unique.
std::vector<std::array<int, 2>> footprintRims(const PlaneFootprint& fp) {
  std::vector<std::array<int, 2>> rims = fp.rims;
  for (const auto& side : fp.covered) {
    std::unordered_map<std::uint64_t, int> uses;
    for (const auto& t : side)
      for (int e = 0; e < 3; ++e) ++uses[edgeKey(t[std::size_t(e)], t[std::size_t((e + 1) % 3)])];
    for (const auto& [key, n] : uses)
      if (n == 1) rims.push_back({int(key >> 32), int(key & 0xffffffffu)});
  }
  std::sort(rims.begin(), rims.end());
  rims.erase(std::unique(rims.begin(), rims.end()), rims.end());
  return rims;
}

/// A sliver's state (state[f->info()], planeBoundary) is the state of the face across its longest
/// edge that is not constrained: across a constrained edge (a contour, a rim, an outline) the state
/// is meant to change. Up to four passes, as neighbours get judged.
void judgeSlivers(const CDT& cdt, std::vector<CDT::Face_handle> slivers, std::vector<int>& state) {
  for (int pass = 0; pass < 4 && !slivers.empty(); ++pass) {
    std::vector<CDT::Face_handle> left;
    for (const CDT::Face_handle f : slivers) {
      int longest = -1;
      double best = -1;
      for (int i = 0; i < 3; ++i) {
        if (f->is_constrained(i)) continue;
        const auto& a = f->vertex(cdt.ccw(i))->point();
        const auto& b = f->vertex(cdt.cw(i))->point();
        const double d = CGAL::squared_distance(a, b);
        if (d > best) {
          best = d;
          longest = i;
        }
      }
      if (longest < 0) continue;  // all three constrained: no boundary face
      const CDT::Face_handle across = f->neighbor(longest);
      const int known = cdt.is_infinite(across) ? -1 : state[std::size_t(across->info())];
      if (known < 0) {
        left.push_back(f);
        continue;
      }
      state[std::size_t(f->info())] = known;
    }
    if (left.size() == slivers.size()) break;
    slivers.swap(left);
  }
}

}  // namespace

PlaneBoundary planeBoundary(int plane, const std::vector<int>& ids, const PlaneFootprint& fp, const SectionVertices& sv,
                            const std::vector<CuttingPlane>& planes, int firstNewId) {
  PlaneBoundary out;
  if (fp.covered[0].empty() && fp.covered[1].empty()) return out;
  const Plane& P = planes[std::size_t(plane)].plane;
  CDT cdt;
  std::unordered_map<int, CDT::Vertex_handle> handle;
  std::unordered_map<int, Vec2> coords;
  for (const int id : ids) {
    const Vec2 q = planeCoordinates(sv, planes, id, plane);
    coords[id] = q;
    const CDT::Vertex_handle h = cdt.insert(K::Point_2(q.x(), q.y()));
    if (h->info().value == 0) h->info().value = id + 1;
    handle[id] = h;
  }
  const auto constrain = [&](int a, int b) {
    const auto ha = handle.find(a), hb = handle.find(b);
    if (ha == handle.end() || hb == handle.end() || ha->second == hb->second) return;
    cdt.insert_constraint(ha->second, hb->second);
  };
  for (const SampledRing& r : sv.rings) {
    if (r.plane != plane) continue;
    for (std::size_t k = 0; k < r.points.size(); ++k) constrain(r.points[k], r.points[(k + 1) % r.points.size()]);
  }
  for (const auto& e : footprintRims(fp)) constrain(e[0], e[1]);
  // New vertices where constraints crossed.
  for (auto it = cdt.finite_vertices_begin(); it != cdt.finite_vertices_end(); ++it)
    if (it->info().value == 0) {
      it->info().value = firstNewId + int(out.new_points.size()) + 1;
      out.new_points.push_back(P.toWorld(Vec2(it->point().x(), it->point().y())));
    }
  const auto corners = [&](const std::array<int, 3>& t) {
    return std::array<Vec2, 3>{coords.at(t[0]), coords.at(t[1]), coords.at(t[2])};
  };
  std::array<std::vector<std::array<Vec2, 3>>, 2> sideTris;
  for (int s = 0; s < 2; ++s)
    for (const auto& t : fp.covered[std::size_t(s)]) sideTris[std::size_t(s)].push_back(corners(t));
  const TriangleIndex minus(std::move(sideTris[0])), plus(std::move(sideTris[1]));
  const SectionLocator sections(sv.sampled[std::size_t(plane)]);
  // Each face's state: outside the sections (0), or covered by the negative side only (1), the
  // positive side only (2), both or neither (3: no boundary). A sliver (three contour points
  // collinear up to rounding) cannot be judged at its centroid: it takes the state of the face
  // across its longest unconstrained edge.
  std::vector<int> state;  // per finite face, by its index (info); -1: not judged yet
  std::vector<CDT::Face_handle> slivers;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    f->info() = int(state.size());
    state.push_back(-1);
  }
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    Vec2 q[3];
    for (int i = 0; i < 3; ++i) q[i] = Vec2(f->vertex(i)->point().x(), f->vertex(i)->point().y());
    if (isSliverTriangle(q[0], q[1], q[2])) {
      slivers.push_back(f);
      continue;
    }
    const Vec2 c = (q[0] + q[1] + q[2]) / 3.0;
    if (sections.holding(c) < 0) {
      state[std::size_t(f->info())] = 0;
      continue;
    }
    const bool m = minus.covers(c), p = plus.covers(c);
    state[std::size_t(f->info())] = m == p ? 3 : (m ? 1 : 2);
  }
  judgeSlivers(cdt, std::move(slivers), state);
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    const int st = state[std::size_t(f->info())];
    if (st < 0 || st == 0 || st == 3) continue;
    std::array<int, 3> v{};
    for (int i = 0; i < 3; ++i) v[std::size_t(i)] = f->vertex(i)->info().value - 1;
    // CDT faces are counter-clockwise in (u, v): their normal is the plane's. The solid on the
    // positive side is bounded here by a face whose outward normal is -normal.
    if (st == 2) std::swap(v[1], v[2]);
    out.faces.push_back(v);
  }
  std::sort(out.faces.begin(), out.faces.end());
  return out;
}

}  // namespace xsect

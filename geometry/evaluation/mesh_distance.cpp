// Distance, side and sampling queries on a triangle mesh (see mesh_distance.h).
// One CGAL AABB tree (Epick kernel) over the mesh's triangles as a soup answers both the distance
// queries (with CGAL's internal KD-tree hint built up front, so that concurrent queries never
// trigger a lazy build) and the ray-parity side test of CGAL::Side_of_triangle_mesh (the vertical
// ray cast it runs on its tree, here on ours: its retry rays come from a fixed seed, so answers
// are deterministic). Ray parity and distances depend on neither the faces' orientation nor their
// connectivity, so the soup is used as it is: no Surface_mesh is built (its manifold check and
// conversion took a fifth of `xsect eval` on a 430,000-triangle mesh). Each triangle keeps its
// vertices' order, and its reference point is its first vertex, as CGAL's face-graph primitive
// had them on the soup's conversion: the same tree, the same answers.
#include "geometry/evaluation/mesh_distance.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/internal/Side_of_triangle_mesh/Point_inside_vertical_ray_cast.h>
#include <Eigen/Geometry>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <stdexcept>

#include "geometry/core/random_streams.h"

namespace xsect {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
// What CGAL::Side_of_triangle_mesh runs on a point within the tree's box (it builds its tree from
// a face graph; the test itself reads nothing but the tree).
using RayCast = CGAL::internal::Point_inside_vertical_ray_cast<Kernel, Tree>;

Point toPoint(const Vec3& p) { return Point(p.x(), p.y(), p.z()); }
Vec3 toVec(const Point& p) { return Vec3(p.x(), p.y(), p.z()); }

/// Runs f(i) for i in [0, n) in parallel; f writes only its own output slot.
template <class F>
void forEachIndex(std::size_t n, const F& f) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i) f(i);
                    });
}
}  // namespace

struct MeshDistance::Impl {
  std::vector<Triangle> triangles;  // the tree's primitives point into it: never resized once built
  Tree tree;
  /// CGAL::Side_of_triangle_mesh's answer: outside the tree's box at once, else by ray parity.
  CGAL::Bounded_side side(const Point& p) const {
    const CGAL::Bbox_3 box = tree.bbox();
    if (p.x() < box.xmin() || p.x() > box.xmax() || p.y() < box.ymin() || p.y() > box.ymax() || p.z() < box.zmin() ||
        p.z() > box.zmax())
      return CGAL::ON_UNBOUNDED_SIDE;
    return RayCast()(p, tree);
  }
};

MeshDistance::MeshDistance(const TriangleMesh& input) {
  if (input.triangles.empty()) throw std::invalid_argument("MeshDistance: mesh has no triangles");
  auto impl = std::make_shared<Impl>();
  impl->triangles.reserve(input.triangles.size());
  for (const auto& t : input.triangles) {
    for (std::uint32_t i : t)
      if (i >= input.vertices.size())
        throw std::invalid_argument("MeshDistance: triangle index out of range");
    const auto corner = [&](std::uint32_t i) {
      const auto& v = input.vertices[i];
      return Point(v.x(), v.y(), v.z());
    };
    impl->triangles.emplace_back(corner(t[0]), corner(t[1]), corner(t[2]));
  }
  impl->tree.insert(impl->triangles.cbegin(), impl->triangles.cend());
  impl->tree.build();
  impl->tree.accelerate_distance_queries();
  impl_ = std::move(impl);
}

MeshDistance::~MeshDistance() = default;

std::vector<double> MeshDistance::distances(const std::vector<Vec3>& points) const {
  std::vector<double> out(points.size());
  const Tree& tree = impl_->tree;
  forEachIndex(points.size(),
               [&](std::size_t i) { out[i] = std::sqrt(tree.squared_distance(toPoint(points[i]))); });
  return out;
}

std::vector<Vec3> MeshDistance::closestPoints(const std::vector<Vec3>& points) const {
  std::vector<Vec3> out(points.size());
  const Tree& tree = impl_->tree;
  forEachIndex(points.size(),
               [&](std::size_t i) { out[i] = toVec(tree.closest_point(toPoint(points[i]))); });
  return out;
}

std::vector<std::uint8_t> MeshDistance::inside(const std::vector<Vec3>& points) const {
  std::vector<std::uint8_t> out(points.size());
  const Impl& m = *impl_;
  forEachIndex(points.size(),
               [&](std::size_t i) { out[i] = m.side(toPoint(points[i])) != CGAL::ON_UNBOUNDED_SIDE ? 1 : 0; });
  return out;
}

std::vector<std::uint8_t> MeshDistance::insideRows(const PointRows& rows) const {
  std::vector<std::uint8_t> out(rows.size());
  if (rows.count <= 0) return out;
  const Impl& m = *impl_;
  const Tree& tree = m.tree;
  const std::size_t count = std::size_t(rows.count);
  const double step2 = rows.step.squaredNorm();
  const auto sideAt = [&](const Vec3& p) { return m.side(toPoint(p)) != CGAL::ON_UNBOUNDED_SIDE ? 1 : 0; };
  using Segment = Kernel::Segment_3;
  using Hit = Tree::Intersection_and_primitive_id<Segment>::Type;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rows.starts.size(), 4),
                    [&](const tbb::blocked_range<std::size_t>& range) {
    std::vector<Hit> hits;
    std::vector<std::pair<double, double>> crossings;  // [t0, t1] along the row, in steps
    for (std::size_t r = range.begin(); r != range.end(); ++r) {
      std::uint8_t* row = out.data() + r * count;
      const Vec3& s = rows.starts[r];
      if (!(step2 > 0)) {
        for (std::size_t i = 0; i < count; ++i) row[i] = std::uint8_t(sideAt(s));
        continue;
      }
      hits.clear();
      crossings.clear();
      tree.all_intersections(Segment(toPoint(s - rows.step), toPoint(s + double(count) * rows.step)),
                             std::back_inserter(hits));
      const auto param = [&](const Point& p) { return (toVec(p) - s).dot(rows.step) / step2; };
      for (const Hit& h : hits) {
        if (const Point* p = boost::get<Point>(&h.first)) {
          const double t = param(*p);
          crossings.emplace_back(t, t);
        } else if (const Segment* g = boost::get<Segment>(&h.first)) {  // the row lies in a face
          const double a = param(g->source()), b = param(g->target());
          crossings.emplace_back(std::min(a, b), std::max(a, b));
        }
      }
      std::sort(crossings.begin(), crossings.end());
      // Stretch k: the points after the k-th crossing (by start) and before the next.
      constexpr double kMargin = 1e-6;
      std::size_t next = 0;       // crossings starting at or before the current point (+ margin)
      double reach = -1e300;      // the farthest end among them
      std::size_t known = SIZE_MAX;  // the stretch whose side is known
      std::uint8_t knownSide = 0;
      for (std::size_t i = 0; i < count; ++i) {
        const double t = double(i);
        while (next < crossings.size() && crossings[next].first <= t + kMargin)
          reach = std::max(reach, crossings[next++].second);
        if (reach >= t - kMargin) {  // on or next to the surface: tested alone
          row[i] = std::uint8_t(sideAt(s + t * rows.step));
          continue;
        }
        if (next != known) {
          known = next;
          knownSide = std::uint8_t(sideAt(s + t * rows.step));
        }
        row[i] = knownSide;
      }
    }
  });
  return out;
}

double surfaceArea(const TriangleMesh& mesh) {
  double area = 0.0;
  for (const auto& t : mesh.triangles) {
    const Vec3 a = mesh.vertices[t[0]].cast<double>();
    area += 0.5 * (mesh.vertices[t[1]].cast<double>() - a)
                      .cross(mesh.vertices[t[2]].cast<double>() - a)
                      .norm();
  }
  return area;
}

std::vector<Vec3> sampleSurface(const TriangleMesh& mesh, std::size_t count, std::uint64_t seed) {
  std::vector<double> cumulative(mesh.triangles.size());
  double total = 0.0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const Vec3 a = mesh.vertices[tri[0]].cast<double>();
    total += 0.5 * (mesh.vertices[tri[1]].cast<double>() - a)
                       .cross(mesh.vertices[tri[2]].cast<double>() - a)
                       .norm();
    cumulative[t] = total;
  }
  std::vector<Vec3> samples;
  if (!(total > 0)) return samples;
  samples.reserve(count);
  constexpr std::uint64_t kStream = 0x5355524653414D50ULL;  // "SURFSAMP"
  std::mt19937_64 rng = makeStream(seed, kStream, 0);
  for (std::size_t s = 0; s < count; ++s) {
    const double pick = uniform01(rng) * total;
    const std::size_t t = std::min<std::size_t>(
        std::upper_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin(),
        cumulative.size() - 1);
    const auto& tri = mesh.triangles[t];
    // Uniform in the triangle: sqrt of the first uniform spreads mass evenly from vertex a.
    const double r1 = std::sqrt(uniform01(rng)), r2 = uniform01(rng);
    samples.push_back((1 - r1) * mesh.vertices[tri[0]].cast<double>() +
                      r1 * (1 - r2) * mesh.vertices[tri[1]].cast<double>() +
                      r1 * r2 * mesh.vertices[tri[2]].cast<double>());
  }
  return samples;
}

}  // namespace xsect

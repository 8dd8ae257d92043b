// Distance, side and sampling queries on a triangle mesh (see mesh_distance.h).
// The mesh is converted once to a CGAL Surface_mesh (Epick kernel); one AABB tree over its faces
// answers both the distance queries (with CGAL's internal KD-tree hint built up front, so that
// concurrent queries never trigger a lazy build) and the ray-parity side test of
// CGAL::Side_of_triangle_mesh (constructed on the same prebuilt tree; its retry rays come from a
// fixed seed, so answers are deterministic). Ray parity does not depend on face orientation, so a
// soup that is not a manifold mesh is first made one by CGAL's orient_polygon_soup (which only
// duplicates vertices and flips faces).
#include "geometry/evaluation/mesh_distance.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
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
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
using SideOf = CGAL::Side_of_triangle_mesh<SurfaceMesh, Kernel>;
static_assert(std::is_same<SideOf::AABB_tree, Tree>::value, "Side_of_triangle_mesh tree type");

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
  SurfaceMesh mesh;
  Tree tree;
  std::unique_ptr<SideOf> side;
};

MeshDistance::MeshDistance(const TriangleMesh& input) {
  if (input.triangles.empty()) throw std::invalid_argument("MeshDistance: mesh has no triangles");
  auto impl = std::make_shared<Impl>();
  std::vector<Point> points;
  points.reserve(input.vertices.size());
  for (const auto& v : input.vertices) points.emplace_back(v.x(), v.y(), v.z());
  std::vector<std::vector<std::size_t>> polygons;
  polygons.reserve(input.triangles.size());
  for (const auto& t : input.triangles) {
    for (std::uint32_t i : t)
      if (i >= input.vertices.size())
        throw std::invalid_argument("MeshDistance: triangle index out of range");
    polygons.push_back({t[0], t[1], t[2]});
  }
  namespace PMP = CGAL::Polygon_mesh_processing;
  if (!PMP::is_polygon_soup_a_polygon_mesh(polygons)) PMP::orient_polygon_soup(points, polygons);
  PMP::polygon_soup_to_polygon_mesh(points, polygons, impl->mesh);

  impl->tree.insert(faces(impl->mesh).first, faces(impl->mesh).second, impl->mesh);
  impl->tree.build();
  impl->tree.accelerate_distance_queries();
  impl->side = std::make_unique<SideOf>(impl->tree);
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
  const SideOf& side = *impl_->side;
  forEachIndex(points.size(), [&](std::size_t i) {
    out[i] = side(toPoint(points[i])) != CGAL::ON_UNBOUNDED_SIDE ? 1 : 0;
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

// Display decimation (see mesh_decimation.h): CGAL edge collapse with Garland-Heckbert policies,
// or vertex clustering for meshes that edge collapse cannot take.
#include "geometry/meshing/mesh_decimation.h"

#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_policies.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>
#include <CGAL/boost/graph/helpers.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <unordered_map>

namespace xsect {

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
namespace SMS = CGAL::Surface_mesh_simplification;

/// Vertices snapped to the centre of mass of their cell in a grid whose cell is chosen so that about
/// max_triangles remain; triangles that collapse are dropped.
TriangleMesh clusteredMesh(const TriangleMesh& mesh, std::size_t maxTriangles) {
  Eigen::Vector3f lo = mesh.vertices.front(), hi = lo;
  for (const auto& v : mesh.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  // A surface of n triangles over a box keeps about n * (cell / its mean edge)^-2 triangles.
  double area = 0;
  for (const auto& t : mesh.triangles)
    area += 0.5 * double((mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]).norm());
  const double cell = std::max(1e-12, std::sqrt(2.0 * area / double(maxTriangles)));
  std::map<std::array<std::int64_t, 3>, std::uint32_t> cellIndex;
  std::vector<Eigen::Vector3d> sums;
  std::vector<int> counts;
  std::vector<std::uint32_t> vertexCell(mesh.vertices.size());
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3f d = (mesh.vertices[i] - lo) / float(cell);
    const std::array<std::int64_t, 3> key{std::int64_t(std::floor(d.x())), std::int64_t(std::floor(d.y())),
                                          std::int64_t(std::floor(d.z()))};
    const auto [it, added] = cellIndex.emplace(key, std::uint32_t(sums.size()));
    if (added) {
      sums.emplace_back(Eigen::Vector3d::Zero());
      counts.push_back(0);
    }
    sums[it->second] += mesh.vertices[i].cast<double>();
    ++counts[it->second];
    vertexCell[i] = it->second;
  }
  TriangleMesh out;
  for (std::size_t c = 0; c < sums.size(); ++c) out.vertices.push_back((sums[c] / counts[c]).cast<float>());
  for (const auto& t : mesh.triangles) {
    const std::array<std::uint32_t, 3> u{vertexCell[t[0]], vertexCell[t[1]], vertexCell[t[2]]};
    if (u[0] != u[1] && u[1] != u[2] && u[0] != u[2]) out.triangles.push_back(u);
  }
  return out;
}

}  // namespace

TriangleMesh decimatedMesh(const TriangleMesh& mesh, std::size_t maxTriangles) {
  if (maxTriangles < 4) throw std::invalid_argument("decimatedMesh: the budget must be at least 4 triangles");
  if (mesh.triangles.size() <= maxTriangles) return mesh;
  SurfaceMesh sm;
  std::vector<SurfaceMesh::Vertex_index> vs;
  vs.reserve(mesh.vertices.size());
  for (const auto& v : mesh.vertices) vs.push_back(sm.add_vertex(Kernel::Point_3(v.x(), v.y(), v.z())));
  bool manifold = true;
  for (const auto& t : mesh.triangles)
    if (sm.add_face(vs[t[0]], vs[t[1]], vs[t[2]]) == SurfaceMesh::null_face()) {
      manifold = false;
      break;
    }
  if (!manifold || !CGAL::is_valid_polygon_mesh(sm)) return clusteredMesh(mesh, maxTriangles);
  SMS::Count_stop_predicate<SurfaceMesh> stop(maxTriangles * 3 / 2);  // edges of a closed mesh: 3/2 per triangle
  SMS::GarlandHeckbert_plane_policies<SurfaceMesh, Kernel> policies(sm);
  SMS::edge_collapse(sm, stop, CGAL::parameters::get_cost(policies.get_cost()).get_placement(policies.get_placement()));
  sm.collect_garbage();
  TriangleMesh out;
  out.vertices.reserve(sm.number_of_vertices());
  for (const auto v : sm.vertices()) {
    const Kernel::Point_3& p = sm.point(v);
    out.vertices.emplace_back(float(p.x()), float(p.y()), float(p.z()));
  }
  out.triangles.reserve(sm.number_of_faces());
  for (const auto f : sm.faces()) {
    std::array<std::uint32_t, 3> t{};
    int k = 0;
    for (const auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) t[std::size_t(k++)] = std::uint32_t(v.idx());
    out.triangles.push_back(t);
  }
  return out;
}

}  // namespace xsect

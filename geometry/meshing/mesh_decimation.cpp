// Display decimation by vertex clustering (see mesh_decimation.h).
#include "geometry/meshing/mesh_decimation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

namespace xsect {

namespace {

/// One clustering at grid cell `cell` (mm).
TriangleMesh clustered(const TriangleMesh& mesh, const Eigen::Vector3f& lo, double cell) {
  std::unordered_map<std::uint64_t, std::uint32_t> cellIndex;
  cellIndex.reserve(mesh.vertices.size() / 2);
  std::vector<Eigen::Vector3d> sums;
  std::vector<int> counts;
  std::vector<std::uint32_t> vertexCell(mesh.vertices.size());
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3d d = (mesh.vertices[i] - lo).cast<double>() / cell;
    // 21 bits per axis: 2 M cells along an axis, far more than a budget of triangles needs.
    const std::uint64_t key = (std::uint64_t(std::min(2097151.0, std::max(0.0, std::floor(d.x())))) << 42) |
                              (std::uint64_t(std::min(2097151.0, std::max(0.0, std::floor(d.y())))) << 21) |
                              std::uint64_t(std::min(2097151.0, std::max(0.0, std::floor(d.z()))));
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
  out.vertices.reserve(sums.size());
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
  Eigen::Vector3f lo = mesh.vertices.front();
  for (const auto& v : mesh.vertices) lo = lo.cwiseMin(v);
  double area = 0;
  for (const auto& t : mesh.triangles)
    area += 0.5 * double((mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]).norm());
  // A surface of area A on a grid of cell c keeps about 2 A / c² triangles; curved and thin parts
  // keep more, so the cell grows until the budget holds.
  double cell = std::max(1e-9, std::sqrt(2.0 * area / double(maxTriangles)));
  for (;;) {
    TriangleMesh out = clustered(mesh, lo, cell);
    if (out.triangles.size() <= maxTriangles) return out;
    cell *= 1.05 * std::sqrt(double(out.triangles.size()) / double(maxTriangles));
  }
}

}  // namespace xsect

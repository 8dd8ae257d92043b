// Components of a union of tetrahedra (see tetrahedra_components.h).
#include "geometry/delaunay/tetrahedra_components.h"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <tuple>

#include "geometry/core/disjoint_sets.h"

namespace xsect {

int tetrahedraComponents(const std::vector<std::array<Vec3, 4>>& tetrahedra) {
  // Every vertex as (position, tetrahedron), sorted by position: equal positions are neighbours.
  struct Corner {
    double x, y, z;
    std::uint32_t tetrahedron;
  };
  std::vector<Corner> corners;
  corners.reserve(4 * tetrahedra.size());
  for (std::size_t t = 0; t < tetrahedra.size(); ++t)
    for (const Vec3& v : tetrahedra[t]) corners.push_back({v.x(), v.y(), v.z(), std::uint32_t(t)});
  // A total order (the tetrahedron breaks ties), so the parallel sort's result is one.
  tbb::parallel_sort(corners.begin(), corners.end(), [](const Corner& a, const Corner& b) {
    return std::tie(a.x, a.y, a.z, a.tetrahedron) < std::tie(b.x, b.y, b.z, b.tetrahedron);
  });
  DisjointSets sets(tetrahedra.size());
  for (std::size_t q = 1; q < corners.size(); ++q) {
    const Corner &a = corners[q - 1], &b = corners[q];
    if (a.x == b.x && a.y == b.y && a.z == b.z) sets.unite(a.tetrahedron, b.tetrahedron);
  }
  int components = 0;
  for (std::size_t t = 0; t < tetrahedra.size(); ++t) components += sets.find(t) == t;
  return components;
}

std::int64_t repeatedVertexCopies(const TriangleMesh& mesh) {
  std::vector<Eigen::Vector3f> v = mesh.vertices;
  std::sort(v.begin(), v.end(), [](const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
    return std::tie(a.x(), a.y(), a.z()) < std::tie(b.x(), b.y(), b.z());
  });
  std::int64_t copies = 0;
  for (std::size_t q = 1; q < v.size(); ++q) copies += v[q] == v[q - 1];
  return copies;
}

}  // namespace xsect

// Components of a union of tetrahedra (see tetrahedra_components.h).
#include "geometry/delaunay/tetrahedra_components.h"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <tuple>

#include "geometry/core/disjoint_sets.h"

namespace xsect {

int tetrahedraComponents(const TetrahedronSet& tetrahedra) {
  // Vertices joined through the tetrahedra, then vertices at one position (sorted by position,
  // ids breaking ties: one order whatever the sort).
  const std::size_t n = tetrahedra.vertices.size();
  DisjointSets sets(n);
  std::vector<std::uint8_t> used(n, 0);
  for (const std::array<int, 4>& c : tetrahedra.corners)
    for (int i = 0; i < 4; ++i) {
      used[std::size_t(c[std::size_t(i)])] = 1;
      sets.unite(std::size_t(c[0]), std::size_t(c[std::size_t(i)]));
    }
  std::vector<std::uint32_t> order;
  for (std::size_t v = 0; v < n; ++v)
    if (used[v]) order.push_back(std::uint32_t(v));
  const auto& x = tetrahedra.vertices;
  tbb::parallel_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return std::make_tuple(x[a].x(), x[a].y(), x[a].z(), a) < std::make_tuple(x[b].x(), x[b].y(), x[b].z(), b);
  });
  for (std::size_t q = 1; q < order.size(); ++q)
    if (x[order[q - 1]] == x[order[q]]) sets.unite(order[q - 1], order[q]);
  int components = 0;
  for (const std::uint32_t v : order) components += sets.find(v) == v;
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

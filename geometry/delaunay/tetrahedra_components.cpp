// Components of a union of tetrahedra (see tetrahedra_components.h).
#include "geometry/delaunay/tetrahedra_components.h"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <tuple>

#include "geometry/core/disjoint_sets.h"

namespace xsect {

int tetrahedraComponents(const TetrahedronSet& tetrahedra, const BoundaryTolerances& bounds) {
  // Vertices joined through the tetrahedra, then vertices at one position (sorted by position,
  // ids breaking ties: one order whatever the sort).
  const std::size_t n = tetrahedra.vertices.size();
  const auto& x = tetrahedra.vertices;
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
  tbb::parallel_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return std::make_tuple(x[a].x(), x[a].y(), x[a].z(), a) < std::make_tuple(x[b].x(), x[b].y(), x[b].z(), b);
  });
  for (std::size_t q = 1; q < order.size(); ++q)
    if (x[order[q - 1]] == x[order[q]]) sets.unite(order[q - 1], order[q]);
  // A class counts when one of its tetrahedra bounds volume.
  std::vector<std::uint8_t> solid(n, 0);
  for (const std::array<int, 4>& c : tetrahedra.corners) {
    const std::size_t root = sets.find(std::size_t(c[0]));
    if (solid[root]) continue;
    const Vec3 &p0 = x[std::size_t(c[0])], &p1 = x[std::size_t(c[1])], &p2 = x[std::size_t(c[2])], &p3 = x[std::size_t(c[3])];
    const double shortest = std::min({(p1 - p0).norm(), (p2 - p0).norm(), (p3 - p0).norm(), (p2 - p1).norm(),
                                      (p3 - p1).norm(), (p3 - p2).norm()});
    const double sixV = std::abs((p1 - p0).dot((p2 - p0).cross(p3 - p0)));
    const double twoA = (p1 - p0).cross(p2 - p0).norm() + (p1 - p0).cross(p3 - p0).norm() +
                        (p2 - p0).cross(p3 - p0).norm() + (p2 - p1).cross(p3 - p1).norm();
    if (shortest >= bounds.weld_mm && sixV >= bounds.flat_thickness_mm * twoA) solid[root] = 1;
  }
  int components = 0;
  for (const std::uint32_t v : order) components += sets.find(v) == v && solid[v];
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

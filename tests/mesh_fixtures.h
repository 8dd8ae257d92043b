// Meshes built in the tests: boxes, a torus, an icosphere and the boundary of a voxel set, all
// closed and oriented with outward normals (inverted on request, for cavity walls).
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include "geometry/core/types.h"

namespace xsect::test {

/// Axis-aligned box [lo, hi] (mm); inverted = normals pointing inwards (a cavity wall).
inline TriangleMesh boxMesh(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi,
                            bool inverted = false) {
  TriangleMesh m;
  for (int k = 0; k < 8; ++k)
    m.vertices.emplace_back((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(),
                            (k & 4) ? hi.z() : lo.z());
  // Quads with outward normals (vertex bit 1 = x, 2 = y, 4 = z).
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    std::array<std::uint32_t, 3> a{std::uint32_t(q[0]), std::uint32_t(q[1]), std::uint32_t(q[2])};
    std::array<std::uint32_t, 3> b{std::uint32_t(q[0]), std::uint32_t(q[2]), std::uint32_t(q[3])};
    if (inverted) {
      std::swap(a[1], a[2]);
      std::swap(b[1], b[2]);
    }
    m.triangles.push_back(a);
    m.triangles.push_back(b);
  }
  return m;
}

/// Appends b to a (vertex indices of b shifted).
inline void append(TriangleMesh* a, const TriangleMesh& b) {
  const auto off = std::uint32_t(a->vertices.size());
  a->vertices.insert(a->vertices.end(), b.vertices.begin(), b.vertices.end());
  for (auto t : b.triangles) a->triangles.push_back({t[0] + off, t[1] + off, t[2] + off});
}

/// Torus around z: major radius R, tube radius r (mm), n x m quads.
inline TriangleMesh torusMesh(double R, double r, int n, int m) {
  TriangleMesh t;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double a = 2 * M_PI * i / n, b = 2 * M_PI * j / m;
      t.vertices.emplace_back(float((R + r * std::cos(b)) * std::cos(a)),
                              float((R + r * std::cos(b)) * std::sin(a)), float(r * std::sin(b)));
    }
  auto id = [&](int i, int j) { return std::uint32_t(((i + n) % n) * m + (j + m) % m); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      // d/da x d/db points outwards for this parametrisation.
      t.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      t.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return t;
}

/// Icosphere of radius r (mm) centred at c, after `levels` 4:1 subdivisions.
inline TriangleMesh icosphere(double r, int levels, const Vec3& c = Vec3::Zero()) {
  const double p = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vec3> v = {{-1, p, 0}, {1, p, 0},  {-1, -p, 0}, {1, -p, 0}, {0, -1, p},  {0, 1, p},
                         {0, -1, -p}, {0, 1, -p}, {p, 0, -1},  {p, 0, 1},  {-p, 0, -1}, {-p, 0, 1}};
  for (auto& x : v) x.normalize();
  std::vector<std::array<std::uint32_t, 3>> f = {
      {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},   {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      return mid[key] = std::uint32_t(v.size() - 1);
    };
    std::vector<std::array<std::uint32_t, 3>> g;
    for (auto t : f) {
      const auto ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
      g.push_back({t[0], ab, ca});
      g.push_back({t[1], bc, ab});
      g.push_back({t[2], ca, bc});
      g.push_back({ab, bc, ca});
    }
    f = g;
  }
  TriangleMesh m;
  for (const auto& x : v) m.vertices.push_back((c + r * x).cast<float>());
  m.triangles = f;
  return m;
}

/// Boundary of a set of unit voxels (voxel (i, j, k) = [i, i+1] x [j, j+1] x [k, k+1] mm): two
/// triangles per face between a voxel of the set and one outside it, vertices shared.
inline TriangleMesh voxelBoundary(const std::set<std::tuple<int, int, int>>& voxels) {
  TriangleMesh m;
  std::map<std::array<int, 3>, std::uint32_t> index;
  auto vid = [&](std::array<int, 3> p) {
    auto it = index.find(p);
    if (it != index.end()) return it->second;
    m.vertices.emplace_back(float(p[0]), float(p[1]), float(p[2]));
    return index[p] = std::uint32_t(m.vertices.size() - 1);
  };
  for (const auto& [i, j, k] : voxels) {
    const std::array<int, 3> cell{i, j, k};
    for (int d = 0; d < 3; ++d)
      for (int s : {-1, 1}) {
        std::array<int, 3> nb = cell;
        nb[d] += s;
        if (voxels.count({nb[0], nb[1], nb[2]})) continue;
        const int e1 = (d + 1) % 3, e2 = (d + 2) % 3;  // e1 x e2 = +d
        std::array<int, 3> base = cell;
        if (s > 0) base[d] += 1;
        auto corner = [&](int a, int b) {
          std::array<int, 3> p = base;
          p[e1] += a;
          p[e2] += b;
          return vid(p);
        };
        const std::uint32_t c00 = corner(0, 0), c10 = corner(1, 0), c11 = corner(1, 1),
                            c01 = corner(0, 1);
        if (s > 0) {
          m.triangles.push_back({c00, c10, c11});
          m.triangles.push_back({c00, c11, c01});
        } else {
          m.triangles.push_back({c00, c11, c10});
          m.triangles.push_back({c00, c01, c11});
        }
      }
  }
  return m;
}

}  // namespace xsect::test

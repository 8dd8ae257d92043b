// Topology of a closed triangle mesh taken as the boundary of a solid.
// Watertight: every undirected edge is used by exactly two triangles, traversed in opposite
// directions (closed, edge-manifold, consistently oriented), and no triangle repeats a vertex.
// Surfaces: components of the triangle adjacency through shared edges (two shells touching at a
// single vertex stay two surfaces). Per surface: chi = V - E + F, genus g = 1 - chi/2, signed
// volume sum(a . (b x c)) / 6. The solid's Betti numbers follow (Alexander duality): b0 = surfaces
// with positive volume, b2 = surfaces with negative volume (cavity walls), b1 = sum of genera.
// The Betti numbers are meaningful only when the mesh is watertight.
#include "geometry/meshing/mesh_topology.h"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <stdexcept>

#include "geometry/core/disjoint_sets.h"

namespace xsect {
namespace {

/// One directed edge use, kept in the bucket of its lower vertex lo: the higher vertex hi, and
/// whether it runs lo -> hi in the top bit above its triangle (8 bytes a use instead of 16: the
/// uses were the diagnose stage's memory on a 4000-frame sweep, issue 17). Sorting by (hi, word)
/// sorts by (hi, forward, triangle).
struct EdgeUse {
  static constexpr std::uint32_t kForward = 0x80000000u;
  std::uint32_t hi, word;
  bool forward() const { return word & kForward; }
  std::uint32_t triangle() const { return word & ~kForward; }
  bool operator<(const EdgeUse& o) const { return hi != o.hi ? hi < o.hi : word < o.word; }
};

/// Every directed edge use of a mesh in (lo, hi, forward, triangle) order: counted into buckets by
/// lo (linear in the mesh; a comparison sort of all uses took most of the diagnose stage on large
/// meshes, issue 17), each bucket (the few edges at one vertex) then sorted.
struct EdgeUses {
  std::vector<std::uint32_t> start;  ///< bucket of vertex v: uses [start[v], start[v + 1])
  std::vector<EdgeUse> uses;
  bool degenerate_triangles = false;  ///< a triangle repeats a vertex

  /// Calls f(i, j) for each undirected edge: uses [i, j) of one bucket with one hi.
  template <typename F>
  void forEachEdge(const F& f) const {
    for (std::size_t v = 0; v + 1 < start.size(); ++v)
      for (std::size_t i = start[v]; i < start[v + 1];) {
        std::size_t j = i;
        while (j < start[v + 1] && uses[j].hi == uses[i].hi) ++j;
        f(i, j);
        i = j;
      }
  }
};

EdgeUses edgeUses(const TriangleMesh& mesh) {
  EdgeUses e;
  const std::size_t nt = mesh.triangles.size();
  const std::size_t nv = mesh.vertices.size();
  std::vector<std::uint32_t>& start = e.start;
  start.assign(nv + 1, 0);
  for (std::uint32_t t = 0; t < nt; ++t) {
    const auto& tri = mesh.triangles[t];
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) e.degenerate_triangles = true;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = tri[k], b = tri[(k + 1) % 3];
      if (a != b) ++start[std::min(a, b) + 1];
    }
  }
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  if (nt >= EdgeUse::kForward) throw std::length_error("meshTopology: more than 2^31 triangles");
  std::vector<EdgeUse>& uses = e.uses;
  uses.resize(start[nv]);
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::uint32_t t = 0; t < nt; ++t) {
    const auto& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = tri[k], b = tri[(k + 1) % 3];
      if (a != b) uses[fill[std::min(a, b)]++] = {std::max(a, b), (a < b ? EdgeUse::kForward : 0u) | t};
    }
  }
  tbb::parallel_for(std::size_t(0), nv, [&](std::size_t v) {
    std::sort(uses.begin() + start[v], uses.begin() + start[v + 1]);
  });
  return e;
}

/// Vertices per surface: a vertex shared by two surfaces (touching shells) counts in both. The
/// first surface met at each vertex, and the (rare) further (vertex, surface) pairs apart.
std::vector<long long> verticesPerSurface(const TriangleMesh& mesh, const std::vector<int>& surfaceOf, int surfaces) {
  std::vector<long long> verts(std::size_t(surfaces), 0);
  std::vector<int> firstSurface(mesh.vertices.size(), -1);
  std::vector<std::pair<std::uint32_t, int>> further;
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t)
    for (const std::uint32_t v : mesh.triangles[t]) {
      const int s = surfaceOf[t];
      if (firstSurface[v] < 0) {
        firstSurface[v] = s;
        ++verts[std::size_t(s)];
      } else if (firstSurface[v] != s) {
        further.emplace_back(v, s);
      }
    }
  std::sort(further.begin(), further.end());
  further.erase(std::unique(further.begin(), further.end()), further.end());
  for (const auto& vs : further) ++verts[std::size_t(vs.second)];
  return verts;
}

}  // namespace

MeshTopology meshTopology(const TriangleMesh& mesh) {
  MeshTopology result;
  const std::size_t nt = mesh.triangles.size();
  if (nt == 0) return result;

  const EdgeUses e = edgeUses(mesh);
  const std::vector<EdgeUse>& uses = e.uses;
  bool watertight = !e.degenerate_triangles;

  // Group uses by undirected edge: connectivity and the closedness test.
  DisjointSets sets(nt);
  e.forEachEdge([&](std::size_t i, std::size_t j) {
    if (j - i != 2 || uses[i].forward() == uses[i + 1].forward()) watertight = false;
    for (std::size_t k = i + 1; k < j; ++k) sets.unite(uses[i].triangle(), uses[k].triangle());
  });
  result.watertight = watertight;

  // Number the surfaces by their smallest triangle (deterministic order).
  std::vector<int> surfaceOf(nt, -1);
  std::vector<std::uint32_t> rootToSurface(nt, UINT32_MAX);
  int surfaces = 0;
  for (std::uint32_t t = 0; t < nt; ++t) {
    const std::uint32_t r = std::uint32_t(sets.find(t));
    if (rootToSurface[r] == UINT32_MAX) rootToSurface[r] = std::uint32_t(surfaces++);
    surfaceOf[t] = int(rootToSurface[r]);
  }
  result.surfaces = surfaces;

  std::vector<long long> faces(surfaces, 0), edges(surfaces, 0);
  std::vector<double> volume(surfaces, 0.0);
  // Volumes are translation invariant for closed surfaces: measure from a mesh vertex to keep
  // the products small when the mesh lies far from the origin.
  const Eigen::Vector3d ref = mesh.vertices[mesh.triangles[0][0]].cast<double>();
  for (std::uint32_t t = 0; t < nt; ++t) {
    const auto& tri = mesh.triangles[t];
    const int s = surfaceOf[t];
    ++faces[s];
    const Eigen::Vector3d a = mesh.vertices[tri[0]].cast<double>() - ref;
    const Eigen::Vector3d b = mesh.vertices[tri[1]].cast<double>() - ref;
    const Eigen::Vector3d c = mesh.vertices[tri[2]].cast<double>() - ref;
    volume[s] += a.dot(b.cross(c)) / 6.0;
  }
  e.forEachEdge([&](std::size_t i, std::size_t) { ++edges[surfaceOf[uses[i].triangle()]]; });
  const std::vector<long long> verts = verticesPerSurface(mesh, surfaceOf, surfaces);

  Betti betti{0, 0, 0};
  double total = 0.0;
  for (int s = 0; s < surfaces; ++s) {
    const long long chi = verts[s] - edges[s] + faces[s];
    const long long genus = (2 - chi) / 2;
    if (volume[s] > 0) ++betti[0];
    if (volume[s] < 0) ++betti[2];
    betti[1] += int(std::max<long long>(genus, 0));
    total += volume[s];
  }
  result.betti = betti;
  result.volume_mm3 = total;
  return result;
}

}  // namespace xsect

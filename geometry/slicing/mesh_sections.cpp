// Rings of a mesh's crossing with a plane, chained through the crossed edges (see mesh_sections.h).
#include "geometry/slicing/mesh_sections.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <unordered_map>

#include "geometry/core/polygon.h"
#include "geometry/core/ring_validity.h"

namespace xsect {

std::vector<Section> meshSections(const TriangleMesh& mesh, const Plane& plane) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& v : mesh.vertices) lo = lo.cwiseMin(v.cast<double>()), hi = hi.cwiseMax(v.cast<double>());
  const double extent = mesh.vertices.empty() ? 0.0 : (hi - lo).norm();
  // A vertex on the plane is moved off it, to the normal's side, by far less than anything the
  // mesh resolves (1e-9 of its size): the crossings next to it are then distinct points of simple
  // rings, not one point that several rings (or one ring twice) would pass through.
  const double lift = 1e-9 * std::max(extent, 1e-300);
  std::vector<double> s(mesh.vertices.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    s[i] = plane.signedDistance(mesh.vertices[i].cast<double>());
    if (s[i] == 0) s[i] = lift;
  }
  const auto above = [&](std::uint32_t i) { return s[i] > 0; };

  // One point per crossed edge, shared by the edge's two triangles.
  std::unordered_map<std::uint64_t, std::uint32_t> pointOfEdge;
  std::vector<Vec2> points;
  std::vector<std::array<std::int64_t, 2>> link;  // each point's two neighbours along its ring
  const auto pointOn = [&](std::uint32_t a, std::uint32_t b) {
    if (a > b) std::swap(a, b);
    const std::uint64_t key = (std::uint64_t(a) << 32) | b;
    const auto [it, added] = pointOfEdge.emplace(key, std::uint32_t(points.size()));
    if (added) {
      const Vec3 xa = mesh.vertices[a].cast<double>(), xb = mesh.vertices[b].cast<double>();
      const double t = s[a] / (s[a] - s[b]);
      points.push_back(plane.toPlane(xa + t * (xb - xa)));
      link.push_back({-1, -1});
    }
    return it->second;
  };
  const auto join = [&](std::uint32_t p, std::uint32_t q) {
    for (const auto& [from, to] : {std::pair{p, q}, std::pair{q, p}}) {
      auto& l = link[from];
      if (l[0] < 0) l[0] = to;
      else if (l[1] < 0) l[1] = to;
      else throw std::invalid_argument("the mesh is not closed where the plane crosses it (an edge shared by more than two triangles)");
    }
  };
  for (const auto& t : mesh.triangles) {
    std::uint32_t crossing[2];
    int n = 0;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k], b = t[(k + 1) % 3];
      if (above(a) != above(b)) crossing[n++] = pointOn(a, b);
    }
    if (n == 2) join(crossing[0], crossing[1]);
  }

  // Rings: walk each point's links.
  std::vector<Ring> rings;
  std::vector<char> used(points.size(), 0);
  for (std::size_t start = 0; start < points.size(); ++start) {
    if (used[start]) continue;
    Ring ring;
    std::int64_t prev = -1, at = std::int64_t(start);
    while (at >= 0 && !used[std::size_t(at)]) {
      used[std::size_t(at)] = 1;
      ring.push_back(points[std::size_t(at)]);
      const auto& l = link[std::size_t(at)];
      if (l[0] < 0 || l[1] < 0)
        throw std::invalid_argument("the mesh is not closed where the plane crosses it (an open chain of crossings)");
      const std::int64_t next = l[0] != prev ? l[0] : l[1];
      prev = at;
      at = next;
    }
    ring = withoutRepeatedVertices(ring);
    const double tiny = 1e-12 * std::max(extent * extent, 1e-300);
    if (ring.size() < 3 || std::abs(signedArea(ring)) <= tiny) continue;  // the plane touches the mesh
    if (!ringIsSimple(ring))
      throw std::invalid_argument("the section crosses itself (the mesh intersects itself there)");
    rings.push_back(std::move(ring));
  }

  // Nesting by containment (rings of a closed mesh's crossing do not cross one another).
  std::vector<int> depth(rings.size(), 0);
  for (std::size_t r = 0; r < rings.size(); ++r)
    for (std::size_t q = 0; q < rings.size(); ++q)
      if (q != r && ringContains(rings[q], rings[r][0])) ++depth[r];
  std::vector<Ring> outers, holes;  // oriented by sectionsFromRings
  for (std::size_t r = 0; r < rings.size(); ++r) (depth[r] % 2 == 1 ? holes : outers).push_back(std::move(rings[r]));
  return sectionsFromRings(std::move(outers), std::move(holes));
}

}  // namespace xsect

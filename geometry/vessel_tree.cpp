// Growth of the vessel-tree phantom (see vessel_tree.h).
#include "geometry/vessel_tree.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "geometry/random_streams.h"

namespace xsect {

double segmentDistance(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1) {
  // Minimise |a0 + s da - b0 - t db| over [0,1]^2: the minimum is either interior (solve the 2x2
  // normal equations) or on one of the four edges (point-to-segment distances).
  const Vec3 da = a1 - a0, db = b1 - b0, r = a0 - b0;
  auto pointSeg = [](const Vec3& p, const Vec3& q0, const Vec3& q1) {
    const Vec3 d = q1 - q0;
    const double l2 = d.squaredNorm();
    const double t = l2 > 0 ? std::clamp((p - q0).dot(d) / l2, 0.0, 1.0) : 0.0;
    return (q0 + t * d - p).norm();
  };
  double best = std::min({pointSeg(a0, b0, b1), pointSeg(a1, b0, b1), pointSeg(b0, a0, a1),
                          pointSeg(b1, a0, a1)});
  const double a = da.squaredNorm(), b = da.dot(db), c = db.squaredNorm();
  const double d = da.dot(r), e = db.dot(r);
  const double den = a * c - b * b;
  if (den > 1e-12 * a * c) {
    const double s = (b * e - c * d) / den, t = (a * e - b * d) / den;
    if (s > 0 && s < 1 && t > 0 && t < 1) best = std::min(best, (r + s * da - t * db).norm());
  }
  return best;
}

std::vector<PhantomShape::Tube> growVesselTree(const VesselTreeParams& p) {
  struct Node {
    PhantomShape::Tube tube;
    int parent;
    double length;
  };
  std::vector<Node> nodes{{{Vec3::Zero(), Vec3(0, 0, p.length), p.radius}, -1, p.length}};
  const double alpha = p.branch_angle_deg * M_PI / 180.0;
  std::mt19937_64 rng = makeStream(p.seed, 0x7472656555ULL /* "treeU" */, 0);
  std::vector<int> tips{0};
  auto adjacent = [&](int i, int j) {
    return nodes[i].parent == j || nodes[j].parent == i ||
           (nodes[i].parent >= 0 && nodes[i].parent == nodes[j].parent);
  };
  auto clear = [&](int i) {
    for (int j = 0; j < int(nodes.size()); ++j) {
      if (j == i || adjacent(i, j)) continue;
      const auto& a = nodes[i].tube;
      const auto& b = nodes[j].tube;
      const double need = a.radius + b.radius + 0.5 * std::min(a.radius, b.radius);
      if (segmentDistance(a.a, a.b, b.a, b.b) <= need) return false;
    }
    return true;
  };
  for (int level = 0; level < p.levels; ++level) {
    std::vector<int> next;
    for (const int tip : tips) {
      const Node parent = nodes[tip];
      bool placed = false;
      for (int attempt = 0; attempt < 256 && !placed; ++attempt) {
        const double phi = uniform(rng, 0.0, 2.0 * M_PI);
        const double len = parent.length * p.length_ratio;
        const double rad = parent.tube.radius * p.radius_ratio;
        const std::size_t first = nodes.size();
        for (int side = 0; side < 2; ++side) {
          const double az = phi + side * M_PI;
          const Vec3 dir(std::sin(alpha) * std::cos(az), std::sin(alpha) * std::sin(az),
                         std::cos(alpha));
          nodes.push_back({{parent.tube.b, parent.tube.b + len * dir, rad}, tip, len});
        }
        placed = clear(int(first)) && clear(int(first) + 1);
        if (!placed) {
          nodes.resize(first);
        } else {
          next.push_back(int(first));
          next.push_back(int(first) + 1);
        }
      }
      if (!placed)
        throw std::runtime_error(
            "vessel_tree: cannot grow branches without contact; reduce levels or radius, or "
            "increase length or branch_angle_deg");
    }
    tips = next;
  }
  std::vector<PhantomShape::Tube> out;
  out.reserve(nodes.size());
  for (const auto& n : nodes) out.push_back(n.tube);
  return out;
}

}  // namespace xsect

// Snapping mesh vertices onto the prisms over the section contours (see conformal_snap.h).
#include "geometry/conformal_snap.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>

namespace xsect {

namespace {

/// Moves x parallel to plane P so that its projection lands on ∂S_P (Newton steps on f_P).
/// Returns false when there is no contour within the raster's band.
bool snapOnto(const Plane& P, const SectionDistanceField& f, Vec3& x) {
  const Vec2 start = P.toPlane(x);
  Vec2 q = start;
  const double e = 0.25 * f.step;
  for (int it = 0; it < 4; ++it) {
    const double v = f.sample(q.x(), q.y());
    if (std::abs(v) >= f.band) return false;
    if (std::abs(v) <= 1e-4 * f.step) break;  // converged
    const Vec2 g((f.sample(q.x() + e, q.y()) - f.sample(q.x() - e, q.y())) / (2 * e),
                 (f.sample(q.x(), q.y() + e) - f.sample(q.x(), q.y() - e)) / (2 * e));
    const double g2 = g.squaredNorm();
    if (g2 < 1e-6) return false;
    q -= v * g / g2;
  }
  x += (q.x() - start.x()) * P.u + (q.y() - start.y()) * P.v;
  return true;
}

bool onContour(const Plane& P, const SectionDistanceField& f, const Vec3& x) {
  const Vec2 q = P.toPlane(x);
  return std::abs(f.sample(q.x(), q.y())) <= 1e-3 * f.step;
}

}  // namespace

SnapStats snapToSectionContours(TriangleMesh& mesh, const std::vector<CuttingPlane>& planes,
                                const std::vector<SectionDistanceField>& fields, double reach,
                                double max_move) {
  const std::size_t n = mesh.vertices.size();
  std::vector<float> moved(n, 0.0f);
  tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
    const Vec3 x = mesh.vertices[i].cast<double>();
    int best = -1;
    double bestDist = std::numeric_limits<double>::infinity();
    for (std::size_t p = 0; p < planes.size(); ++p) {
      const double d = std::abs(planes[p].plane.signedDistance(x));
      if (d < bestDist) {
        bestDist = d;
        best = int(p);
      }
    }
    if (best < 0 || bestDist > reach || planes[best].sections.empty()) return;
    // Transversal planes also within reach: near their crossing line with the nearest plane the
    // vertex should sit on both prisms (both sections agree on the line, R follows both walls).
    std::vector<int> constraints{best};
    const Vec3& n = planes[best].plane.normal;
    for (std::size_t p = 0; p < planes.size(); ++p)
      if (int(p) != best && !planes[p].sections.empty() &&
          std::abs(planes[p].plane.signedDistance(x)) <= reach &&
          std::abs(planes[p].plane.normal.dot(n)) < 0.87)
        constraints.push_back(int(p));
    const auto attempt = [&](std::size_t count, Vec3& y) {
      y = x;
      for (int round = 0; round < (count > 1 ? 12 : 1); ++round) {
        for (std::size_t c = 0; c < count; ++c)
          if (!snapOnto(planes[constraints[c]].plane, fields[constraints[c]], y)) return false;
        bool all = true;  // alternating projections converged?
        for (std::size_t c = 0; c < count && all; ++c)
          all = onContour(planes[constraints[c]].plane, fields[constraints[c]], y);
        if (all) break;
      }
      for (std::size_t c = 0; c < count; ++c)
        if (!onContour(planes[constraints[c]].plane, fields[constraints[c]], y)) return false;
      return (y - x).norm() <= max_move;
    };
    Vec3 y;
    if (!attempt(constraints.size(), y) && (constraints.size() == 1 || !attempt(1, y))) return;
    mesh.vertices[i] = y.cast<float>();
    moved[i] = float((y - x).norm());
  });
  SnapStats s;
  for (float m : moved)
    if (m > 0) {
      ++s.moved;
      s.max_move_mm = std::max(s.max_move_mm, double(m));
    }
  return s;
}

}  // namespace xsect

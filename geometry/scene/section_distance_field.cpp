// Section distance raster (see section_distance_field.h). Distances: each contour edge updates the
// nodes within `band` of it (O(edges * (band/step)^2)). Signs: even-odd crossings of the contour
// edges with each raster row, edges bucketed by the rows they span.
#include "geometry/scene/section_distance_field.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace xsect {

SectionDistanceField sectionDistanceField(const std::vector<Section>& sections, double step,
                                          double band) {
  if (!(step > 0)) throw std::invalid_argument("section distance raster: step must be positive");
  if (!(band > step)) throw std::invalid_argument("section distance raster: band must exceed step");
  SectionDistanceField f;
  f.step = step;
  f.band = float(band);
  std::vector<std::pair<Vec2, Vec2>> edges;
  Vec2 lo = Vec2::Constant(1e300), hi = Vec2::Constant(-1e300);
  const auto addRing = [&](const Ring& r) {
    for (std::size_t i = 0, n = r.size(); i < n; ++i) {
      edges.emplace_back(r[i], r[(i + 1) % n]);
      lo = lo.cwiseMin(r[i]);
      hi = hi.cwiseMax(r[i]);
    }
  };
  for (const auto& s : sections) {
    addRing(s.outer);
    for (const auto& h : s.holes) addRing(h);
  }
  if (edges.empty()) return f;
  // Raster covers the sections' bounds grown by the band, nodes on a lattice of `step`.
  f.origin = Vec2(std::floor((lo.x() - band) / step) * step, std::floor((lo.y() - band) / step) * step);
  f.nu = int(std::ceil((hi.x() + band - f.origin.x()) / step)) + 2;
  f.nv = int(std::ceil((hi.y() + band - f.origin.y()) / step)) + 2;
  f.values.assign(std::size_t(f.nu) * f.nv, float(band));

  // Unsigned distance within the band.
  for (const auto& [a, b] : edges) {
    const Vec2 emin = a.cwiseMin(b), emax = a.cwiseMax(b);
    const int i0 = std::max(0, int(std::floor((emin.x() - band - f.origin.x()) / step)));
    const int i1 = std::min(f.nu - 1, int(std::ceil((emax.x() + band - f.origin.x()) / step)));
    const int j0 = std::max(0, int(std::floor((emin.y() - band - f.origin.y()) / step)));
    const int j1 = std::min(f.nv - 1, int(std::ceil((emax.y() + band - f.origin.y()) / step)));
    const Vec2 d = b - a;
    const double l2 = d.squaredNorm();
    for (int j = j0; j <= j1; ++j) {
      float* row = &f.values[std::size_t(j) * f.nu];
      for (int i = i0; i <= i1; ++i) {
        const Vec2 p = f.origin + step * Vec2(i, j);
        const double t = l2 > 0 ? std::clamp((p - a).dot(d) / l2, 0.0, 1.0) : 0.0;
        const float dist = float((a + t * d - p).norm());
        if (dist < row[i]) row[i] = dist;
      }
    }
  }
  // Sign by even-odd crossings along each row.
  std::vector<std::vector<double>> crossings(f.nv);
  for (const auto& [a, b] : edges) {
    if (a.y() == b.y()) continue;
    const double ya = (a.y() - f.origin.y()) / step, yb = (b.y() - f.origin.y()) / step;
    const int j0 = std::max(0, int(std::ceil(std::min(ya, yb))));
    const int j1 = std::min(f.nv - 1, int(std::floor(std::max(ya, yb))));
    for (int j = j0; j <= j1; ++j) {
      const double y = double(j);
      // half-open rule: count the edge when y in [min, max)
      if (!((ya <= y && y < yb) || (yb <= y && y < ya))) continue;
      const double t = (y - ya) / (yb - ya);
      crossings[j].push_back((a.x() - f.origin.x()) / step + t * (b.x() - a.x()) / step);
    }
  }
  for (int j = 0; j < f.nv; ++j) {
    auto& c = crossings[j];
    std::sort(c.begin(), c.end());
    float* row = &f.values[std::size_t(j) * f.nu];
    for (std::size_t k = 0; k + 1 < c.size(); k += 2) {
      const int i0 = std::max(0, int(std::ceil(c[k])));
      const int i1 = std::min(f.nu - 1, int(std::ceil(c[k + 1])) - 1);
      for (int i = i0; i <= i1; ++i) row[i] = -row[i];
    }
  }
  return f;
}

}  // namespace xsect

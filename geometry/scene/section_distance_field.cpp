// Section distance raster (see section_distance_field.h). Distances: each contour edge updates the
// nodes within `band` of it (O(edges * (band/step)^2)). Signs: even-odd crossings of the contour
// edges with each raster row, edges bucketed by the rows they span.
#include "geometry/scene/section_distance_field.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace xsect {

namespace {

/// The edges of every ring of the sections, their bounds grown into lo..hi.
std::vector<std::pair<Vec2, Vec2>> sectionEdges(const std::vector<Section>& sections, Vec2& lo, Vec2& hi) {
  std::vector<std::pair<Vec2, Vec2>> edges;
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
  return edges;
}

/// Per raster row j (0..rows-1, at origin.y + j step), where the edges cross it, in node units
/// along the row (unsorted); an edge counts when the row's y is in [its lower y, its upper y).
std::vector<std::vector<double>> rowCrossings(const std::vector<std::pair<Vec2, Vec2>>& edges, const Vec2& origin,
                                              double step, int rows) {
  std::vector<std::vector<double>> crossings(static_cast<std::size_t>(rows));
  for (const auto& [a, b] : edges) {
    if (a.y() == b.y()) continue;
    const double ya = (a.y() - origin.y()) / step, yb = (b.y() - origin.y()) / step;
    const int j0 = std::max(0, int(std::ceil(std::min(ya, yb))));
    const int j1 = std::min(rows - 1, int(std::floor(std::max(ya, yb))));
    for (int j = j0; j <= j1; ++j) {
      const double y = double(j);
      if (!((ya <= y && y < yb) || (yb <= y && y < ya))) continue;
      const double t = (y - ya) / (yb - ya);
      crossings[std::size_t(j)].push_back((a.x() - origin.x()) / step + t * (b.x() - a.x()) / step);
    }
  }
  return crossings;
}

}  // namespace

SectionDistanceField sectionDistanceField(const std::vector<Section>& sections, double step,
                                          double band) {
  if (!(step > 0)) throw std::invalid_argument("section distance raster: step must be positive");
  if (!(band > step)) throw std::invalid_argument("section distance raster: band must exceed step");
  SectionDistanceField f;
  f.step = step;
  f.band = float(band);
  Vec2 lo = Vec2::Constant(1e300), hi = Vec2::Constant(-1e300);
  const std::vector<std::pair<Vec2, Vec2>> edges = sectionEdges(sections, lo, hi);
  if (edges.empty()) return f;
  // Raster covers the sections' bounds grown by the band, nodes on a lattice of `step`.
  f.origin = Vec2(std::floor((lo.x() - band) / step) * step, std::floor((lo.y() - band) / step) * step);
  f.nu = int(std::ceil((hi.x() + band - f.origin.x()) / step)) + 2;
  f.nv = int(std::ceil((hi.y() + band - f.origin.y()) / step)) + 2;
  const int T = SectionDistanceField::kTile;
  f.tilesU_ = (f.nu + T - 1) / T;
  f.tilesV_ = (f.nv + T - 1) / T;
  f.tiles_.assign(std::size_t(f.tilesU_) * std::size_t(f.tilesV_), SectionDistanceField::kOutside);

  // The nodes each edge may bring within the band, and the tiles holding them, stored.
  struct Range {
    int i0, i1, j0, j1;
  };
  std::vector<Range> ranges(edges.size());
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const auto& [a, b] = edges[e];
    const Vec2 emin = a.cwiseMin(b), emax = a.cwiseMax(b);
    Range& r = ranges[e];
    r.i0 = std::max(0, int(std::floor((emin.x() - band - f.origin.x()) / step)));
    r.i1 = std::min(f.nu - 1, int(std::ceil((emax.x() + band - f.origin.x()) / step)));
    r.j0 = std::max(0, int(std::floor((emin.y() - band - f.origin.y()) / step)));
    r.j1 = std::min(f.nv - 1, int(std::ceil((emax.y() + band - f.origin.y()) / step)));
    for (int tv = r.j0 / T; tv <= r.j1 / T; ++tv)
      for (int tu = r.i0 / T; tu <= r.i1 / T; ++tu) {
        std::int32_t& t = f.tiles_[std::size_t(tv) * std::size_t(f.tilesU_) + std::size_t(tu)];
        if (t >= 0) continue;
        t = std::int32_t(f.pool_.size() / SectionDistanceField::kTileNodes);
        f.pool_.resize(f.pool_.size() + SectionDistanceField::kTileNodes, float(band));
      }
  }

  // Unsigned distance within the band.
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const auto& [a, b] = edges[e];
    const Range& r = ranges[e];
    const Vec2 d = b - a;
    const double l2 = d.squaredNorm();
    for (int j = r.j0; j <= r.j1; ++j)
      for (int i = r.i0; i <= r.i1; ++i) {
        const Vec2 p = f.origin + step * Vec2(i, j);
        const double t = l2 > 0 ? std::clamp((p - a).dot(d) / l2, 0.0, 1.0) : 0.0;
        const float dist = float((a + t * d - p).norm());
        float& v = f.stored(i, j);
        if (dist < v) v = dist;
      }
  }
  // Sign by even-odd crossings along each row.
  std::vector<std::vector<double>> crossings = rowCrossings(edges, f.origin, step, f.nv);
  for (int j = 0; j < f.nv; ++j) {
    auto& c = crossings[j];
    std::sort(c.begin(), c.end());
    const int tv = j / T;
    for (std::size_t k = 0; k + 1 < c.size(); k += 2) {
      const int i0 = std::max(0, int(std::ceil(c[k])));
      const int i1 = std::min(f.nu - 1, int(std::ceil(c[k + 1])) - 1);
      for (int i = i0; i <= i1;) {  // stored tiles node by node; the others below
        const int tileEnd = std::min(i1, (i / T) * T + T - 1);
        if (f.tiles_[std::size_t(tv) * std::size_t(f.tilesU_) + std::size_t(i / T)] >= 0)
          for (int q = i; q <= tileEnd; ++q) f.stored(q, j) = -f.stored(q, j);
        i = tileEnd + 1;
      }
    }
    // A tile no contour comes within the band of lies on one side of the contours: its first
    // node's side, read on its first row, is the tile's.
    if (j % T != 0) continue;
    for (int tu = 0; tu < f.tilesU_; ++tu) {
      std::int32_t& t = f.tiles_[std::size_t(tv) * std::size_t(f.tilesU_) + std::size_t(tu)];
      if (t >= 0) continue;
      const int i = tu * T;
      bool in = false;
      for (std::size_t k = 0; k + 1 < c.size() && !in; k += 2)
        in = std::max(0, int(std::ceil(c[k]))) <= i && i <= int(std::ceil(c[k + 1])) - 1;
      if (in) t = SectionDistanceField::kInside;
    }
  }
  return f;
}

SectionDistanceField SectionDistanceField::fromNodes(const Vec2& origin, double step, int nu, int nv, float band,
                                                     const std::vector<float>& values) {
  if (values.size() != std::size_t(nu) * std::size_t(nv))
    throw std::invalid_argument("section distance raster: values do not match the node counts");
  SectionDistanceField f;
  f.origin = origin;
  f.step = step;
  f.nu = nu;
  f.nv = nv;
  f.band = band;
  const int T = kTile;
  f.tilesU_ = (nu + T - 1) / T;
  f.tilesV_ = (nv + T - 1) / T;
  f.tiles_.assign(std::size_t(f.tilesU_) * std::size_t(f.tilesV_), kOutside);
  for (int tv = 0; tv < f.tilesV_; ++tv)
    for (int tu = 0; tu < f.tilesU_; ++tu) {
      const int i1 = std::min(nu, (tu + 1) * T), j1 = std::min(nv, (tv + 1) * T);
      const float first = values[std::size_t(tv * T) * std::size_t(nu) + std::size_t(tu * T)];
      bool uniform = first == band || first == -band;
      for (int j = tv * T; j < j1 && uniform; ++j)
        for (int i = tu * T; i < i1 && uniform; ++i) uniform = values[std::size_t(j) * std::size_t(nu) + std::size_t(i)] == first;
      std::int32_t& t = f.tiles_[std::size_t(tv) * std::size_t(f.tilesU_) + std::size_t(tu)];
      if (uniform) {
        t = first == band ? kOutside : kInside;
        continue;
      }
      t = std::int32_t(f.pool_.size() / kTileNodes);
      f.pool_.resize(f.pool_.size() + kTileNodes, band);
      for (int j = tv * T; j < j1; ++j)
        for (int i = tu * T; i < i1; ++i) f.stored(i, j) = values[std::size_t(j) * std::size_t(nu) + std::size_t(i)];
    }
  return f;
}

}  // namespace xsect

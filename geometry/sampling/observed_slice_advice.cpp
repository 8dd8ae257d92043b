// Greedy slice advice on the Ω-cells (see observed_slice_advice.h).
#include "geometry/sampling/observed_slice_advice.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "geometry/core/plane_of_pose.h"

namespace xsect {

namespace {

/// The Ω-cells followed by the advice (observed_slice_advice.h), indexed by Ω-cell.
struct FollowedOmegaCells {
  std::vector<double> critical;                  ///< the least critical value of its cells, mm; NaN: none known
  std::vector<std::vector<std::size_t>> points;  ///< its lattice points, in scan order (open Ω-cells only)
  std::vector<std::vector<Vec3>> where;          ///< where they are, mm
  std::vector<char> followed;
};

/// The Ω-cells with a cell not shown satisfied that the lattice meets, those holding sections if
/// any does (where the object is known to be), and each one's critical value.
FollowedOmegaCells followedOmegaCells(const SamplingDiagnosis& d) {
  const bool densityFirst = d.density == SamplingVerdict::violated ||
                            (d.transversality != SamplingVerdict::violated && d.density != SamplingVerdict::satisfied);
  const CellScan& scan = d.scan;
  const std::size_t omegas = std::size_t(d.observed_cells);
  FollowedOmegaCells f;
  std::vector<double>& critical = f.critical;
  critical.assign(omegas, std::numeric_limits<double>::quiet_NaN());
  std::vector<char> open(omegas, 0), sections(omegas, 0);
  for (std::size_t i = 0; i < d.cells.size(); ++i) {
    const CellSampling& c = d.cells[i];
    if (c.observed_cell < 0) continue;
    const std::size_t o = std::size_t(c.observed_cell);
    sections[o] = sections[o] || holdsSections(c);
    if (c.verdict != SamplingVerdict::satisfied) open[o] = 1;
    const double crit = densityFirst || !std::isfinite(c.transversality.critical_mm) ? c.density.critical_mm
                                                                                     : c.transversality.critical_mm;
    if (std::isfinite(crit) && crit > 0) critical[o] = std::isnan(critical[o]) ? crit : std::min(critical[o], crit);
  }
  // The lattice points of each open Ω-cell, in scan order, and where they are.
  const GridSpec& L = scan.lattice;
  std::vector<std::vector<std::size_t>>& points = f.points;
  std::vector<std::vector<Vec3>>& where = f.where;
  points.resize(omegas);
  where.resize(omegas);
  for (int k = 0; k < L.dims[2]; ++k)
    for (int j = 0; j < L.dims[1]; ++j)
      for (int i = 0; i < L.dims[0]; ++i) {
        const std::size_t q = std::size_t(L.index(i, j, k));
        const int cell = scan.cell_of_point[q];
        if (cell < 0) continue;
        const int o = d.cells[std::size_t(cell)].observed_cell;
        if (o < 0 || !open[std::size_t(o)]) continue;
        points[std::size_t(o)].push_back(q);
        where[std::size_t(o)].push_back(L.centre(i, j, k));
      }
  // Followed: the open Ω-cells the lattice meets, those holding sections if any does.
  const bool anySections = [&] {
    for (std::size_t o = 0; o < omegas; ++o)
      if (open[o] && sections[o] && !points[o].empty()) return true;
    return false;
  }();
  std::vector<char>& followed = f.followed;
  followed.assign(omegas, 0);
  for (std::size_t o = 0; o < omegas; ++o)
    followed[o] = open[o] && !points[o].empty() && (sections[o] || !anySections);
  return f;
}

}  // namespace

std::vector<AdvisedSlice> adviseObservedSlices(const SamplingDiagnosis& d, const AdviceParams& params) {
  std::vector<AdvisedSlice> out;
  const CellScan& scan = d.scan;
  const std::size_t n = scan.cell_of_point.size();
  if (d.observed_distance_mm.size() != n) throw std::invalid_argument("adviseObservedSlices: no distances to the pieces");
  if (params.count <= 0 || d.observed_cells <= 0) return out;
  const double rho = scan.half_diagonal_mm;

  const FollowedOmegaCells f = followedOmegaCells(d);
  const std::vector<double>& critical = f.critical;
  const std::vector<std::vector<std::size_t>>& points = f.points;
  const std::vector<std::vector<Vec3>>& where = f.where;
  const std::vector<char>& followed = f.followed;
  const std::size_t omegas = critical.size();
  bool anyCritical = false;
  double minCritical = std::numeric_limits<double>::infinity();
  for (std::size_t o = 0; o < omegas; ++o)
    if (followed[o] && !std::isnan(critical[o])) anyCritical = true, minCritical = std::min(minCritical, critical[o]);

  std::vector<double> distance = d.observed_distance_mm;  // lowered by each slice advised
  // Each followed Ω-cell's deepest point (its place in points[o], first in scan order) and ratio.
  const auto deepest = [&](std::size_t o) {
    std::size_t best = 0;
    for (std::size_t e = 1; e < points[o].size(); ++e)
      if (distance[points[o][e]] > distance[points[o][best]]) best = e;
    return best;
  };
  const auto score = [&](std::size_t o, std::size_t e) {
    const double h = std::max(rho, distance[points[o][e]] + rho);
    if (!anyCritical) return h;
    return h / (std::isnan(critical[o]) ? minCritical : critical[o]);
  };
  const auto worst = [&](std::size_t* at) {
    int w = -1;
    double s = -1;
    for (std::size_t o = 0; o < omegas; ++o) {
      if (!followed[o] || points[o].empty()) continue;
      const std::size_t e = deepest(o);
      if (score(o, e) > s) s = score(o, e), w = int(o), *at = e;
    }
    return w;
  };

  const std::vector<Vec3> dirs = adviceDirections();
  std::vector<double> largest(dirs.size());
  for (int it = 0; it < params.count; ++it) {
    std::size_t e0 = 0;
    const int w = worst(&e0);
    if (w < 0) break;
    const double before = score(std::size_t(w), e0);
    if (params.until_resolved && anyCritical && before < 1) break;
    const std::vector<std::size_t>& ps = points[std::size_t(w)];
    const std::vector<Vec3>& xs = where[std::size_t(w)];
    if (!(distance[ps[e0]] > 0)) break;
    const Vec3 c = xs[e0];
    // The direction whose plane leaves the least largest distance over the Ω-cell's points.
    tbb::parallel_for(std::size_t(0), dirs.size(), [&](std::size_t k) {
      double m = 0;
      for (std::size_t e = 0; e < ps.size(); ++e)
        m = std::max(m, std::min(distance[ps[e]], std::abs(dirs[k].dot(xs[e] - c))));
      largest[k] = m;
    });
    std::size_t best = 0;
    for (std::size_t k = 1; k < dirs.size(); ++k)
      if (largest[k] < largest[best] - 1e-12) best = k;
    const Plane added = planeThrough(c, dirs[best]);
    // Only the followed Ω-cells' points are read again.
    tbb::parallel_for(std::size_t(0), omegas, [&](std::size_t o) {
      for (std::size_t e = 0; e < points[o].size(); ++e)
        distance[points[o][e]] = std::min(distance[points[o][e]], std::abs(added.signedDistance(where[o][e])));
    });
    AdvisedSlice a;
    a.plane = added;
    a.cell = scan.cell_of_point[ps[e0]];  // the cell of the diagnosis the slice goes through
    a.worst_before = before;
    std::size_t e1 = 0;
    const int after = worst(&e1);
    a.worst_after = after < 0 ? 0.0 : score(std::size_t(after), e1);
    a.ratio = anyCritical;
    out.push_back(a);
  }
  return out;
}

}  // namespace xsect

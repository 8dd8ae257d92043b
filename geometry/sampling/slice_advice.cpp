// Greedy slice advice (see slice_advice.h).
#include "geometry/sampling/slice_advice.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "geometry/core/plane_of_pose.h"
#include "geometry/sampling/cell_height.h"

namespace xsect {

namespace {

struct Followed {
  std::vector<int> sides;   ///< against every plane, the added ones included
  double critical = 0;      ///< mm; NaN: unknown
  CellHeight height;
  int cell = -1;
};

/// The cells followed: the worst that are not shown satisfied, at most `followed`, each with its
/// critical value and its height (the diagnosis' where exact, else measured in the box lo..hi).
/// Density first (the sections' connectivity, Thm 3): the cells are ranked by their density ratio
/// while the Density Condition is violated somewhere, or undetermined with nothing violated; else
/// by their transversality ratio. Cells holding sections first: where the object is known to be,
/// the connectivity of its sections is at stake; cells without sections only matter for what the
/// planes miss (Prop. 2).
std::vector<Followed> followedCells(const std::vector<Plane>& ps, const CellKeys& keys, const SamplingDiagnosis& d,
                                    const Vec3& lo, const Vec3& hi, int followed) {
  const bool densityFirst = d.density == SamplingVerdict::violated ||
                            (d.transversality != SamplingVerdict::violated && d.density != SamplingVerdict::satisfied);
  std::vector<int> order;
  for (int pass = 0; pass < 2 && order.empty(); ++pass)
    for (std::size_t i = 0; i < d.cells.size(); ++i)
      if (d.cells[i].verdict != SamplingVerdict::satisfied && (pass == 1 || holdsSections(d.cells[i])) &&
          (d.cells[i].scanned >= 0 || d.cells[i].height_exact))  // else its centre lies on a plane
        order.push_back(int(i));
  const auto score0 = [&](const CellSampling& c) {
    const double crit = densityFirst ? c.density.critical_mm : c.transversality.critical_mm;
    return std::isfinite(crit) && crit > 0 ? c.height_hi_mm / crit : -1.0;
  };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    const CellSampling &ca = d.cells[std::size_t(a)], &cb = d.cells[std::size_t(b)];
    if (score0(ca) != score0(cb)) return score0(ca) > score0(cb);
    return ca.height_hi_mm > cb.height_hi_mm;
  });
  if (int(order.size()) > followed) order.resize(std::size_t(followed));
  std::vector<Followed> cells(order.size());
  tbb::parallel_for(std::size_t(0), order.size(), [&](std::size_t k) {
    const CellSampling& c = d.cells[std::size_t(order[k])];
    Followed& f = cells[k];
    f.cell = order[k];
    const double crit = densityFirst || !std::isfinite(c.transversality.critical_mm) ? c.density.critical_mm
                                                                                     : c.transversality.critical_mm;
    f.critical = std::isfinite(crit) && crit > 0 ? crit : std::nan("");
    f.sides = keys.sides(c.centre);
    if (!c.height_exact || c.scanned < 0) {
      f.height = cellHeight(ps, f.sides, lo, hi, false);
    } else {
      f.height.height = c.height_hi_mm;
      f.height.centre = c.centre;
    }
  });
  return cells;
}

/// Of the planes through the target's centre along `dirs`, the one whose larger half of the cell
/// (the heights on either side, in the box lo..hi) is the smallest.
Plane halvingPlane(const std::vector<Plane>& ps, const Followed& target, const std::vector<Vec3>& dirs, const Vec3& lo,
                   const Vec3& hi) {
  const Vec3 c = target.height.centre;
  std::vector<double> halves(dirs.size() * 2, 0);
  tbb::parallel_for(std::size_t(0), halves.size(), [&](std::size_t h) {
    std::vector<Plane> local = ps;
    local.push_back(planeThrough(c, dirs[h / 2]));
    std::vector<int> sides = target.sides;
    sides.push_back(h % 2 ? 1 : -1);
    // The target's facets from the start (its ball's bounding planes, then the new one): only the
    // heights are compared, and they do not depend on the rows a program starts with.
    std::vector<int> first = target.height.bounding_planes;
    first.push_back(int(ps.size()));
    halves[h] = cellHeight(local, sides, lo, hi, false, first).height;
  });
  std::size_t best = 0;
  for (std::size_t k = 0; k < dirs.size(); ++k)
    if (std::max(halves[2 * k], halves[2 * k + 1]) < std::max(halves[2 * best], halves[2 * best + 1]) - 1e-12)
      best = k;
  return planeThrough(c, dirs[best]);
}

}  // namespace

std::vector<Vec3> adviceDirections() {
  std::vector<Vec3> d;
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z) {
        const Vec3 v(x, y, z);
        // One of each ± pair: the first non-zero coordinate positive.
        if (v.isZero() || (x < 0) || (x == 0 && y < 0) || (x == 0 && y == 0 && z < 0)) continue;
        d.push_back(v.normalized());
      }
  return d;  // 13
}

std::vector<AdvisedSlice> adviseSlices(const std::vector<CuttingPlane>& planes, const SamplingDiagnosis& d,
                                       const Vec3& lo, const Vec3& hi, const AdviceParams& params) {
  std::vector<AdvisedSlice> out;
  if (params.count <= 0) return out;
  std::vector<Plane> ps;
  for (const CuttingPlane& p : planes) ps.push_back(p.plane);
  const CellKeys keys(ps);
  const Vec3 pad = Vec3::Constant(1e-6 * (hi - lo).norm());

  std::vector<Followed> cells = followedCells(ps, keys, d, lo - pad, hi + pad, params.followed_cells);
  bool anyCritical = false;
  for (const Followed& f : cells) anyCritical = anyCritical || !std::isnan(f.critical);
  double minCritical = INFINITY;
  for (const Followed& f : cells)
    if (!std::isnan(f.critical)) minCritical = std::min(minCritical, f.critical);
  // Ratios where critical values are known (cells without one are measured against the least known);
  // heights otherwise.
  const auto score = [&](const Followed& f) {
    if (!anyCritical) return f.height.height;
    return f.height.height / (std::isnan(f.critical) ? minCritical : f.critical);
  };
  const auto worst = [&]() {
    int w = -1;
    for (std::size_t k = 0; k < cells.size(); ++k)
      if (w < 0 || score(cells[k]) > score(cells[std::size_t(w)])) w = int(k);
    return w;
  };

  const std::vector<Vec3> dirs = adviceDirections();
  for (int it = 0; it < params.count && !cells.empty(); ++it) {
    const int w = worst();
    const Followed target = cells[std::size_t(w)];  // a copy: `cells` grows below
    const double before = score(target);
    if (params.until_resolved && anyCritical && before < 1) break;
    if (target.height.height <= 0) break;
    const Plane added = halvingPlane(ps, target, dirs, lo - pad, hi + pad);
    ps.push_back(added);
    // Every followed cell the new plane crosses is re-measured on the side of its ball's centre; the
    // other side becomes a followed cell of its own.
    std::vector<std::size_t> remeasure;
    const std::size_t n = cells.size();
    for (std::size_t k = 0; k < n; ++k) {
      const double s = added.signedDistance(cells[k].height.centre);
      cells[k].sides.push_back(s > 0 ? 1 : -1);
      if (std::abs(s) >= cells[k].height.height) continue;
      remeasure.push_back(k);
      Followed other = cells[k];
      other.sides.back() = -other.sides.back();
      cells.push_back(other);
      remeasure.push_back(cells.size() - 1);
    }
    tbb::parallel_for(std::size_t(0), remeasure.size(), [&](std::size_t k) {
      Followed& f = cells[remeasure[k]];
      f.height = cellHeight(ps, f.sides, lo - pad, hi + pad, false);
    });
    AdvisedSlice a;
    a.plane = added;
    a.cell = target.cell;
    a.worst_before = before;
    a.worst_after = score(cells[std::size_t(worst())]);
    a.ratio = anyCritical;
    out.push_back(a);
  }
  return out;
}

}  // namespace xsect

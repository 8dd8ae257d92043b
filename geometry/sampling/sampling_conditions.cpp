// Per-cell sampling conditions and the verdict (see sampling_conditions.h).
#include "geometry/sampling/sampling_conditions.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "geometry/sampling/cell_height.h"
#include "geometry/sampling/cell_interior.h"
#include "geometry/sampling/observed_cells.h"

namespace xsect {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kDegree = 3.14159265358979323846 / 180.0;

/// A critical value as known: `sat` the value a height must stay below for the condition to be
/// shown (NaN: a prior it needs is missing), `vio` the value a height reaching shows it violated
/// (+inf: nothing known), `data` whether `vio` comes from the data's bounds alone.
struct Critical {
  double sat = kNaN, vio = kInf;
  bool data = false;
};

Critical sideOf(const std::optional<double>& prior, double bound) {
  Critical k;
  k.sat = prior ? std::min(*prior, bound) : kNaN;
  k.vio = prior ? std::min(*prior, bound) : bound;
  k.data = std::isfinite(bound) && (!prior || bound < *prior);
  return k;
}

Critical lesser(const Critical& a, const Critical& b) {
  Critical k;
  k.sat = std::isnan(a.sat) || std::isnan(b.sat) ? kNaN : std::min(a.sat, b.sat);
  const Critical& v = a.vio <= b.vio ? a : b;
  k.vio = v.vio;
  k.data = v.data;
  return k;
}

Critical scaled(const Critical& k, double satFactor, double vioFactor, bool data) {
  return {std::isnan(satFactor) ? kNaN : satFactor * k.sat, vioFactor * k.vio, data};
}

double transversalFactor(double alpha_deg) { return 0.5 * (1 - std::sin(alpha_deg * kDegree)); }

ConditionCheck check(double lo, double hi, const Critical& k) {
  ConditionCheck c;
  if (!std::isnan(k.sat) && hi < k.sat) {
    c.verdict = SamplingVerdict::satisfied;
    c.critical_mm = k.sat;
  } else if (std::isfinite(k.vio) && lo >= k.vio) {
    c.verdict = SamplingVerdict::violated;
    c.critical_mm = k.vio;
    c.from_data = k.data;
  } else {
    c.critical_mm = std::isnan(k.sat) ? k.vio : k.sat;
  }
  return c;
}

bool straddles(double lo, double hi, const Critical& k) {
  return (!std::isnan(k.sat) && lo < k.sat && hi >= k.sat) || (std::isfinite(k.vio) && lo < k.vio && hi >= k.vio);
}

SamplingVerdict combine(SamplingVerdict a, SamplingVerdict b) {
  if (a == SamplingVerdict::violated || b == SamplingVerdict::violated) return SamplingVerdict::violated;
  if (a == SamplingVerdict::satisfied && b == SamplingVerdict::satisfied) return SamplingVerdict::satisfied;
  return SamplingVerdict::undetermined;
}

/// The critical values of a cell's two conditions (see the header for the definitions).
void criticalsOf(const CellSampling& c, ReconstructionMethod method, const SamplingPrior& prior, Critical* density,
                 Critical* transversality) {
  const bool sections = holdsSections(c);
  const Critical ri = sideOf(prior.reach_interior_mm, c.interior_bound_mm);
  const Critical re = sideOf(prior.reach_exterior_mm, c.exterior_bound_mm);
  const Critical reach = lesser(ri, re);
  // α_C: 0 without contour points; else the prior raised to what was measured (unknown without a
  // prior when showing the condition; what was measured, or 0, when showing a violation).
  // Measured angles raise the prior as measured, and count with their margin taken off when they
  // show a violation (alpha_lower_deg).
  const double measured = c.alpha_samples > 0 ? c.alpha_max_deg : 0.0;
  const double measuredLow = c.alpha_samples > 0 ? c.alpha_lower_deg : 0.0;
  const double alphaSat = !sections ? 0.0 : prior.max_angle_deg ? std::max(*prior.max_angle_deg, measured) : kNaN;
  const double alphaVio = !sections ? 0.0 : prior.max_angle_deg ? std::max(*prior.max_angle_deg, measuredLow) : measuredLow;
  const bool alphaData = !prior.max_angle_deg || measuredLow >= *prior.max_angle_deg;
  const double fSat = std::isnan(alphaSat) ? kNaN : transversalFactor(alphaSat);
  if (!sections) {
    // O ∩ ∂C is empty: either O misses C, where R misses it too and the conditions hold trivially
    // (np(m) ∉ O for every m in C), or a component of O lies inside C, holding a medial ball of
    // radius ≥ reach_i (Prop. 2). h_C < reach_i rules the second case out, for both methods.
    *density = ri;
    *transversality = ri;
    return;
  }
  if (method == ReconstructionMethod::nearest_plane) {
    *density = reach;  // C1; for a cell without sections it also covers Prop. 2
    *transversality = scaled(reach, fSat, transversalFactor(alphaVio), reach.data && alphaData);  // C2
    return;
  }
  *density = re;  // C'1
  // C'3 holds per contour point a: h'_C < ½(1 − sin α_a)·reach(a). A crossing bounds it at once
  // (transversal_bound_mm); elsewhere α_a ≥ 0 leaves ½·reach. The largest α and the least reach of
  // the cell are not those of one point, so they are not combined as for C2.
  Critical t;
  // Shown with a prior on every α_a (raised to what was measured) and on the reach, lowered to
  // what the crossings allow.
  t.sat = std::isnan(fSat) || std::isnan(reach.sat) ? kNaN : std::min(fSat * reach.sat, c.transversal_bound_mm);
  t.vio = 0.5 * reach.vio;
  t.data = reach.data;
  if (prior.max_angle_deg && !std::isnan(fSat)) {  // the prior bounds every α_a: its product
    const double v = transversalFactor(*prior.max_angle_deg) * reach.vio;
    if (v < t.vio) t.vio = v, t.data = false;
  }
  if (c.transversal_bound_mm < t.vio) t.vio = c.transversal_bound_mm, t.data = true;
  *transversality = t;
}

/// The verdict of a cell's conditions: satisfied when C1 and C2 are shown, or (method 1) C1 and
/// the Intersection Condition shown on the data in C2's place; otherwise violated when C1 or C2 is
/// shown violated (C2 is violated as a condition even where the data show the Intersection
/// Condition: the guarantee then rests on C1, not shown), else undetermined.
SamplingVerdict cellVerdict(SamplingVerdict density, SamplingVerdict transversality, SamplingVerdict intersection,
                            ReconstructionMethod method) {
  if (method == ReconstructionMethod::nearest_plane && density == SamplingVerdict::satisfied &&
      intersection == SamplingVerdict::satisfied)
    return SamplingVerdict::satisfied;
  return combine(density, transversality);
}

void evaluate(CellSampling& c, ReconstructionMethod method, const SamplingPrior& prior) {
  Critical d, t;
  criticalsOf(c, method, prior, &d, &t);
  // Method 2 on a cell with sections: the height is h'_C ≥ h_C, bounded above where computed.
  const bool sectionHeight = method == ReconstructionMethod::section_voronoi && holdsSections(c);
  const double hi = sectionHeight ? c.section_height_hi_mm : c.height_hi_mm;
  c.density = check(c.height_lo_mm, hi, d);
  c.transversality = check(c.height_lo_mm, hi, t);
  if (c.observed_members > 1 && holdsSections(c)) {
    // An Ω-cell of several cells is not convex. Of the thesis' results, Lemma 3 and Thm 3 (the
    // sections joined as in O) rest on balls only and hold on it; Prop. 2 (a piece may lie inside
    // O, its section without contour: method 2's C'1 through Thm 21) and the topological theorems
    // (Thm 14-16, Lemma 6; Thm 23-24) use convex cells with whole faces and fail on it (docs/methods.md,
    // "Observed pieces"). So only method 1's C1 may be shown there; violations stand (a condition
    // not met shows nothing either way). An Ω-cell without sections keeps its one condition: a
    // component of O inside it would hold a ball of radius reach_i touching no piece, whatever
    // the cell's shape, and where there is none, R misses the cell as O does.
    if (method != ReconstructionMethod::nearest_plane && c.density.verdict == SamplingVerdict::satisfied)
      c.density.verdict = SamplingVerdict::undetermined;
    if (c.transversality.verdict == SamplingVerdict::satisfied) c.transversality.verdict = SamplingVerdict::undetermined;
  }
  c.verdict = cellVerdict(c.density.verdict, c.transversality.verdict, c.intersection, method);
  const double crit = std::isfinite(c.transversality.critical_mm) ? c.transversality.critical_mm
                                                                   : c.density.critical_mm;
  const double height = sectionHeight && std::isfinite(hi) ? hi : c.height_hi_mm;
  c.ratio = std::isfinite(crit) && crit > 0 ? height / crit : kNaN;
}

bool needsExactHeight(const CellSampling& c, ReconstructionMethod method, const SamplingPrior& prior) {
  if (c.height_exact) return false;
  Critical d, t;
  criticalsOf(c, method, prior, &d, &t);
  return straddles(c.height_lo_mm, c.height_hi_mm, d) || straddles(c.height_lo_mm, c.height_hi_mm, t);
}

/// Method 2: upper bounds of h'_C (section_cell_height.h) for the cells with sections where they
/// may show a condition (every prior it needs given, the lower bound below it), then for the
/// worst cells, within the budget. `keyPoints[k]`: the point that keyed
/// arrangement cell k (for cells met by no lattice point).
void boundSectionHeights(SamplingDiagnosis& out, const std::vector<Plane>& ps, const CellKeys& keys,
                         const std::vector<CuttingPlane>& planes, const SectionArrangement& arrangement,
                         const std::vector<KeyPoint>& keyPoints, const Vec3& lo, const Vec3& hi,
                         const SamplingParams& params) {
  std::vector<int> decisive, worst;
  std::vector<double> target(out.cells.size(), 0.0);
  for (std::size_t i = 0; i < out.cells.size(); ++i) {
    const CellSampling& c = out.cells[i];
    // An Ω-cell of several cells is no convex polytope: its h'_C is not bounded (stays +inf).
    if (c.arrangement_cell < 0 || c.observed_members > 1) continue;
    Critical d, t;
    criticalsOf(c, out.method, out.prior, &d, &t);
    const double sat = std::isnan(d.sat) || std::isnan(t.sat) ? kNaN : std::min(d.sat, t.sat);
    if (!std::isnan(sat) && c.height_lo_mm < sat) {
      decisive.push_back(int(i));
      target[i] = sat;
    } else {
      worst.push_back(int(i));
    }
  }
  const auto deeper = [&](int a, int b) {
    const double ha = out.cells[std::size_t(a)].height_lo_mm, hb = out.cells[std::size_t(b)].height_lo_mm;
    return ha != hb ? ha > hb : a < b;
  };
  std::sort(decisive.begin(), decisive.end(), deeper);
  const std::size_t shownWorst = std::min<std::size_t>(20, worst.size());
  std::partial_sort(worst.begin(), worst.begin() + std::ptrdiff_t(shownWorst), worst.end(), deeper);
  std::vector<int> todo(decisive.begin(),
                        decisive.begin() + std::ptrdiff_t(std::min<std::size_t>(decisive.size(),
                                                                                std::size_t(params.section_height_cells))));
  todo.insert(todo.end(), worst.begin(), worst.begin() + std::ptrdiff_t(shownWorst));
  // The points of S_C of the arrangement cells to bound (a trace point bounds up to four cells).
  std::vector<int> slot(std::size_t(std::max(arrangement.cells, 0)), -1);
  for (std::size_t e = 0; e < todo.size(); ++e) slot[std::size_t(out.cells[std::size_t(todo[e])].arrangement_cell)] = int(e);
  std::vector<std::vector<Vec3>> pointsOf(todo.size());
  for (const SectionPoint& s : arrangement.points)
    for (int k = 0; k < 2; ++k)
      for (const int cell : {s.cell[std::size_t(k)], s.cell_alt[std::size_t(k)]})
        if (cell >= 0 && slot[std::size_t(cell)] >= 0)
          pointsOf[std::size_t(slot[std::size_t(cell)])].push_back(planes[std::size_t(s.plane)].plane.toWorld(s.p));
  const double resolution = std::max(arrangement.sample_spacing_mm, 1e-9 * (hi - lo).norm());
  const Vec3 pad = Vec3::Constant(1e-6 * (hi - lo).norm());
  tbb::parallel_for(std::size_t(0), todo.size(), [&](std::size_t e) {
    CellSampling& c = out.cells[std::size_t(todo[e])];
    std::vector<int> sides;
    Vec3 interior;
    const Interior found = cellInterior(c, ps, keys, keyPoints, lo - pad, hi + pad, &sides, &interior);
    if (found == Interior::none) c.section_height_hi_mm = c.height_lo_mm;  // no open region: nothing to reach
    if (found != Interior::found) return;
    const SectionHeightBound b = sectionHeightBound(ps, sides, interior, lo - pad, hi + pad, pointsOf[e],
                                                    target[std::size_t(todo[e])], resolution, params.section_height);
    c.section_height_hi_mm = b.upper_mm;  // ≥ h'_C ≥ h_C: sampling.json lets a test check it
    c.section_farthest = b.farthest;
  });
  out.section_height_max_mm = 0;
  for (const CellSampling& c : out.cells) {
    if (!holdsSections(c)) continue;
    out.section_height_cells += std::isfinite(c.section_height_hi_mm);
    out.section_height_max_mm = std::max(out.section_height_max_mm, c.section_height_hi_mm);
  }
}

/// Method 1: the Intersection Condition on the data (intersection_condition.h) in the cells with
/// sections where C1 is shown, largest heights first, within the budget; cells without sections
/// hold it trivially.
void checkIntersection(SamplingDiagnosis& out, const std::vector<Plane>& ps,
                       const std::vector<SectionDistanceField>& fields, const CellKeys& keys,
                       const std::vector<KeyPoint>& keyPoints, const Vec3& lo, const Vec3& hi, double voxel_mm,
                       const SamplingParams& params) {
  CellTopologyParams tp = params.cell_topology;
  if (!(tp.max_spacing_mm > 0)) tp.max_spacing_mm = voxel_mm;
  std::vector<int> todo;
  for (std::size_t i = 0; i < out.cells.size(); ++i) {
    CellSampling& c = out.cells[i];
    c.intersection = holdsSections(c) ? SamplingVerdict::undetermined : SamplingVerdict::satisfied;
    // An Ω-cell of several cells is not sampled (R_C is sampled over a convex cell): undetermined.
    if (c.arrangement_cell >= 0 && c.observed_members == 1 && c.density.verdict == SamplingVerdict::satisfied)
      todo.push_back(int(i));
  }
  std::sort(todo.begin(), todo.end(), [&](int a, int b) {
    const double ha = out.cells[std::size_t(a)].height_hi_mm, hb = out.cells[std::size_t(b)].height_hi_mm;
    return ha != hb ? ha > hb : a < b;
  });
  if (todo.size() > std::size_t(params.intersection_cells)) {
    out.intersection_unsampled += int(todo.size()) - params.intersection_cells;
    todo.resize(std::size_t(params.intersection_cells));
  }
  const Vec3 pad = Vec3::Constant(1e-6 * (hi - lo).norm());
  std::vector<CellReconstructionTopology> topo(todo.size());
  tbb::parallel_for(std::size_t(0), todo.size(), [&](std::size_t e) {
    CellSampling& c = out.cells[std::size_t(todo[e])];
    std::vector<int> sides;
    Vec3 interior;
    const Interior found = cellInterior(c, ps, keys, keyPoints, lo - pad, hi + pad, &sides, &interior);
    if (found == Interior::none) {  // no open region: R_C is empty, the condition holds trivially
      topo[e].sampled = true;
      return;
    }
    if (found != Interior::found) return;
    topo[e] = cellReconstructionTopology(ps, fields, sides, interior, lo - pad, hi + pad, tp);
  });
  for (std::size_t e = 0; e < todo.size(); ++e) {
    CellSampling& c = out.cells[std::size_t(todo[e])];
    if (!topo[e].sampled) {
      ++out.intersection_unsampled;
      continue;
    }
    ++out.intersection_checked;
    if (topo[e].contractible()) {
      c.intersection = SamplingVerdict::satisfied;
    } else {
      ++out.intersection_not_contractible;
    }
  }
}

/// Observed pieces: every cell takes its Ω-cell's height (max of D_Ω over the Ω-cell's lattice
/// points, observed_cells.h) and the data's bounds and angles of all the Ω-cell's cells (its
/// boundary is theirs, less the unobserved faces between them). A cell only the arrangement meets,
/// in an Ω-cell of its own, keeps h ≤ ρ: a point of it farther than ρ from the pieces lies within
/// ρ of a lattice point that it reaches through no piece, so it belongs to that point's Ω-cell and
/// is counted there (where the lattice sees the passage: observed_cells.h).
void joinObservedCells(SamplingDiagnosis& out, ObservedCells oc) {
  const CellScan& scan = out.scan;
  const std::size_t scanned = scan.cells.size();
  const auto omegaOf = [&](std::size_t i) {
    return i < scanned ? oc.cell_of_scanned[i] : oc.cell_of_extra[i - scanned];
  };
  struct Joined {
    double height = -1, lower = 0;  ///< max of D_Ω over its lattice points (-1: none), and its lower bound
    Vec3 centre = Vec3::Zero();
    bool end = false, sections = false;
    double interior = kInf, exterior = kInf, transversal = kInf;
    double alphaMax = kNaN, alphaLower = 0, alphaEstimated = kNaN;
    int alphaSamples = 0;
  };
  std::vector<Joined> joined(std::size_t(oc.count));
  const auto larger = [](double a, double b) { return std::isnan(a) ? b : std::isnan(b) ? a : std::max(a, b); };
  for (std::size_t i = 0; i < out.cells.size(); ++i) {  // scanned cells first, in scan order
    const CellSampling& c = out.cells[i];
    Joined& g = joined[std::size_t(omegaOf(i))];
    if (i < scanned) {
      if (oc.max_distance_mm[i] > g.height) g.height = oc.max_distance_mm[i], g.centre = oc.farthest[i];
      g.lower = std::max(g.lower, oc.max_distance_lo_mm[i]);
    }
    g.end = g.end || c.end_cell;
    g.sections = g.sections || c.arrangement_cell >= 0;
    g.interior = std::min(g.interior, c.interior_bound_mm);
    g.exterior = std::min(g.exterior, c.exterior_bound_mm);
    g.transversal = std::min(g.transversal, c.transversal_bound_mm);
    if (c.alpha_samples > 0) g.alphaMax = larger(g.alphaMax, c.alpha_max_deg);
    g.alphaLower = std::max(g.alphaLower, c.alpha_lower_deg);
    g.alphaSamples += c.alpha_samples;
    g.alphaEstimated = larger(g.alphaEstimated, c.alpha_estimated_deg);
  }
  for (std::size_t i = 0; i < out.cells.size(); ++i) {
    CellSampling& c = out.cells[i];
    const int id = omegaOf(i);
    const Joined& g = joined[std::size_t(id)];
    c.observed_cell = id;
    c.observed_members = oc.members[std::size_t(id)];
    c.observed_cell_sections = g.sections;
    if (g.height >= 0) {  // else an Ω-cell the lattice does not meet: h ≤ ρ (above)
      c.height_lo_mm = g.lower;
      c.height_hi_mm = std::max(scan.half_diagonal_mm, g.height + scan.half_diagonal_mm);
      c.centre = g.centre;
    }
    c.end_cell = g.end;
    c.interior_bound_mm = g.interior;
    c.exterior_bound_mm = g.exterior;
    c.transversal_bound_mm = g.transversal;
    c.alpha_max_deg = g.alphaMax;
    c.alpha_lower_deg = g.alphaLower;
    c.alpha_samples = g.alphaSamples;
    c.alpha_estimated_deg = g.alphaEstimated;
    out.cells_joined += c.observed_members > 1;
    out.cells_joined_with_sections += c.observed_members > 1 && g.sections;
  }
  out.observed_cells = oc.count;
  out.unobserved_crossings = oc.unobserved_crossings;
  out.observed_distance_mm = std::move(oc.distance_mm);
}

/// Worst first: larger ratio, then larger height, then scan order.
bool worse(const CellSampling& a, const CellSampling& b, int ia, int ib) {
  const double ra = std::isnan(a.ratio) ? -1 : a.ratio, rb = std::isnan(b.ratio) ? -1 : b.ratio;
  if (ra != rb) return ra > rb;
  if (a.height_hi_mm != b.height_hi_mm) return a.height_hi_mm > b.height_hi_mm;
  return ia < ib;
}

}  // namespace

/// The arrangement's cells keyed (sign vectors) among the scanned ones: per arrangement cell, the
/// diagnosis' cell (cellOfArrangement, -1: none) and the point that keyed it; cells only the
/// arrangement meets are appended to out.cells (their height only bounded by ρ).
struct ArrangementCells {
  std::vector<int> cell_of_arrangement;
  std::vector<KeyPoint> key_points;
};

ArrangementCells keyArrangementCells(const std::vector<CuttingPlane>& planes, const SectionArrangement& arrangement,
                                     const CellKeys& keys, const Vec3& lo, const Vec3& hi,
                                     std::unordered_map<std::uint64_t, int>& cellOfKey, SamplingDiagnosis& out) {
  const CellScan& scan = out.scan;
  // The arrangement's cells (those bounded by a section): the key of a point of theirs that lies on
  // no other plane, on the cell's side of its own plane.
  const int nArr = arrangement.cells;
  struct Candidate {
    int point = -1, side = 0;  ///< side of the point's own plane (0: negative)
    int traceSide = 0;         ///< trace points: side of the trace plane (±1)
  };
  struct Candidates {  // up to four points of the cell
    std::array<Candidate, 4> at;
    int count = 0;
    const Candidate* begin() const { return at.data(); }
    const Candidate* end() const { return at.data() + count; }
  };
  std::vector<Candidates> candidates(std::size_t(std::max(nArr, 0)));
  const auto addCandidate = [&](int cell, const Candidate& c) {
    if (cell < 0) return;
    Candidates& cs = candidates[std::size_t(cell)];
    if (cs.count < 4) cs.at[std::size_t(cs.count++)] = c;
  };
  // Vertices and samples first (they lie on one plane), then trace points (on two).
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t i = 0; i < arrangement.points.size(); ++i) {
      const SectionPoint& s = arrangement.points[i];
      if ((s.kind == SectionPoint::trace) != (pass == 1)) continue;
      for (int side = 0; side < 2; ++side) {
        addCandidate(s.cell[std::size_t(side)], {int(i), side, s.kind == SectionPoint::trace ? 1 : 0});
        if (s.kind == SectionPoint::trace) addCandidate(s.cell_alt[std::size_t(side)], {int(i), side, -1});
      }
    }
  std::vector<std::uint64_t> arrKey(candidates.size(), 0);
  std::vector<Vec3> arrPoint(candidates.size(), Vec3::Zero());
  std::vector<char> arrFound(candidates.size(), 0);
  ArrangementCells result;
  std::vector<KeyPoint>& keyPoints = result.key_points;
  keyPoints.resize(candidates.size());
  const double tiny = 1e-9 * (hi - lo).norm();
  tbb::parallel_for(std::size_t(0), candidates.size(), [&](std::size_t cell) {
    for (const Candidate& cand : candidates[cell]) {
      const SectionPoint& s = arrangement.points[std::size_t(cand.point)];
      const Vec3 x = planes[std::size_t(s.plane)].plane.toWorld(s.p);
      // A trace point lies on the trace plane too: its side forced as well.
      KeyPoint kp{s.plane, cand.side ? 1 : -1};
      if (cand.traceSide != 0) kp.trace_plane = s.trace_plane, kp.trace_side = cand.traceSide;
      double clearance = 0;
      const std::uint64_t k = keys.of(x, kp.plane, kp.side, &clearance, kp.trace_plane, kp.trace_side);
      kp.generic = clearance > tiny;
      if (kp.generic || !arrFound[cell]) arrKey[cell] = k, arrPoint[cell] = x, arrFound[cell] = 1, keyPoints[cell] = kp;
      if (kp.generic) break;
    }
  });
  std::vector<int>& cellOfArrangement = result.cell_of_arrangement;
  cellOfArrangement.assign(candidates.size(), -1);
  for (std::size_t cell = 0; cell < candidates.size(); ++cell) {
    if (!arrFound[cell]) {  // no point of it listed (not expected): nothing is shown
      ++out.unmatched_cells;
      continue;
    }
    const auto it = cellOfKey.find(arrKey[cell]);
    if (it != cellOfKey.end()) {
      CellSampling& c = out.cells[std::size_t(it->second)];
      if (c.arrangement_cell < 0) c.arrangement_cell = int(cell);
      cellOfArrangement[cell] = it->second;
      continue;
    }
    cellOfArrangement[cell] = int(out.cells.size());
    CellSampling c;  // no lattice point inside: h_C ≤ ρ
    c.key = arrKey[cell];
    c.arrangement_cell = int(cell);
    c.height_hi_mm = scan.half_diagonal_mm;
    c.centre = arrPoint[cell];
    cellOfKey.emplace(c.key, int(out.cells.size()));
    out.cells.push_back(c);
  }

  return result;
}

/// Angles and reach bounds where contours cross, given to the four cells around each crossing.
void addCrossingBounds(const std::vector<CuttingPlane>& planes, const SectionArrangement& arrangement,
                       const CellKeys& keys, const Vec3& lo, const Vec3& hi, double tolerance_mm,
                       const SamplingParams& params, const std::unordered_map<std::uint64_t, int>& cellOfKey,
                       SamplingDiagnosis& out) {
  out.crossings = contourCrossings(planes, arrangement, tolerance_mm, params.crossings);
  const double eps = 1e-7 * (hi - lo).norm();
  for (const ContourCrossing& x : out.crossings) {
    const Vec3 na = planes[std::size_t(x.plane_a)].plane.normal, nb = planes[std::size_t(x.plane_b)].plane.normal;
    const double alpha = std::max(x.alpha_a_deg, x.alpha_b_deg);
    const double reachBound = std::min(x.interior_bound_mm, x.exterior_bound_mm);
    const double transversal =
        std::min(transversalFactor(std::max(0.0, x.alpha_a_deg - x.alpha_margin_deg)),
                 transversalFactor(std::max(0.0, x.alpha_b_deg - x.alpha_margin_deg))) *
        reachBound;
    out.reach_interior_bound_mm = std::min(out.reach_interior_bound_mm, x.interior_bound_mm);
    out.reach_exterior_bound_mm = std::min(out.reach_exterior_bound_mm, x.exterior_bound_mm);
    out.alpha_max_measured_deg = std::isnan(out.alpha_max_measured_deg) ? alpha : std::max(out.alpha_max_measured_deg, alpha);
    for (int sa = -1; sa <= 1; sa += 2)
      for (int sb = -1; sb <= 1; sb += 2) {
        const auto it = cellOfKey.find(keys.of(x.point + eps * (sa * na + sb * nb)));
        if (it == cellOfKey.end()) continue;
        CellSampling& c = out.cells[std::size_t(it->second)];
        c.alpha_max_deg = c.alpha_samples ? std::max(c.alpha_max_deg, alpha) : alpha;
        c.alpha_lower_deg = std::max(c.alpha_lower_deg, alpha - x.alpha_margin_deg);
        ++c.alpha_samples;
        c.interior_bound_mm = std::min(c.interior_bound_mm, x.interior_bound_mm);
        c.exterior_bound_mm = std::min(c.exterior_bound_mm, x.exterior_bound_mm);
        c.transversal_bound_mm = std::min(c.transversal_bound_mm, transversal);
      }
  }
}

/// α estimated from neighbouring near-parallel slices: reported with the cells, not used.
void addNeighbourAngles(const std::vector<CuttingPlane>& planes, const SectionArrangement& arrangement,
                        double tolerance_mm, const SamplingParams& params, const std::vector<int>& cellOfArrangement,
                        SamplingDiagnosis& out) {
  for (const NeighbourAngle& e : neighbourAngles(planes, arrangement, tolerance_mm, params.neighbour_angles)) {
    out.alpha_estimates_deg.push_back(e.alpha_deg);
    for (const int cell : arrangement.points[std::size_t(e.point)].cell) {
      if (cell < 0 || cellOfArrangement[std::size_t(cell)] < 0) continue;
      CellSampling& c = out.cells[std::size_t(cellOfArrangement[std::size_t(cell)])];
      c.alpha_estimated_deg = std::isnan(c.alpha_estimated_deg) ? e.alpha_deg : std::max(c.alpha_estimated_deg, e.alpha_deg);
    }
  }
}

/// Reach bounds at contour points, given to the cells on both sides of their plane.
void addContourReachBounds(const std::vector<CuttingPlane>& planes, const std::vector<SectionDistanceField>& fields,
                           const SectionArrangement& arrangement, const Vec3& lo, const Vec3& hi, double tolerance_mm,
                           const SamplingParams& params, const std::vector<int>& cellOfArrangement,
                           SamplingDiagnosis& out) {
  for (const ContourReachBound& b : contourReachBounds(planes, fields, arrangement, tolerance_mm, (hi - lo).norm(),
                                                       params.reach_bounds)) {
    if (!std::isfinite(b.interior_mm) && !std::isfinite(b.exterior_mm)) continue;
    ++out.contour_points_bounded;
    out.reach_interior_bound_mm = std::min(out.reach_interior_bound_mm, b.interior_mm);
    out.reach_exterior_bound_mm = std::min(out.reach_exterior_bound_mm, b.exterior_mm);
    for (const int cell : arrangement.points[std::size_t(b.point)].cell) {
      if (cell < 0 || cellOfArrangement[std::size_t(cell)] < 0) continue;
      CellSampling& c = out.cells[std::size_t(cellOfArrangement[std::size_t(cell)])];
      c.interior_bound_mm = std::min(c.interior_bound_mm, b.interior_mm);
      c.exterior_bound_mm = std::min(c.exterior_bound_mm, b.exterior_mm);
    }
  }
}

/// Exact heights (Chebyshev balls) where the lattice's bounds straddle a critical value, then for
/// the worst cells and the largest cell without sections, within the budget. Returns the largest
/// cell without sections (-1: none).
int solveExactHeights(const std::vector<Plane>& ps, const CellKeys& keys, const std::vector<KeyPoint>& keyPoints,
                      const Vec3& lo, const Vec3& hi, ReconstructionMethod method, const SamplingPrior& prior,
                      const SamplingParams& params, SamplingDiagnosis& out) {
  const CellScan& scan = out.scan;
  std::vector<int> order(out.cells.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = int(i);
  const auto worseIndex = [&](int a, int b) {
    return worse(out.cells[std::size_t(a)], out.cells[std::size_t(b)], a, b);
  };
  const std::size_t top = std::min<std::size_t>(20, order.size());
  std::partial_sort(order.begin(), order.begin() + std::ptrdiff_t(top), order.end(), worseIndex);
  std::vector<int> exact;
  std::vector<char> chosen(out.cells.size(), 0);
  const auto choose = [&](int i) {
    // An Ω-cell of several cells is not the convex cell whose Chebyshev ball is solved.
    if (i >= 0 && !chosen[std::size_t(i)] && out.cells[std::size_t(i)].observed_members == 1 &&
        int(exact.size()) < params.exact_cells)
      chosen[std::size_t(i)] = 1, exact.push_back(i);
  };
  int largestEmpty = -1;
  for (std::size_t i = 0; i < out.cells.size(); ++i)
    if (!holdsSections(out.cells[i]) &&
        (largestEmpty < 0 || out.cells[i].height_lo_mm > out.cells[std::size_t(largestEmpty)].height_lo_mm))
      largestEmpty = int(i);
  choose(largestEmpty);
  for (std::size_t i = 0; i < top; ++i) choose(order[i]);
  std::vector<int> straddling;
  for (std::size_t i = 0; i < out.cells.size(); ++i)
    if (needsExactHeight(out.cells[i], method, prior)) straddling.push_back(int(i));
  std::sort(straddling.begin(), straddling.end(), worseIndex);
  for (int i : straddling) choose(i);
  const Vec3 pad = Vec3::Constant(std::max(scan.lattice.voxel, 1e-6 * (hi - lo).norm()));
  tbb::parallel_for(std::size_t(0), exact.size(), [&](std::size_t e) {
    CellSampling& c = out.cells[std::size_t(exact[e])];
    // The signs of its lattice point, or those the section point that keyed it gives.
    const std::vector<int> sides = c.scanned >= 0 ? keys.sides(c.centre)
                                                  : keyPoints[std::size_t(c.arrangement_cell)].sides(keys, c.centre);
    const CellHeight h = cellHeight(ps, sides, lo - pad, hi + pad, false);
    // A ball outside the lattice's bounds means the sign vector named another cell (or none):
    // the bounds stay.
    const double eps = 1e-6 * (hi - lo).norm();
    if (h.open || h.height < c.height_lo_mm - eps || h.height > c.height_hi_mm + eps || keys.of(h.centre) != c.key)
      return;
    if (out.observed_cells > 0) {
      // On the pieces the whole cell's ball is a lower bound of its Ω-cell's height (D_Ω ≥ D); it
      // is the height only if every face lies in a piece, which the lattice does not prove.
      c.height_lo_mm = std::max(c.height_lo_mm, h.height);
      return;
    }
    c.height_lo_mm = c.height_hi_mm = h.height;
    c.height_exact = true;
    c.centre = h.centre;
  });
  for (int i : exact) out.exact_cells += out.cells[std::size_t(i)].height_exact;
  for (int i : exact) evaluate(out.cells[std::size_t(i)], method, prior);
  return largestEmpty;
}

/// The verdicts over all cells. A cell met neither by the lattice nor by a section holds no section
/// and has h_C ≤ ρ: for the guarantee, ρ must pass a cell without sections' conditions.
void combineVerdicts(ReconstructionMethod method, const SamplingPrior& prior, SamplingDiagnosis& out) {
  const CellScan& scan = out.scan;
  out.density = out.transversality = SamplingVerdict::satisfied;
  const bool m1 = method == ReconstructionMethod::nearest_plane;
  out.intersection = m1 ? SamplingVerdict::satisfied : SamplingVerdict::undetermined;
  // Method 1: every cell shows C2 or, in its place, the Intersection Condition.
  bool intersectionEverywhere = m1;
  for (const CellSampling& c : out.cells) {
    out.density = combine(out.density, c.density.verdict);
    out.transversality = combine(out.transversality, c.transversality.verdict);
    out.intersection = combine(out.intersection, c.intersection);
    intersectionEverywhere = intersectionEverywhere && (c.intersection == SamplingVerdict::satisfied ||
                                                        c.transversality.verdict == SamplingVerdict::satisfied);
  }
  CellSampling unmet;  // no section: the Intersection Condition holds there trivially
  unmet.height_hi_mm = scan.half_diagonal_mm;
  evaluate(unmet, method, prior);
  // An unmet cell's height is only bounded above (≤ ρ): it can show a condition, never a violation.
  const auto unmetVerdict = [](SamplingVerdict v) {
    return v == SamplingVerdict::violated ? SamplingVerdict::undetermined : v;
  };
  out.density = combine(out.density, unmetVerdict(unmet.density.verdict));
  out.transversality = combine(out.transversality, unmetVerdict(unmet.transversality.verdict));
  if (out.unmatched_cells > 0) {  // cells holding sections that were not told apart: nothing is shown
    for (SamplingVerdict* v : {&out.density, &out.transversality, &out.intersection})
      if (*v == SamplingVerdict::satisfied) *v = SamplingVerdict::undetermined;
  }
  out.verdict = cellVerdict(out.density, out.transversality,
                            intersectionEverywhere && out.unmatched_cells == 0 ? SamplingVerdict::satisfied
                                                                               : SamplingVerdict::undetermined,
                            method);

}

/// The cells that decide the verdict, the worst 20, one cell per Ω-cell (its cells share its
/// height and ratio).
void listDecidingCells(SamplingDiagnosis& out) {
  const auto worseIndex = [&](int a, int b) {
    return worse(out.cells[std::size_t(a)], out.cells[std::size_t(b)], a, b);
  };
  std::vector<int> deciding;
  for (std::size_t i = 0; i < out.cells.size(); ++i)
    if (out.verdict == SamplingVerdict::satisfied || out.cells[i].verdict == out.verdict) deciding.push_back(int(i));
  std::sort(deciding.begin(), deciding.end(), worseIndex);
  std::unordered_set<int> listed;
  for (const int i : deciding) {
    if (out.deciding.size() == 20) break;
    const int omega = out.cells[std::size_t(i)].observed_cell;
    if (omega < 0 || listed.insert(omega).second) out.deciding.push_back(i);
  }
}

SamplingDiagnosis diagnoseSampling(const std::vector<CuttingPlane>& planes,
                                   const std::vector<SectionDistanceField>& fields, const SectionArrangement& arrangement,
                                   ReconstructionMethod method, const SamplingPrior& prior, const Vec3& lo,
                                   const Vec3& hi, double voxel_mm, double tolerance_mm,
                                   const SamplingParams& params, const std::vector<ObservedPiece>* pieces) {
  SamplingDiagnosis out;
  out.method = method;
  out.prior = prior;
  std::vector<Plane> ps;
  ps.reserve(planes.size());
  for (const CuttingPlane& p : planes) ps.push_back(p.plane);
  const CellKeys keys(ps);
  out.scan = scanCells(ps, keys, lo, hi, scanSpacing(lo, hi, voxel_mm, ps.size(), params.lattice_work));
  const CellScan& scan = out.scan;

  // Scanned cells keep their scan index; cells only the arrangement meets are appended.
  std::unordered_map<std::uint64_t, int> cellOfKey = scan.index_of_key;
  out.cells.reserve(scan.cells.size() + std::size_t(std::max(arrangement.cells, 0)));
  for (std::size_t i = 0; i < scan.cells.size(); ++i) {
    const ScannedCell& s = scan.cells[i];
    CellSampling c;
    c.key = s.key;
    c.scanned = int(i);
    c.height_lo_mm = s.max_distance_mm;
    c.height_hi_mm = scan.heightBound(s);
    c.centre = s.farthest;
    c.end_cell = s.on_box;
    out.cells.push_back(c);
  }

  const ArrangementCells arr = keyArrangementCells(planes, arrangement, keys, lo, hi, cellOfKey, out);
  addCrossingBounds(planes, arrangement, keys, lo, hi, tolerance_mm, params, cellOfKey, out);
  addNeighbourAngles(planes, arrangement, tolerance_mm, params, arr.cell_of_arrangement, out);
  addContourReachBounds(planes, fields, arrangement, lo, hi, tolerance_mm, params, arr.cell_of_arrangement, out);
  if ((prior.reach_interior_mm && *prior.reach_interior_mm > out.reach_interior_bound_mm) ||
      (prior.reach_exterior_mm && *prior.reach_exterior_mm > out.reach_exterior_bound_mm))
    out.prior_contradicted = true;

  if (pieces && pieces->size() == ps.size() &&
      std::any_of(pieces->begin(), pieces->end(), [](const ObservedPiece& p) { return !p.whole; })) {
    std::vector<std::uint64_t> unscanned;  // the cells only the arrangement meets
    for (std::size_t i = scan.cells.size(); i < out.cells.size(); ++i) unscanned.push_back(out.cells[i].key);
    joinObservedCells(out, observedCells(scan, ps, keys, *pieces, unscanned));
  }
  for (CellSampling& c : out.cells) evaluate(c, method, prior);
  const int largestEmpty = solveExactHeights(ps, keys, arr.key_points, lo, hi, method, prior, params, out);
  if (method == ReconstructionMethod::section_voronoi) {
    boundSectionHeights(out, ps, keys, planes, arrangement, arr.key_points, lo, hi, params);
    for (CellSampling& c : out.cells) evaluate(c, method, prior);
  } else {
    checkIntersection(out, ps, fields, keys, arr.key_points, lo, hi, voxel_mm, params);
    for (CellSampling& c : out.cells) evaluate(c, method, prior);
  }
  combineVerdicts(method, prior, out);
  out.largest_empty_cell = largestEmpty;
  listDecidingCells(out);
  return out;
}

std::vector<std::string> samplingConsequences(const SamplingDiagnosis& d) {
  std::vector<std::string> out;
  const bool m1 = d.method == ReconstructionMethod::nearest_plane;
  if (d.density == SamplingVerdict::satisfied && d.cells_joined_with_sections > 0)  // method 1 only (evaluate)
    out.push_back("Separation Condition (Lemma 3) on the cells of the observed pieces: the sections are joined as "
                  "in the object (Thm 3); whether every component of its boundary is cut (Prop. 2) is not shown, "
                  "cells joined through unobserved parts of planes not being convex");
  else if (d.density == SamplingVerdict::satisfied)  // on pieces: Ω-cells with sections are cells of whole planes
    out.push_back(std::string(m1 ? "Separation Condition (Lemma 3): the sections are joined as in the object (Thm 3) "
                                   "and every component of its boundary is cut by "
                                 : "Weak Density Condition: every component of the object's boundary is cut by ") +
                  (d.observed_cells > 0 ? "an observed piece" : "a plane") + (m1 ? " (Prop. 2)" : ""));
  if (m1 && d.intersection == SamplingVerdict::satisfied)
    out.push_back("Intersection Condition shown on the data (§4.4: in every cell, the components of R_C, "
                  "homotopy equivalent to lift(S_C), are contractible, at the resolution of a lattice per cell)");
  if (d.verdict == SamplingVerdict::satisfied)
    out.push_back(m1 ? std::string(d.transversality == SamplingVerdict::satisfied
                                       ? "Transversality Condition (Thm 15), so the Intersection Condition holds"
                                       : "Separation and Intersection Conditions") +
                           ": the reconstruction is homotopy equivalent (Thm 14), homeomorphic and isotopic "
                           "(Thm 16) to the object"
                     : "Weak Density and Transversality Conditions: the reconstruction is homotopy equivalent, "
                       "homeomorphic and isotopic to the object (Thm 23-24); its Hausdorff distance to the object "
                       "is at most max h'_C" +
                           (std::isfinite(d.section_height_max_mm)
                                ? " <= " + std::to_string(d.section_height_max_mm) + " mm"
                                : std::string()) +
                           " (Thm 20) if the Weak Transversality Condition (C'2) holds too, which the data cannot "
                           "show (C'3 is the more restrictive for piecewise linear shapes, remark after Def. 32)");
  return out;
}

}  // namespace xsect

// The sampling diagnosis stage and its JSON (see sampling_stage.h).
#include "pipeline/sampling_stage.h"

#include <algorithm>
#include <cmath>
#include <chrono>
#include <sstream>
#include <tuple>
#include <utility>

#include "geometry/core/median.h"
#include "geometry/sampling/observed_slice_advice.h"
#include "pipeline/json_values.h"

namespace xsect {

using json = nlohmann::ordered_json;

namespace {

json finite(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

const char* name(SamplingVerdict v) { return nameOf(kSamplingVerdicts, v); }

struct ConditionNames {
  const char* density;
  const char* transversality;
};
ConditionNames conditionNames(ReconstructionMethod m) {
  if (m == ReconstructionMethod::nearest_plane) return {"C1 density", "C2 transversality"};
  return {"C'1 weak density", "C'3 transversality"};
}

double medianPixel(const SectionScene& scene) {
  std::vector<double> px;
  for (std::size_t i = 0; i < scene.real_planes; ++i)
    if (scene.planes[i].pixel_mm > 0) px.push_back(scene.planes[i].pixel_mm);
  return upperMedian(std::move(px));  // 0 when no plane knows its pixel (contours given directly)
}

/// The advised plane as an image of the sections' bounds seen on it.
PoseRecord poseOf(const Plane& p, const Vec3& bmin, const Vec3& bmax, double pixel) {
  Vec2 lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
  for (int c = 0; c < 8; ++c) {
    const Vec3 x((c & 1) ? bmax.x() : bmin.x(), (c & 2) ? bmax.y() : bmin.y(), (c & 4) ? bmax.z() : bmin.z());
    const Vec2 q = p.toPlane(x);
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  PoseRecord r;
  r.width = int(std::ceil((hi.x() - lo.x()) / pixel)) + 1;
  r.height = int(std::ceil((hi.y() - lo.y()) / pixel)) + 1;
  r.image_to_world = Mat4::Identity();
  r.image_to_world.block<3, 1>(0, 0) = p.u * pixel;
  r.image_to_world.block<3, 1>(0, 1) = p.v * pixel;
  r.image_to_world.block<3, 1>(0, 2) = p.normal * pixel;
  r.image_to_world.block<3, 1>(0, 3) = p.toWorld(lo);
  return r;
}

json cellJson(const SamplingStage& s, int id) {
  const CellSampling& c = s.diagnosis.cells[std::size_t(id)];
  const ConditionNames n = conditionNames(s.diagnosis.method);
  const bool densityDecides =
      c.density.verdict == c.verdict || c.transversality.verdict == SamplingVerdict::satisfied;
  const ConditionCheck& k = densityDecides ? c.density : c.transversality;
  json j = {{"cell", id},
            {"holds_sections", holdsSections(c)},
            {"end_cell", c.end_cell},
            {"height_mm", c.height_hi_mm},
            {"height_lower_mm", c.height_lo_mm},
            {"height_exact", c.height_exact},
            {"centre_mm", vecJson(c.centre)},
            {"verdict", name(c.verdict)},
            {"condition", densityDecides ? n.density : n.transversality},
            {"critical_mm", finite(k.critical_mm)},
            {"ratio", finite(c.ratio)},
            {"shown_by_data_alone", k.from_data},
            {"alpha_max_deg", finite(c.alpha_max_deg)}};
  if (c.observed_cell >= 0) {
    j["observed_cell"] = c.observed_cell;
    j["observed_cell_joins"] = c.observed_members;
  }
  if (s.diagnosis.method == ReconstructionMethod::section_voronoi && holdsSections(c)) {
    j["section_height_mm"] = finite(c.section_height_hi_mm);
    j["section_height_farthest_mm"] = std::isfinite(c.section_height_hi_mm) ? vecJson(c.section_farthest) : json(nullptr);
  }
  return j;
}

}  // namespace

SamplingPrior samplingPrior(const RunConfig& c) {
  SamplingPrior p;
  p.reach_interior_mm = c.sampling.reach_interior_mm ? c.sampling.reach_interior_mm : c.sampling.reach_mm;
  p.reach_exterior_mm = c.sampling.reach_exterior_mm ? c.sampling.reach_exterior_mm : c.sampling.reach_mm;
  p.max_angle_deg = c.sampling.max_angle_deg;
  return p;
}

SamplingStage samplingStage(const RunConfig& c, const Method& method, const SectionScene& scene,
                            const ArrangeStage& arrangement, bool advise) {
  SamplingStage s;
  const ReconstructionLayout& L = scene.layout;
  s.lo = L.sections_min - Vec3::Constant(L.end_margin_mm);
  s.hi = L.sections_max + Vec3::Constant(L.end_margin_mm);
  const double pixel = medianPixel(scene);
  const double tolerance = std::max(scene.params.voxel_mm, 2 * pixel);
  const auto start = std::chrono::steady_clock::now();
  const auto since = [](std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  };
  s.run_method = method.id();
  s.diagnosis = diagnoseSampling(scene.planes, scene.fields, arrangement.arrangement, method.samplingConditions(),
                                 samplingPrior(c), s.lo, s.hi, scene.params.voxel_mm, tolerance, {}, &scene.pieces);
  s.diagnosis_s = since(start);
  if (!advise || s.diagnosis.verdict == SamplingVerdict::satisfied) return s;
  const auto adviceStart = std::chrono::steady_clock::now();
  // Default: while the Density Condition is violated, slices until every cell passes it (at most as
  // many as the input has, and 30); otherwise 10 (the transversality, where α is near 90°, is
  // rarely brought under its critical value by slices alone).
  const bool densityViolated = s.diagnosis.density == SamplingVerdict::violated;
  const int inputSlices = int(scene.real_planes);
  AdviceParams a;
  if (c.sampling.advice_count) {
    a.count = *c.sampling.advice_count;
  } else {
    a.count = std::min(inputSlices, densityViolated ? 30 : 10);
    a.until_resolved = densityViolated;
  }
  // On the pieces, once cells are joined, on the Ω-cells (whose heights the diagnosis gave).
  s.advice = s.diagnosis.cells_joined > 0 ? adviseObservedSlices(s.diagnosis, a)
                                          : adviseSlices(scene.planes, s.diagnosis, s.lo, s.hi, a);
  s.advice_pixel_mm = pixel > 0 ? pixel : (L.sections_max - L.sections_min).maxCoeff() / 256;
  // An image over the sections' box; on Ω-cells over the end planes' box and two pixels (its piece
  // is eroded by one), as the advice on them takes each slice to observe (observed_slice_advice.h).
  const bool overEndBox = s.diagnosis.cells_joined > 0;
  const Vec3 pad = Vec3::Constant(2 * s.advice_pixel_mm);
  for (const AdvisedSlice& slice : s.advice)
    s.advice_poses.push_back(overEndBox ? poseOf(slice.plane, s.lo - pad, s.hi + pad, s.advice_pixel_mm)
                                        : poseOf(slice.plane, L.sections_min, L.sections_max, s.advice_pixel_mm));
  s.advice_s = since(adviceStart);
  return s;
}

json samplingSummaryJson(const SamplingStage& s) {
  const SamplingDiagnosis& d = s.diagnosis;
  const ConditionNames n = conditionNames(d.method);
  int withSections = 0, counts[3] = {0, 0, 0}, fromData = 0;
  double maxHeight = 0;
  for (const CellSampling& c : d.cells) {
    withSections += holdsSections(c);
    ++counts[int(c.verdict)];
    fromData += c.verdict == SamplingVerdict::violated && (c.density.from_data || c.transversality.from_data);
    maxHeight = std::max(maxHeight, c.height_hi_mm);
  }
  json deciding = json::array();
  for (int id : d.deciding) deciding.push_back(cellJson(s, id));
  json r;
  r["verdict"] = name(d.verdict);
  r["method"] = nameOf(kReconstructionMethods, d.method);
  if (s.run_method != d.method) {
    r["for_method"] = nameOf(kReconstructionMethods, s.run_method);
    r["note"] = "method 3 (delaunay) has no sampling theorem in the thesis: the conditions, verdict and guarantees "
                "are method 2's, for R' (R'' joins at least the sections R' joins: G' is a subgraph of G''); they "
                "say whether the slices suffice for method 2, not that R'' is right";
  }
  r["conditions"] = {{n.density, name(d.density)}, {n.transversality, name(d.transversality)}};
  if (d.method == ReconstructionMethod::nearest_plane)
    r["conditions"]["intersection_on_data"] = name(d.intersection);
  r["guarantees"] = samplingConsequences(d);
  r["prior"] = {{"reach_interior_mm", d.prior.reach_interior_mm ? json(*d.prior.reach_interior_mm) : json(nullptr)},
                {"reach_exterior_mm", d.prior.reach_exterior_mm ? json(*d.prior.reach_exterior_mm) : json(nullptr)},
                {"max_angle_deg", d.prior.max_angle_deg ? json(*d.prior.max_angle_deg) : json(nullptr)}};
  r["prior_contradicted_by_data"] = d.prior_contradicted;
  std::vector<double> est = d.alpha_estimates_deg;
  std::sort(est.begin(), est.end());
  const auto quantile = [&](double q) { return est.empty() ? json(nullptr) : json(est[std::size_t(q * double(est.size() - 1))]); };
  r["data"] = {{"contour_crossings", d.crossings.size()},
               {"contour_points_bounded", d.contour_points_bounded},
               {"reach_interior_bound_mm", finite(d.reach_interior_bound_mm)},
               {"reach_exterior_bound_mm", finite(d.reach_exterior_bound_mm)},
               {"alpha_max_measured_deg", finite(d.alpha_max_measured_deg)},
               {"alpha_estimated_from_neighbouring_slices",
                {{"points", est.size()}, {"median_deg", quantile(0.5)}, {"p90_deg", quantile(0.9)},
                 {"max_deg", quantile(1.0)},
                 {"meaning", "an estimate (the surface taken straight between slices), not a bound: to help "
                             "choose sampling.max_angle_deg; never used for the verdict"}}}};
  r["cells"] = {{"total", d.cells.size()},
                {"holding_sections", withSections},
                {"satisfied", counts[int(SamplingVerdict::satisfied)]},
                {"violated", counts[int(SamplingVerdict::violated)]},
                {"violated_by_data_alone", fromData},
                {"undetermined", counts[int(SamplingVerdict::undetermined)]},
                {"exact_heights", d.exact_cells},
                {"holding_sections_not_told_apart", d.unmatched_cells}};
  if (d.method == ReconstructionMethod::nearest_plane)
    r["cells"]["intersection_on_data"] = {
        {"checked", d.intersection_checked},
        {"not_contractible", d.intersection_not_contractible},
        {"not_sampled", d.intersection_unsampled},
        {"meaning", "cells where C1 is shown whose reconstruction R_C (homotopy equivalent to lift(S_C)) was "
                    "sampled: its components must all be contractible for the Intersection Condition (§4.4)"}};
  r["max_height_mm"] = maxHeight;
  if (d.method == ReconstructionMethod::section_voronoi)
    r["section_heights"] = {
        {"cells_bounded", d.section_height_cells},
        {"max_mm", finite(d.section_height_max_mm)},
        {"meaning", "h'_C (Def. 31), the largest distance of a point of a cell to the sections on its boundary, "
                    "bounded from above; null where a cell with sections was not bounded. Under C'1 and the Weak "
                    "Transversality Condition (C'2, not checked) the Hausdorff distance to the object is at most "
                    "its max (Thm 20)"}};
  if (d.observed_cells > 0)
    r["observed_pieces"] = {
        {"cells", d.observed_cells},
        {"cells_joined", d.cells_joined},
        {"cells_joined_with_sections", d.cells_joined_with_sections},
        {"lattice_edges_through_unobserved_parts", d.unobserved_crossings},
        {"meaning", "the conditions are checked on the cells of the observed pieces (Omega-cells: the whole planes' "
                    "cells joined across the parts of their faces no slice observed); a cell's height is the largest "
                    "distance of its points to the pieces. Joined cells are not convex: their Chebyshev balls, "
                    "h'_C bounds and Intersection Condition are not computed, and where they hold sections only "
                    "method 1's C1 can be shown (Lemma 3, Thm 3); the rest stays undetermined"}};
  r["lattice_spacing_mm"] = d.scan.lattice.voxel;
  r["end_box_mm"] = {vecJson(s.lo), vecJson(s.hi)};
  r["assumes"] = "the object lies inside the end planes' box; its boundary is smooth; the contours are its sections";
  r["deciding_cells"] = deciding;
  if (d.largest_empty_cell >= 0) {
    const CellSampling& c = d.cells[std::size_t(d.largest_empty_cell)];
    r["largest_cell_without_sections"] = {
        {"cell", d.largest_empty_cell},
        {"height_mm", c.height_hi_mm},
        {"centre_mm", vecJson(c.centre)},
        {"meaning", d.observed_cells > 0
                        ? "no observed piece touches a ball of this radius there: an object component of that size "
                          "could be missed entirely"
                        : "no plane touches a ball of this radius there: an object component of that size could be "
                          "missed entirely (Prop. 2)"}};
  }
  r["advice"] = {{"slices", s.advice.size()}, {"file", s.advice.empty() ? json(nullptr) : json("advice.yaml")}};
  r["timings_s"] = {{"diagnosis", s.diagnosis_s}, {"advice", s.advice_s}};
  return r;
}

json samplingDetailsJson(const SamplingStage& s) {
  const SamplingDiagnosis& d = s.diagnosis;
  const ConditionNames n = conditionNames(d.method);
  json cols;
  json id = json::array(), sections = json::array(), endCell = json::array(), lo = json::array(), hi = json::array(),
       exact = json::array(), centre = json::array(), alpha = json::array(), alphaN = json::array(),
       ri = json::array(), re = json::array(), dc = json::array(), dv = json::array(), tc = json::array(),
       tv = json::array(), verdict = json::array(), ratio = json::array(), data = json::array(),
       alphaEst = json::array(), sectionHeight = json::array(),
       inter = json::array(), observed = json::array();
  // At most kListed cells: the worst (largest ratio, then height), listed by id.
  constexpr std::size_t kListed = 20000;
  std::vector<std::size_t> listed(d.cells.size());
  for (std::size_t i = 0; i < listed.size(); ++i) listed[i] = i;
  if (listed.size() > kListed) {
    const auto key = [&](std::size_t i) {
      const CellSampling& c = d.cells[i];
      return std::make_tuple(std::isnan(c.ratio) ? -1.0 : c.ratio, c.height_hi_mm, -double(i));
    };
    std::nth_element(listed.begin(), listed.begin() + std::ptrdiff_t(kListed), listed.end(),
                     [&](std::size_t a, std::size_t b) { return key(a) > key(b); });
    listed.resize(kListed);
    std::sort(listed.begin(), listed.end());
  }
  for (const std::size_t i : listed) {
    const CellSampling& c = d.cells[i];
    id.push_back(i);
    sections.push_back(holdsSections(c));
    endCell.push_back(c.end_cell);
    lo.push_back(c.height_lo_mm);
    hi.push_back(c.height_hi_mm);
    exact.push_back(c.height_exact);
    centre.push_back(vecJson(c.centre));
    alpha.push_back(finite(c.alpha_max_deg));
    alphaEst.push_back(finite(c.alpha_estimated_deg));
    alphaN.push_back(c.alpha_samples);
    ri.push_back(finite(c.interior_bound_mm));
    re.push_back(finite(c.exterior_bound_mm));
    dc.push_back(finite(c.density.critical_mm));
    dv.push_back(name(c.density.verdict));
    tc.push_back(finite(c.transversality.critical_mm));
    tv.push_back(name(c.transversality.verdict));
    inter.push_back(name(c.intersection));
    verdict.push_back(name(c.verdict));
    ratio.push_back(finite(c.ratio));
    data.push_back(c.density.from_data || c.transversality.from_data);
    sectionHeight.push_back(holdsSections(c) ? finite(c.section_height_hi_mm) : json(nullptr));
    observed.push_back(c.observed_cell >= 0 ? json(c.observed_cell) : json(nullptr));
  }
  if (d.method == ReconstructionMethod::section_voronoi) cols["section_height_mm"] = sectionHeight;
  cols["id"] = id;
  cols["holds_sections"] = sections;
  cols["end_cell"] = endCell;
  cols["height_lower_mm"] = lo;
  cols["height_mm"] = hi;
  cols["height_exact"] = exact;
  cols["centre_mm"] = centre;
  cols["alpha_max_deg"] = alpha;
  cols["alpha_samples"] = alphaN;
  cols["alpha_estimated_deg"] = alphaEst;
  cols["reach_interior_bound_mm"] = ri;
  cols["reach_exterior_bound_mm"] = re;
  cols["density_critical_mm"] = dc;
  cols["density"] = dv;
  cols["transversality_critical_mm"] = tc;
  cols["transversality"] = tv;
  if (d.method == ReconstructionMethod::nearest_plane) cols["intersection_on_data"] = inter;
  cols["verdict"] = verdict;
  cols["ratio"] = ratio;
  cols["violated_by_data_alone"] = data;
  if (d.observed_cells > 0) cols["observed_cell"] = observed;
  json crossings = json::array();
  for (const ContourCrossing& x : d.crossings)
    crossings.push_back({{"point_mm", vecJson(x.point)},
                         {"planes", {x.plane_a, x.plane_b}},
                         {"normal", vecJson(x.normal)},
                         {"alpha_deg", {x.alpha_a_deg, x.alpha_b_deg}},
                         {"reach_interior_bound_mm", finite(x.interior_bound_mm)},
                         {"reach_exterior_bound_mm", finite(x.exterior_bound_mm)}});
  json advice = json::array();
  for (const AdvisedSlice& a : s.advice)
    advice.push_back({{"cell", a.cell},
                      {"point_mm", vecJson(a.plane.origin)},
                      {"normal", vecJson(a.plane.normal)},
                      {a.ratio ? "worst_ratio_before" : "worst_height_before_mm", a.worst_before},
                      {a.ratio ? "worst_ratio_after" : "worst_height_after_mm", a.worst_after}});
  json summary = samplingSummaryJson(s);
  summary.erase("timings_s");  // the file's bytes depend only on the inputs (report.json has them)
  return {{"summary", summary},
          {"conditions", {{"density", n.density}, {"transversality", n.transversality}}},
          {"cells_total", d.cells.size()},
          {"cells_listed", listed.size()},
          {"cells", cols},
          {"contour_crossings", crossings},
          {"advice", advice}};
}

std::string samplingLine(const SamplingStage& s) {
  const SamplingDiagnosis& d = s.diagnosis;
  std::ostringstream os;
  os << "sampling: " << name(d.verdict);
  if (!d.deciding.empty() && d.verdict != SamplingVerdict::satisfied) {
    const json c = cellJson(s, d.deciding.front());
    os << " (worst cell " << d.deciding.front() << ": " << c["condition"].get<std::string>() << ", h_C "
       << c["height_mm"].get<double>() << " mm";
    if (c.contains("section_height_mm") && !c["section_height_mm"].is_null())
      os << ", h'_C <= " << c["section_height_mm"].get<double>() << " mm";
    if (!c["critical_mm"].is_null()) os << " against " << c["critical_mm"].get<double>() << " mm";
    if (c["shown_by_data_alone"].get<bool>()) os << ", shown by the data alone";
    os << ")";
  }
  if (!d.prior.reach_interior_mm && !d.prior.reach_exterior_mm && d.verdict == SamplingVerdict::undetermined)
    os << "; give sampling.reach_mm (and sampling.max_angle_deg) to decide";
  if (!s.advice.empty()) os << "; advice.yaml proposes " << s.advice.size() << " slices";
  if (s.run_method != d.method) os << " (method 2's conditions: method 3 has none of its own)";
  return os.str();
}

namespace {

/// The ratio of `cell` (−1 for none or an unknown one).
float cellRatio(const SamplingStage& s, std::int32_t cell) {
  const double r = cell < 0 ? -1.0 : s.diagnosis.cells[std::size_t(cell)].ratio;
  return std::isnan(r) ? -1.0f : float(r);
}

}  // namespace

void samplingRatioRow(const SamplingStage& s, const GridSpec& grid, int j, int k, float* row) {
  const GridSpec& L = s.diagnosis.scan.lattice;
  const Vec3 start = grid.centre(0, j, k);
  const double ty = std::round((start.y() - L.origin.y()) / L.voxel), tz = std::round((start.z() - L.origin.z()) / L.voxel);
  const int nx = grid.dims[0];
  if (ty < 0 || ty > L.dims[1] - 1 || tz < 0 || tz > L.dims[2] - 1) {
    std::fill(row, row + nx, -1.0f);
    return;
  }
  const std::int32_t* cells = s.diagnosis.scan.cell_of_point.data() + L.index(0, int(ty), int(tz));
  const double step = grid.voxel / L.voxel, x0 = (start.x() - L.origin.x()) / L.voxel;
  for (int i = 0; i < nx; ++i) {
    const double tx = std::round(x0 + i * step);
    row[i] = cellRatio(s, tx < 0 || tx > L.dims[0] - 1 ? -1 : cells[std::size_t(tx)]);
  }
}

const CellSampling* samplingCellAt(const SamplingStage& s, const Vec3& x) {
  const GridSpec& L = s.diagnosis.scan.lattice;
  std::array<int, 3> t{};
  for (int a = 0; a < 3; ++a) {
    const double c = std::round((x[a] - L.origin[a]) / L.voxel);
    if (!(c >= 0 && c <= L.dims[a] - 1)) return nullptr;
    t[std::size_t(a)] = int(c);
  }
  const std::int32_t cell = s.diagnosis.scan.cell_of_point[std::size_t(L.index(t[0], t[1], t[2]))];
  return cell < 0 ? nullptr : &s.diagnosis.cells[std::size_t(cell)];
}

}  // namespace xsect

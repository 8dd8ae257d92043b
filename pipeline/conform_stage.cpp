// Stage 3: measure, flag, drop, enforce, re-measure (see conform_stage.h).
#include "pipeline/conform_stage.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "geometry/conformity/conformity_enforcement.h"
#include "geometry/arrangement/plane_pair_traces.h"
#include "geometry/conformity/pose_smoothing.h"
#include "segmentation/coincident_consensus.h"

namespace xsect {
namespace {

using json = nlohmann::ordered_json;

/// Agreement below this (symmetric difference, mm) is floating-point rounding.
constexpr double kAgree = 1e-6;
/// A slice is judged on the median of its pairs; with fewer pairs one bad partner decides.
constexpr int kPairsToFlag = 3;
/// ...and against the other slices: flagged above this many times the median slice's median, so
/// that a uniformly noisy series (every slice disagrees by about as much) flags nobody.
constexpr double kTimesTypical = 3.0;

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

struct SliceStats {
  int pairs = 0;
  double median_mismatch = 0, max_mismatch = 0, symmetric_difference = 0;
};

std::vector<SliceStats> sliceStats(const std::vector<PlanePairTraces>& pairs, std::size_t planes) {
  std::vector<std::vector<double>> mismatch(planes);
  std::vector<SliceStats> s(planes);
  for (const PlanePairTraces& p : pairs)
    for (const int i : {p.a, p.b}) {
      SliceStats& st = s[std::size_t(i)];
      ++st.pairs;
      st.max_mismatch = std::max(st.max_mismatch, p.disagreement.max_endpoint_mismatch_mm);
      st.symmetric_difference += p.disagreement.symmetric_difference_mm;
      mismatch[std::size_t(i)].push_back(p.disagreement.max_endpoint_mismatch_mm);
    }
  for (std::size_t i = 0; i < planes; ++i) s[i].median_mismatch = median(mismatch[i]);
  return s;
}

json pairsSummary(const std::vector<PlanePairTraces>& pairs) {
  std::vector<double> m;
  double sd = 0;
  int disagreeing = 0;
  for (const PlanePairTraces& p : pairs) {
    m.push_back(p.disagreement.max_endpoint_mismatch_mm);
    sd += p.disagreement.symmetric_difference_mm;
    disagreeing += p.disagreement.symmetric_difference_mm > kAgree;
  }
  double mean = 0;
  for (const double x : m) mean += x;
  return {{"pairs_disagreeing", disagreeing},
          {"mean_mismatch_mm", m.empty() ? 0.0 : mean / double(m.size())},
          {"median_mismatch_mm", median(m)},
          {"max_mismatch_mm", m.empty() ? 0.0 : *std::max_element(m.begin(), m.end())},
          {"symmetric_difference_mm", sd}};
}

json traceJson(const Trace& t) {
  json a = json::array();
  for (const Interval& i : t)  // infinite ends (contours on whole planes) become null
    a.push_back({std::isfinite(i.t0) ? json(i.t0) : json(nullptr), std::isfinite(i.t1) ? json(i.t1) : json(nullptr)});
  return a;
}

json vec(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

std::string number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}

std::string mm(double v) { return number(v) + " mm"; }

}  // namespace

ConformStage conformStage(const RunConfig::Conformity& settings, std::vector<CuttingPlane> planes,
                          std::vector<std::vector<Section>> labelled) {
  ConformStage out;
  // Observations of one plane become one plane carrying their consensus (issue 15): the thesis'
  // planes are distinct, and two sections on one plane must agree before anything compares traces.
  CoincidentMerge merged = mergeCoincidentPlanes(std::move(planes), std::move(labelled));
  planes = std::move(merged.planes);
  labelled = std::move(merged.labelled);
  json coincident = json::array();
  for (const CoincidentConsensus& c : merged.consensus) {
    coincident.push_back({{"slices", c.slices},
                          {"kept", c.slices.front()},
                          {"rule", c.rule},
                          {"max_offset_mm", c.group.max_offset_mm},
                          {"max_angle_deg", c.group.max_angle_deg},
                          {"disagreement_area_mm2", c.disagreement_area_mm2},
                          {"max_correction_mm", c.max_correction_mm}});
    std::string list;
    for (std::size_t k = 0; k < c.slices.size(); ++k)
      list += (k == 0 ? "" : k + 1 == c.slices.size() ? " and " : ", ") + std::to_string(c.slices[k]);
    const std::string head = "slices " + list + " observe one plane (within " + mm(c.group.max_offset_mm) + ")";
    if (c.rule == "identical")
      out.warnings.push_back(head + " with the same contours: merged into one plane");
    else
      out.warnings.push_back(head + "; their sections differ over " + number(c.disagreement_area_mm2) +
                             " mm² (a contour moves up to " + mm(c.max_correction_mm) + " to the consensus): one plane with " +
                             (c.rule == "union" ? "the union of their contours" : "the median of their signed distances") +
                             " is used");
  }
  // Tracked sweeps: the poses smoothed along the sweep first (the sections move with their
  // planes), so that everything after, measurement included, sees the smoothed poses.
  json poseSmoothing = nullptr;
  std::vector<double> poseShift(planes.size(), 0.0), poseRotation(planes.size(), 0.0),
      poseWeight(planes.size(), 1.0);
  if (settings.pose_smoothing_frames > 0) {
    std::vector<Plane> poses;
    std::vector<Vec2> centres;  // the observed region's centre: what the fit holds to the sweep
    for (const CuttingPlane& p : planes) {
      poses.push_back(p.plane);
      centres.push_back(0.5 * (p.extent.min + p.extent.max));
    }
    const PoseSmoothing smoothed = smoothPoseTrajectory(poses, centres, settings.pose_smoothing_frames);
    for (std::size_t i = 0; i < planes.size(); ++i) planes[i].plane = smoothed.planes[i];
    poseShift = smoothed.shift_mm;
    poseRotation = smoothed.rotation_deg;
    poseWeight = smoothed.robustness;
    json outliers = json::array();
    for (std::size_t i = 0; i < planes.size(); ++i)
      if (smoothed.robustness[i] == 0) outliers.push_back(planes[i].slice);
    const auto meanOf = [](const std::vector<double>& v) {
      double t = 0;
      for (const double x : v) t += x;
      return v.empty() ? 0.0 : t / double(v.size());
    };
    const auto maxOf = [](const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); };
    poseSmoothing = {{"half_window_frames", settings.pose_smoothing_frames},
                     {"mean_shift_mm", meanOf(poseShift)},
                     {"max_shift_mm", maxOf(poseShift)},
                     {"mean_rotation_deg", meanOf(poseRotation)},
                     {"max_rotation_deg", maxOf(poseRotation)},
                     {"sweeps", smoothed.sweeps},
                     {"outlier_slices", outliers}};
  }
  PlanePairSearch search = planePairTraces(planes, settings.min_angle_deg);
  const std::vector<SliceStats> before = sliceStats(search.pairs, planes.size());
  const json beforeSummary = pairsSummary(search.pairs);
  const std::size_t pairsMeasured = search.pairs.size();
  // The worst pairs as measured, before any slice is dropped.
  std::vector<std::size_t> order(search.pairs.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    return search.pairs[x].disagreement.max_endpoint_mismatch_mm >
           search.pairs[y].disagreement.max_endpoint_mismatch_mm;
  });
  json worst = json::array();
  for (std::size_t k = 0; k < std::min<std::size_t>(5, order.size()); ++k) {
    const PlanePairTraces& p = search.pairs[order[k]];
    worst.push_back({{"slice_a", planes[std::size_t(p.a)].slice},
                     {"slice_b", planes[std::size_t(p.b)].slice},
                     {"max_mismatch_mm", p.disagreement.max_endpoint_mismatch_mm},
                     {"symmetric_difference_mm", p.disagreement.symmetric_difference_mm}});
  }

  // Flags: the median over a slice's pairs of their largest endpoint mismatch. A slice whose
  // pose is wrong disagrees with every partner; a good slice paired with it only once.
  std::vector<char> flagged(planes.size(), 0);
  json flaggedSlices = json::array(), droppedSlices = json::array();
  std::vector<double> medians;
  for (const SliceStats& st : before)
    if (st.pairs > 0) medians.push_back(st.median_mismatch);
  const double typical = median(medians);
  const double flagAbove = std::max(settings.flag_mm, kTimesTypical * typical);
  for (std::size_t i = 0; i < planes.size(); ++i)
    if (before[i].pairs >= kPairsToFlag && before[i].median_mismatch > flagAbove) {
      flagged[i] = 1;
      flaggedSlices.push_back(planes[i].slice);
    }
  json slices = json::array();
  for (std::size_t i = 0; i < planes.size(); ++i)
    slices.push_back({{"slice", planes[i].slice},
                      {"name", planes[i].name},
                      {"pairs", before[i].pairs},
                      {"before", {{"median_mismatch_mm", before[i].median_mismatch},
                                  {"max_mismatch_mm", before[i].max_mismatch},
                                  {"symmetric_difference_mm", before[i].symmetric_difference}}},
                      {"after", nullptr},
                      {"pose_shift_mm", poseShift[i]},
                      {"pose_rotation_deg", poseRotation[i]},
                      {"pose_weight", poseWeight[i]},
                      {"flagged", bool(flagged[i])},
                      {"dropped", settings.drop_flagged && flagged[i]}});
  std::vector<std::size_t> rowOfPlane(planes.size());  // row in `slices` of each kept plane
  for (std::size_t i = 0; i < planes.size(); ++i) rowOfPlane[i] = i;
  if (settings.drop_flagged && !flaggedSlices.empty()) {
    std::vector<CuttingPlane> kept;
    std::vector<std::vector<Section>> keptLabelled;
    std::vector<std::size_t> keptRows;
    for (std::size_t i = 0; i < planes.size(); ++i) {
      if (flagged[i]) {
        droppedSlices.push_back(planes[i].slice);
        continue;
      }
      kept.push_back(std::move(planes[i]));
      if (i < labelled.size()) keptLabelled.push_back(std::move(labelled[i]));
      keptRows.push_back(i);
    }
    planes = std::move(kept);
    if (!labelled.empty()) labelled = std::move(keptLabelled);
    rowOfPlane = std::move(keptRows);
    search = planePairTraces(planes, settings.min_angle_deg);
  }

  std::vector<PlanePairTraces> after;
  ConformityEnforcement enforced;
  int unmeasuredDisturbed = 0;
  if (settings.enforce) {
    ConformityParams params;
    params.mode = settings.mode;
    params.max_correction_mm = settings.max_correction_mm;
    params.band_mm = settings.band_mm;
    params.tolerance_mm = kAgree;
    enforced = enforceConformity(planes, search.pairs, params, search.unmeasured);
    planes = std::move(enforced.planes);
    after = retrace(search.pairs, planes);
    // Lines that were not measured (no section on them, or nearly parallel planes) must not
    // have been changed by the edits.
    const std::vector<PlanePairTraces> now = retrace(search.unmeasured, planes);
    for (std::size_t k = 0; k < now.size(); ++k) {
      const PlanePairTraces &p = now[k], &was = search.unmeasured[k];
      unmeasuredDisturbed += traceDisagreement(p.trace_a, was.trace_a, p.common).symmetric_difference_mm > kAgree ||
                             traceDisagreement(p.trace_b, was.trace_b, p.common).symmetric_difference_mm > kAgree;
    }
    const std::vector<SliceStats> a = sliceStats(after, planes.size());
    for (std::size_t i = 0; i < planes.size(); ++i)
      slices[rowOfPlane[i]]["after"] = {{"median_mismatch_mm", a[i].median_mismatch},
                                        {"max_mismatch_mm", a[i].max_mismatch},
                                        {"symmetric_difference_mm", a[i].symmetric_difference}};
  }

  json pairs = json::array();
  int corrected = 0, overMax = 0, agreeing = 0, notEditablePairs = 0;
  for (std::size_t k = 0; k < search.pairs.size(); ++k) {
    const PlanePairTraces& p = search.pairs[k];
    json j = {{"slice_a", planes[std::size_t(p.a)].slice},
              {"slice_b", planes[std::size_t(p.b)].slice},
              {"angle_deg", p.line.angle_deg},
              {"line_point_mm", vec(p.line.point)},
              {"line_direction", vec(p.line.direction)},
              {"common", traceJson(p.common)},
              {"trace_a", traceJson(p.trace_a)},
              {"trace_b", traceJson(p.trace_b)},
              {"symmetric_difference_mm", p.disagreement.symmetric_difference_mm},
              {"max_mismatch_mm", p.disagreement.max_endpoint_mismatch_mm}};
    if (settings.enforce) {
      const PairCorrection& c = enforced.corrections[k];
      corrected += c.applied;
      overMax += c.over_max;
      agreeing += c.agrees;
      notEditablePairs += c.not_editable;
      j["enforced"] = c.applied;
      j["agrees"] = c.agrees;
      j["over_max_correction"] = c.over_max;
      j["not_editable"] = c.not_editable;
      j["correction_a_mm"] = c.correction_a_mm;
      j["correction_b_mm"] = c.correction_b_mm;
      j["consensus"] = traceJson(c.consensus);
      j["after"] = {{"trace_a", traceJson(after[k].trace_a)},
                    {"trace_b", traceJson(after[k].trace_b)},
                    {"symmetric_difference_mm", after[k].disagreement.symmetric_difference_mm},
                    {"max_mismatch_mm", after[k].disagreement.max_endpoint_mismatch_mm}};
    }
    pairs.push_back(std::move(j));
  }
  json notEditable = json::array();
  for (const int i : enforced.planes_not_editable) notEditable.push_back(planes[std::size_t(i)].slice);

  const json afterSummary = settings.enforce ? pairsSummary(after) : json(nullptr);
  out.summary = {{"enforce", settings.enforce},
                 {"coincident_planes", coincident},
                 {"mode", nameOf(kConsensusModes, settings.mode)},
                 {"max_correction_mm", settings.max_correction_mm},
                 {"band_mm", settings.band_mm},
                 {"min_angle_deg", settings.min_angle_deg},
                 {"flag_mm", settings.flag_mm},
                 {"pose_smoothing", poseSmoothing},
                 {"typical_slice_mismatch_mm", typical},
                 {"flagged_above_mm", flagAbove},
                 {"drop_flagged", settings.drop_flagged},
                 {"pairs_measured", pairsMeasured},
                 {"pairs", search.pairs.size()},
                 {"pairs_near_parallel", search.pairs_near_parallel},
                 {"pairs_without_sections", search.pairs_without_sections},
                 {"before", beforeSummary},
                 {"after", afterSummary},
                 {"pairs_enforced", settings.enforce ? json(corrected) : json(nullptr)},
                 {"pairs_agreeing_after", settings.enforce ? json(agreeing) : json(nullptr)},
                 {"pairs_over_max_correction", settings.enforce ? json(overMax) : json(nullptr)},
                 {"pairs_not_editable", settings.enforce ? json(notEditablePairs) : json(nullptr)},
                 {"unmeasured_pairs_disturbed", settings.enforce ? json(unmeasuredDisturbed) : json(nullptr)},
                 {"enforcement_rounds", enforced.rounds},
                 {"slices_edited", enforced.planes_edited},
                 {"endpoint_moves", enforced.bumps},
                 {"edits_added", enforced.rhombi_added},
                 {"edits_removed", enforced.rhombi_removed},
                 {"vertices_shared", enforced.vertices_shared},
                 {"max_edit_half_width_mm", enforced.max_half_width_mm},
                 {"slices_not_editable", notEditable},
                 {"flagged_slices", flaggedSlices},
                 {"dropped_slices", droppedSlices},
                 {"worst_pairs", worst}};
  out.details = {{"summary", out.summary}, {"slices", slices}, {"pairs", pairs}};

  // Terminal and warnings.
  std::string s;
  if (settings.pose_smoothing_frames > 0)
    s += "conformity: poses smoothed over ±" + std::to_string(settings.pose_smoothing_frames) +
         " frames: corrections mean " + mm(poseSmoothing["mean_shift_mm"].get<double>()) + " / " +
         number(poseSmoothing["mean_rotation_deg"].get<double>()) + "°, max " +
         mm(poseSmoothing["max_shift_mm"].get<double>()) + " / " +
         number(poseSmoothing["max_rotation_deg"].get<double>()) + "°" +
         (poseSmoothing["outlier_slices"].empty()
              ? std::string()
              : "; " + std::to_string(poseSmoothing["outlier_slices"].size()) +
                    " slice(s) off the trajectory, put back onto it (conformity.json pose_weight 0)") +
         "\n";
  s += "conformity: " + std::to_string(pairsMeasured) + " pairs of slices meet at " +
                  number(settings.min_angle_deg) + "° or more" +
                  (search.pairs_near_parallel ? " (" + std::to_string(search.pairs_near_parallel) + " nearly parallel pairs not compared)" : "");
  if (!search.pairs.empty()) {
    s += "; disagreement median " + mm(beforeSummary["median_mismatch_mm"].get<double>()) + ", max " +
         mm(beforeSummary["max_mismatch_mm"].get<double>());
    if (!worst.empty())
      s += " (slices " + std::to_string(worst[0]["slice_a"].get<int>()) + " and " +
           std::to_string(worst[0]["slice_b"].get<int>()) + ")";
  }
  if (settings.enforce)
    s += std::string("\nconformity: enforced (") + nameOf(kConsensusModes, settings.mode) + ") on " + std::to_string(corrected) +
         " pairs; after: max " + mm(afterSummary["max_mismatch_mm"].get<double>()) +
         (overMax ? "; " + std::to_string(overMax) + " pairs over max_correction_mm left as they were" : "");
  out.stderr_summary = s;
  if (!flaggedSlices.empty()) {
    std::string list;
    for (const auto& f : flaggedSlices) list += (list.empty() ? "" : ", ") + std::to_string(f.get<int>());
    out.warnings.push_back(std::to_string(flaggedSlices.size()) + " slice(s) disagree with the slices they cross by " +
                           mm(flagAbove) + " or more (median over their pairs; conformity.flag_mm or " +
                           "3 times the typical slice's): probable tracking or segmentation failures: slice " + list +
                           (settings.drop_flagged ? " (dropped)" : " (set conformity.drop_flagged: true to leave them out)"));
  }
  if (overMax)
    out.warnings.push_back(std::to_string(overMax) + " pair(s) of slices disagree by more than conformity.max_correction_mm (" +
                           mm(settings.max_correction_mm) + "): left as they were (conformity.json)");
  if (unmeasuredDisturbed)
    out.warnings.push_back(std::to_string(unmeasuredDisturbed) + " line(s) of slices that were not compared (nearly parallel, or no section on them) changed under the edits");
  if (!notEditable.empty())
    out.warnings.push_back(std::to_string(notEditable.size()) + " slice(s) have sections that are not simple polygons and were not edited");
  if (settings.enforce && !labelled.empty()) {
    bool any = false;
    for (const auto& l : labelled) any = any || !l.empty();
    if (any) out.warnings.push_back("conformity.enforce edits the union of the labels; each material keeps its segmented sections");
  }
  out.planes = std::move(planes);
  out.labelled = std::move(labelled);
  return out;
}

}  // namespace xsect

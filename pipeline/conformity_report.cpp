// Stage 3's report (see conform_stage.h): report.json "conformity", conformity.json, the lines
// for the terminal and the warnings, from the stage's typed result.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "pipeline/json_values.h"
#include "pipeline/conform_stage.h"

namespace xsect {
namespace {

using json = nlohmann::ordered_json;

json traceJson(const Trace& t) {
  json a = json::array();
  for (const Interval& i : t)  // infinite ends (contours on whole planes) become null
    a.push_back({std::isfinite(i.t0) ? json(i.t0) : json(nullptr), std::isfinite(i.t1) ? json(i.t1) : json(nullptr)});
  return a;
}

std::string number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}

std::string mm(double v) { return number(v) + " mm"; }

json summaryJson(const PairsSummary& s) {
  return {{"pairs_disagreeing", s.pairs_disagreeing},
          {"mean_mismatch_mm", s.mean_mismatch_mm},
          {"median_mismatch_mm", s.median_mismatch_mm},
          {"max_mismatch_mm", s.max_mismatch_mm},
          {"symmetric_difference_mm", s.symmetric_difference_mm}};
}

json disagreementJson(const SliceDisagreement& d) {
  return {{"median_mismatch_mm", d.median_mismatch_mm},
          {"max_mismatch_mm", d.max_mismatch_mm},
          {"symmetric_difference_mm", d.symmetric_difference_mm}};
}

json coincidentJson(const std::vector<CoincidentConsensus>& groups) {
  json a = json::array();
  for (const CoincidentConsensus& c : groups)
    a.push_back({{"slices", c.slices},
                 {"kept", c.slices.front()},
                 {"rule", c.rule},
                 {"max_offset_mm", c.group.max_offset_mm},
                 {"max_angle_deg", c.group.max_angle_deg},
                 {"disagreement_area_mm2", c.disagreement_area_mm2},
                 {"max_correction_mm", c.max_correction_mm}});
  return a;
}

json poseJson(const PoseSmoothingSummary& p) {
  if (!p.applied) return nullptr;
  return {{"half_window_frames", p.half_window_frames},
          {"mean_shift_mm", p.mean_shift_mm},
          {"max_shift_mm", p.max_shift_mm},
          {"mean_rotation_deg", p.mean_rotation_deg},
          {"max_rotation_deg", p.max_rotation_deg},
          {"sweeps", p.sweeps},
          {"outlier_slices", p.outlier_slices}};
}

json correctionJson(const SliceCorrection& c) {
  return {{"shift_mm", c.shift_mm},
          {"rotation_deg", c.rotation_deg},
          {"translation_mm", vecJson(c.translation)},
          {"rotation_vector_deg", vecJson(c.rotation * (180.0 / M_PI))},
          {"pivot_mm", vecJson(c.pivot)},
          {"sigma_shift_mm", c.sigma_shift_mm},
          {"sigma_rotation_deg", c.sigma_rotation_deg},
          {"unobservable", c.unobservable},
          {"crossings_before", c.crossings_before},
          {"crossings_after", c.crossings_after},
          {"gap_before_mm", c.gap_before_mm},
          {"gap_after_mm", c.gap_after_mm},
          {"outlier", c.outlier}};
}

json poseCorrectionJson(const RunConfig::Conformity& settings, const PoseCorrectionSummary& c) {
  if (!c.applied) return nullptr;
  const PoseCorrection& f = c.fit;
  double meanShift = 0, maxShift = 0, meanRot = 0, maxRot = 0;
  for (const SliceCorrection& s : f.slices) {
    meanShift += s.shift_mm;
    meanRot += s.rotation_deg;
    maxShift = std::max(maxShift, s.shift_mm);
    maxRot = std::max(maxRot, s.rotation_deg);
  }
  const double n = std::max<double>(1, double(f.slices.size()));
  return {{"kind", nameOf(kPoseCorrectionKinds, settings.pose_correction)},
          {"sigma_mm", f.sigma_mm},
          {"sigma_deg", f.sigma_deg},
          {"sigma_mm_auto", !settings.pose_sigma_mm},
          {"sigma_deg_auto", !settings.pose_sigma_deg},
          {"noise_mm", f.noise_mm},
          {"gate_mm", f.gate_mm},
          {"robust_scale_mm", f.robust_scale_mm},
          {"rounds", f.rounds},
          {"converged", f.converged},
          {"crossings_before", f.crossings_before},
          {"crossings_after", f.crossings_after},
          {"gap_rms_before_mm", f.gap_before_mm},
          {"gap_rms_after_mm", f.gap_after_mm},
          {"gap_median_before_mm", f.median_gap_before_mm},
          {"gap_median_after_mm", f.median_gap_after_mm},
          {"mean_shift_mm", meanShift / n},
          {"max_shift_mm", maxShift},
          {"mean_rotation_deg", meanRot / n},
          {"max_rotation_deg", maxRot},
          {"outliers", f.outliers},
          {"slices_with_unobservable", f.slices_with_unobservable},
          {"uncorrected", summaryJson(c.uncorrected)}};
}

json slicesJson(const ConformityResult& r) {
  json slices = json::array();
  for (const SliceConformity& s : r.slices)
    slices.push_back({{"slice", s.slice},
                      {"name", s.name},
                      {"pairs", s.before.pairs},
                      {"before", disagreementJson(s.before)},
                      {"after", s.measured_after ? disagreementJson(s.after) : json(nullptr)},
                      {"pose_shift_mm", s.pose_shift_mm},
                      {"pose_rotation_deg", s.pose_rotation_deg},
                      {"pose_weight", s.pose_weight},
                      {"pose_correction", r.correction.applied ? correctionJson(s.correction) : json(nullptr)},
                      {"flagged", s.flagged},
                      {"unplaced", s.unplaced},
                      {"unreconciled", s.unreconciled},
                      {"dropped", s.dropped}});
  return slices;
}

json pairsJson(const RunConfig::Conformity& settings, const ConformityResult& r) {
  json pairs = json::array();
  for (std::size_t k = 0; k < r.search.pairs.size(); ++k) {
    const PlanePairTraces& p = r.search.pairs[k];
    json j = {{"slice_a", r.slice_of_plane[std::size_t(p.a)]},
              {"slice_b", r.slice_of_plane[std::size_t(p.b)]},
              {"angle_deg", p.line.angle_deg},
              {"line_point_mm", vecJson(p.line.point)},
              {"line_direction", vecJson(p.line.direction)},
              {"common", traceJson(p.common)},
              {"trace_a", traceJson(p.trace_a)},
              {"trace_b", traceJson(p.trace_b)},
              {"symmetric_difference_mm", p.disagreement.symmetric_difference_mm},
              {"max_mismatch_mm", p.disagreement.max_endpoint_mismatch_mm}};
    if (settings.enforce) {
      const PairCorrection& c = r.enforcement.corrections[k];
      const PlanePairTraces& a = r.after[k];
      j["enforced"] = c.applied;
      j["agrees"] = c.agrees;
      j["over_max_correction"] = c.over_max;
      j["not_editable"] = c.not_editable;
      j["correction_a_mm"] = c.correction_a_mm;
      j["correction_b_mm"] = c.correction_b_mm;
      j["consensus"] = traceJson(c.consensus);
      j["after"] = {{"trace_a", traceJson(a.trace_a)},
                    {"trace_b", traceJson(a.trace_b)},
                    {"symmetric_difference_mm", a.disagreement.symmetric_difference_mm},
                    {"max_mismatch_mm", a.disagreement.max_endpoint_mismatch_mm}};
    }
    pairs.push_back(std::move(j));
  }
  return pairs;
}

std::vector<int> slicesNotEditable(const ConformityResult& r) {
  std::vector<int> s;
  for (const int i : r.enforcement.planes_not_editable) s.push_back(r.slice_of_plane[std::size_t(i)]);
  return s;
}

}  // namespace

json conformitySummaryJson(const RunConfig::Conformity& settings, const ConformityResult& r) {
  const bool e = settings.enforce;
  const ConformityEnforcement& en = r.enforcement;
  json worst = json::array();
  for (const WorstPair& w : r.worst)
    worst.push_back({{"slice_a", w.slice_a}, {"slice_b", w.slice_b}, {"max_mismatch_mm", w.max_mismatch_mm},
                     {"symmetric_difference_mm", w.symmetric_difference_mm}});
  return {{"enforce", settings.enforce},
          {"coincident_planes", coincidentJson(r.coincident)},
          {"mode", nameOf(kConsensusModes, settings.mode)},
          {"max_correction_mm", settings.max_correction_mm},
          {"band_mm", settings.band_mm},
          {"min_angle_deg", settings.min_angle_deg},
          {"flag_mm", settings.flag_mm},
          {"pose_smoothing", poseJson(r.pose)},
          {"pose_correction", poseCorrectionJson(settings, r.correction)},
          {"typical_slice_mismatch_mm", r.typical_mismatch_mm},
          {"flagged_above_mm", r.flagged_above_mm},
          {"drop_flagged", settings.drop_flagged},
          {"drop_unplaced", settings.drop_unplaced},
          {"drop_unreconciled", settings.drop_unreconciled},
          {"unreconciled_above_mm", r.correction.applied ? json(r.unreconciled_above_mm) : json(nullptr)},
          {"pairs_measured", r.pairs_measured},
          {"pairs", r.search.pairs.size()},
          {"pairs_near_parallel", r.search.pairs_near_parallel},
          {"pairs_without_sections", r.search.pairs_without_sections},
          {"before", summaryJson(r.before)},
          {"after", e ? summaryJson(r.after_summary) : json(nullptr)},
          {"pairs_enforced", e ? json(r.pairs_enforced) : json(nullptr)},
          {"pairs_agreeing_after", e ? json(r.pairs_agreeing) : json(nullptr)},
          {"pairs_over_max_correction", e ? json(r.pairs_over_max) : json(nullptr)},
          {"pairs_not_editable", e ? json(r.pairs_not_editable) : json(nullptr)},
          {"unmeasured_pairs_disturbed", e ? json(r.unmeasured_disturbed) : json(nullptr)},
          {"enforcement_rounds", en.rounds},
          {"slices_edited", en.planes_edited},
          {"endpoint_moves", en.bumps},
          {"edits_added", en.rhombi_added},
          {"edits_removed", en.rhombi_removed},
          {"vertices_shared", en.vertices_shared},
          {"max_edit_half_width_mm", en.max_half_width_mm},
          {"slices_not_editable", slicesNotEditable(r)},
          {"flagged_slices", r.flagged_slices},
          {"unplaced_slices", r.unplaced_slices},
          {"unreconciled_slices", r.unreconciled_slices},
          {"dropped_slices", r.dropped_slices},
          {"worst_pairs", worst}};
}

json conformityDetailsJson(const RunConfig::Conformity& settings, const ConformityResult& r) {
  return {{"summary", conformitySummaryJson(settings, r)}, {"slices", slicesJson(r)}, {"pairs", pairsJson(settings, r)}};
}

std::string conformityTerminalSummary(const RunConfig::Conformity& settings, const ConformityResult& r) {
  std::string s;
  const PoseSmoothingSummary& p = r.pose;
  if (p.applied)
    s += "conformity: poses smoothed over ±" + std::to_string(settings.pose_smoothing_frames) +
         " frames: corrections mean " + mm(p.mean_shift_mm) + " / " + number(p.mean_rotation_deg) + "°, max " +
         mm(p.max_shift_mm) + " / " + number(p.max_rotation_deg) + "°" +
         (p.outlier_slices.empty()
              ? std::string()
              : "; " + std::to_string(p.outlier_slices.size()) +
                    " slice(s) off the trajectory, put back onto it (conformity.json pose_weight 0)") +
         "\n";
  if (r.correction.applied) {
    const PoseCorrection& f = r.correction.fit;
    s += std::string("conformity: poses corrected (") + nameOf(kPoseCorrectionKinds, settings.pose_correction) + ") from " +
         std::to_string(f.crossings_before) + " contour crossings: gap median " + mm(f.median_gap_before_mm) + " -> " +
         mm(f.median_gap_after_mm) + " in " + std::to_string(f.rounds) + " rounds" +
         (f.outliers ? "; " + std::to_string(f.outliers) + " outlier slice(s)" : "") + "\n";
  }
  s += "conformity: " + std::to_string(r.pairs_measured) + " pairs of slices meet at " +
       number(settings.min_angle_deg) + "° or more" +
       (r.search.pairs_near_parallel
            ? " (" + std::to_string(r.search.pairs_near_parallel) + " nearly parallel pairs not compared)"
            : "");
  if (!r.search.pairs.empty()) {
    s += "; disagreement median " + mm(r.before.median_mismatch_mm) + ", max " + mm(r.before.max_mismatch_mm);
    if (!r.worst.empty())
      s += " (slices " + std::to_string(r.worst[0].slice_a) + " and " + std::to_string(r.worst[0].slice_b) + ")";
  }
  if (settings.enforce)
    s += std::string("\nconformity: enforced (") + nameOf(kConsensusModes, settings.mode) + ") on " +
         std::to_string(r.pairs_enforced) + " pairs; after: max " + mm(r.after_summary.max_mismatch_mm) +
         (r.pairs_over_max ? "; " + std::to_string(r.pairs_over_max) + " pairs over max_correction_mm left as they were"
                           : "");
  return s;
}

std::vector<std::string> conformityWarnings(const RunConfig::Conformity& settings, const ConformityResult& r) {
  std::vector<std::string> w;
  for (const CoincidentConsensus& c : r.coincident) {
    std::string list;
    for (std::size_t k = 0; k < c.slices.size(); ++k)
      list += (k == 0 ? "" : k + 1 == c.slices.size() ? " and " : ", ") + std::to_string(c.slices[k]);
    const std::string head = "slices " + list + " observe one plane (within " + mm(c.group.max_offset_mm) + ")";
    if (c.rule == "identical")
      w.push_back(head + " with the same contours: merged into one plane");
    else
      w.push_back(head + "; their sections differ over " + number(c.disagreement_area_mm2) +
                  " mm² (a contour moves up to " + mm(c.max_correction_mm) + " to the consensus): one plane with " +
                  (c.rule == "union" ? "the union of their contours" : "the median of their signed distances") +
                  " is used");
  }
  if (!r.flagged_slices.empty()) {
    std::string list;
    for (const int f : r.flagged_slices) list += (list.empty() ? "" : ", ") + std::to_string(f);
    w.push_back(std::to_string(r.flagged_slices.size()) + " slice(s) disagree with the slices they cross by " +
                mm(r.flagged_above_mm) + " or more (median over their pairs; conformity.flag_mm or " +
                "3 times the typical slice's): probable tracking or segmentation failures: slice " + list +
                (settings.drop_flagged || std::all_of(r.flagged_slices.begin(), r.flagged_slices.end(), [&](int f) {
                   return std::find(r.dropped_slices.begin(), r.dropped_slices.end(), f) != r.dropped_slices.end();
                 })
                     ? " (dropped)"
                     : " (set conformity.drop_flagged: true to leave them out)"));
  }
  if (r.correction.applied) {
    std::string outliers, unplaced;
    std::vector<int> partly;  // slices with some motion no crossing constrains
    for (const SliceConformity& s : r.slices) {
      if (s.correction.outlier) outliers += (outliers.empty() ? "" : ", ") + std::to_string(s.slice);
      if (!s.correction.unobservable.empty()) partly.push_back(s.slice);
      if (s.unplaced) unplaced += (unplaced.empty() ? "" : ", ") + std::to_string(s.slice);
    }
    std::string unobservable;
    for (std::size_t k = 0; k < partly.size() && k < 8; ++k) unobservable += (k ? ", " : "") + std::to_string(partly[k]);
    if (partly.size() > 8) unobservable += ", ...";
    if (!partly.empty())
      unobservable = std::to_string(partly.size()) + " of " + std::to_string(r.slices.size()) + " slices (" +
                     unobservable + "): those were left uncorrected (conformity.json slices[].pose_correction.unobservable)";
    if (!unplaced.empty())
      unobservable += "; every motion of slice " + unplaced +
                      ", whose sections meet others' with no usable crossing: " +
                      (settings.drop_unplaced ? "left out (conformity.drop_unplaced: false keeps them, at the recorded pose)"
                                              : "left at the recorded pose (conformity.drop_unplaced: true leaves them out)");
    if (!outliers.empty())
      w.push_back("pose correction: slice " + outliers +
                  " disagreed with the slices it crosses far more than the others (probable tracking glitch or segmentation failure): corrected against them with theirs held, so that it moves none of them");
    if (!unobservable.empty())
      w.push_back("pose correction: no crossing constrains some motions of " + unobservable);
    if (!r.unreconciled_slices.empty()) {
      std::string list;
      for (const int s : r.unreconciled_slices) list += (list.empty() ? "" : ", ") + std::to_string(s);
      const bool one = r.unreconciled_slices.size() == 1;
      w.push_back(std::string("pose correction: ") + (one ? "slice " : "slices ") + list +
                  (one ? " still disagrees" : " still disagree") + " with the slices crossing " + (one ? "it" : "them") +
                  " after the fit (median over " + (one ? "its" : "their") + " pairs above " +
                  mm(r.unreconciled_above_mm) + ", where the typical slice's is " + mm(r.typical_mismatch_mm) + "): " +
                  (settings.drop_unreconciled
                       ? "left out (conformity.drop_unreconciled: false keeps them, at their corrected poses)"
                       : "kept at their corrected poses (conformity.drop_unreconciled: true leaves them out)"));
    }
    if (!r.correction.fit.converged)
      w.push_back("pose correction did not converge in " + std::to_string(r.correction.fit.rounds) + " rounds");
  }
  if (r.pairs_over_max)
    w.push_back(std::to_string(r.pairs_over_max) + " pair(s) of slices disagree by more than conformity.max_correction_mm (" +
                mm(settings.max_correction_mm) + "): left as they were (conformity.json)");
  if (r.unmeasured_disturbed)
    w.push_back(std::to_string(r.unmeasured_disturbed) +
                " line(s) of slices that were not compared (nearly parallel, or no section on them) changed under the edits");
  if (!r.enforcement.planes_not_editable.empty())
    w.push_back(std::to_string(r.enforcement.planes_not_editable.size()) +
                " slice(s) have sections that are not simple polygons and were not edited");
  if (settings.enforce && r.labelled)
    w.push_back("conformity.enforce edits the union of the labels; each material keeps its segmented sections");
  return w;
}

}  // namespace xsect

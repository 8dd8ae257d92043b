// Stage 3 (docs/methods.md), conformity along plane intersections (thesis Introduction §3.1, ch. 2 §5):
// observations of one plane merged (segmentation/coincident_consensus.h); a tracked sweep's poses
// smoothed (geometry/conformity/pose_smoothing.h); then measured, for every pair of slices whose
// observed regions meet, how their sections' traces on the common line disagree; slices whose
// disagreement with the others is too large to be segmentation noise flagged (probable tracking or
// segmentation failures) and optionally dropped; optionally a consensus trace enforced on every
// line (geometry/conformity/conformity_enforcement.h) and the pairs measured again. The stage
// returns data; pipeline/conformity_report.cpp writes it (report.json "conformity",
// conformity.json, the terminal and the warnings).
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "geometry/arrangement/plane_pair_traces.h"
#include "geometry/conformity/conformity_enforcement.h"
#include "geometry/conformity/pose_correction.h"
#include "geometry/core/types.h"
#include "io/run_config.h"
#include "segmentation/coincident_consensus.h"

namespace xsect {

/// Disagreement over a set of pairs (mm): the largest endpoint mismatch per pair, summarised.
struct PairsSummary {
  int pairs_disagreeing = 0;            ///< symmetric difference above rounding
  double mean_mismatch_mm = 0, median_mismatch_mm = 0, max_mismatch_mm = 0;
  double symmetric_difference_mm = 0;   ///< summed over the pairs
};

/// One slice's pairs, summarised: how many, the median and largest mismatch, the summed
/// symmetric difference.
struct SliceDisagreement {
  int pairs = 0;
  double median_mismatch_mm = 0, max_mismatch_mm = 0, symmetric_difference_mm = 0;
};

/// One row per plane that entered the measurement (after coincident merging).
struct SliceConformity {
  int slice = -1;
  std::string name;
  SliceDisagreement before;
  bool measured_after = false;          ///< enforcement ran and the slice was kept
  SliceDisagreement after;
  double pose_shift_mm = 0, pose_rotation_deg = 0, pose_weight = 1;
  SliceCorrection correction;           ///< pose correction (when conformity.pose_correction)
  bool flagged = false, dropped = false;
  bool unplaced = false;                ///< pose correction could not move it in any direction
  bool unreconciled = false;            ///< after pose correction it still disagrees with its partners
};

struct PoseSmoothingSummary {
  bool applied = false;
  int half_window_frames = 0;
  double mean_shift_mm = 0, max_shift_mm = 0, mean_rotation_deg = 0, max_rotation_deg = 0;
  int sweeps = 1;
  std::vector<int> outlier_slices;      ///< off the trajectory: put back onto it (weight 0)
};

/// The pose correction's summary (the per-slice corrections are in the rows).
struct PoseCorrectionSummary {
  bool applied = false;
  PoseCorrection fit;                   ///< without its planes (moved into the stage's)
  PairsSummary uncorrected;             ///< the pairs' disagreement on the recorded (or smoothed) poses
};

/// A slice's pose as used, against the one read: x -> transform x (world), for
/// corrected_slices.yaml. Coincident observations share their plane's.
struct PoseChange {
  int slice = -1;
  Mat4 transform = Mat4::Identity();
};

struct WorstPair {
  int slice_a = -1, slice_b = -1;
  double max_mismatch_mm = 0, symmetric_difference_mm = 0;
};

struct ConformityResult {
  std::vector<CoincidentConsensus> coincident;
  PoseSmoothingSummary pose;
  PoseCorrectionSummary correction;
  /// With pose smoothing or correction: every slice read (dropped ones too), its pose as used.
  std::vector<PoseChange> pose_changes;
  std::size_t pairs_measured = 0;       ///< before any slice was dropped
  PlanePairSearch search;               ///< the pairs of the kept slices
  PairsSummary before;                  ///< over the pairs measured
  std::vector<WorstPair> worst;         ///< the five worst pairs, before dropping
  double typical_mismatch_mm = 0, flagged_above_mm = 0;
  std::vector<int> flagged_slices, dropped_slices;
  std::vector<int> unplaced_slices;     ///< SliceConformity::unplaced, in slice order
  std::vector<int> unreconciled_slices;  ///< SliceConformity::unreconciled, in slice order
  double unreconciled_above_mm = 0;     ///< the median disagreement beyond which a slice is unreconciled
  std::vector<SliceConformity> slices;
  std::vector<int> slice_of_plane;      ///< CuttingPlane::slice of each kept plane (search's indices)
  // Enforcement (when conformity.enforce).
  ConformityEnforcement enforcement;    ///< its planes moved into the stage's planes
  std::vector<PlanePairTraces> after;   ///< search.pairs traced again after the edits
  PairsSummary after_summary;
  int unmeasured_disturbed = 0, pairs_enforced = 0, pairs_over_max = 0, pairs_agreeing = 0,
      pairs_not_editable = 0;
  bool labelled = false;                ///< some plane had per-label sections
};

struct ConformStage {
  std::vector<CuttingPlane> planes;              ///< merged, dropped slices removed, sections edited
  std::vector<std::vector<Section>> labelled;    ///< per-label sections, rows kept in step
  ConformityResult result;
};

/// @param planes    the segmented slices (non-virtual cutting planes).
/// @param labelled  per plane, the sections of each label (may be empty: single material).
/// @param progress  optional, called with the pairs of planes examined and the pairs in all, from
///                  several threads at once, by each search for the pairs (planePairTraces; with
///                  pose correction or dropped slices there are two, each counting from 0).
/// Slice numbers in the outputs are CuttingPlane::slice.
ConformStage conformStage(const RunConfig::Conformity& settings, std::vector<CuttingPlane> planes,
                          std::vector<std::vector<Section>> labelled,
                          const std::function<void(std::int64_t, std::int64_t)>& progress = {});

/// report.json "conformity" (measurement part; also `xsect check`'s).
nlohmann::ordered_json conformitySummaryJson(const RunConfig::Conformity& settings, const ConformityResult& r);
/// conformity.json: the summary, per slice and per pair.
nlohmann::ordered_json conformityDetailsJson(const RunConfig::Conformity& settings, const ConformityResult& r);
/// One to three lines for the terminal.
std::string conformityTerminalSummary(const RunConfig::Conformity& settings, const ConformityResult& r);
/// The stage's warnings, in plain words.
std::vector<std::string> conformityWarnings(const RunConfig::Conformity& settings, const ConformityResult& r);

}  // namespace xsect

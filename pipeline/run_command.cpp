// `xsect run` and `xsect check` (docs/commands.md). run: the stages (run_stages.h), then the one
// writer (run_outputs.h, stage 8) and the last lines. check: the stages that need no solid.
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
#include <nlohmann/json.hpp>

#include "io/input_error.h"
#include "pipeline/arrange_stage.h"
#include "pipeline/check_summary.h"
#include "pipeline/commands.h"
#include "pipeline/confidence_stage.h"
#include "pipeline/input_stage.h"
#include "pipeline/json_values.h"
#include "pipeline/plus_summary.h"
#include "pipeline/mesh_stage.h"
#include "pipeline/reconstruct_stage.h"
#include "pipeline/run_outputs.h"
#include "pipeline/run_stages.h"
#include "pipeline/sampling_stage.h"
#include "pipeline/scene_stage.h"
#include "pipeline/smooth_stage.h"

namespace xsect {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

int runCommand(const RunOptions& o) {
  Progress progress(o.quiet);
  runStages(o, progress, [&](const RunResults& results, StageClock& clock) {
    progress.stage("write");
    const json report = writeRunOutputs(results, o, clock);
    progress.finish();
    for (const auto& w : runWarnings(results)) progress.note("warning: " + w);
    // The last lines (issue 21): the sampling verdict, the Betti numbers with their confidence
    // (issue 52), what the two mean for this result in plain words, the page to look at.
    const Betti& betti = results.diagnosis.topology.betti;
    const TopologyConfidence& confidence = results.confidence.confidence;
    progress.note(samplingLine(results.sampling));
    progress.note("topology: " + std::to_string(betti[0]) + " " + std::to_string(betti[1]) + " " +
                  std::to_string(betti[2]) + ", confidence " + confidenceText(confidence) +
                  (confidence.level != ConfidenceLevel::high && !results.reconstruction.topology
                       ? " (if you know the answer: reconstruction.topology)"
                       : ""));
    progress.note(report["in_plain_words"].get<std::string>());
    progress.note("report: " + (results.inputs.output_dir / "report.html").string());
  });
  return 0;
}

int checkCommand(const RunOptions& o) {
  Progress progress(o.quiet);
  StageClock clock;
  const RunInputs in = loadInputs(o, clock, progress);
  std::vector<std::string> warnings = in.warnings;
  int sections = 0;
  for (const auto& p : in.planes) sections += int(p.sections.size());
  json r;
  std::string verdict;
  r["config"] = in.config.path;
  r["valid"] = true;
  r["counts"] = {{"slices", in.slices}, {"sections", sections}};
  if (in.plus) r["plus_sequence"] = plusSequenceJson(*in.plus);
  r["conformity"] = conformitySummaryJson(in.config.conformity, in.conformity);
  if (sections > 0) {
    // The scene stage of `run` (its refusals: memory, time, representable sizes), then the
    // arrangement and the sampling diagnosis, which need no solid (issue 18).
    const SceneStage built = sceneStage(in, true, clock.total(), true);
    warnings = warningsThroughScene(in, built);
    const ReconstructionLayout& L = built.scene.layout;
    const RunConfig& c = in.config;
    r["voxel_size"] = voxelSizeJson(built.voxel_size);
    r["sections_bounds_mm"] = {vecJson(L.sections_min), vecJson(L.sections_max)};
    r["end_margin_mm"] = L.end_margin_mm;
    r["grid_dims"] = L.grid.dims;
    r["estimated_voxels"] = L.grid.count();
    // What the run will keep (issue 17): the solid by blocks, measured on a coarse trial.
    const SolidMemoryEstimate& e = *built.memory_trial;
    r["estimated_memory_mb"] = e.total() / 1e6;
    r["estimated_memory"] = {{"blocks", e.blocks},
                             {"boundary_blocks", e.boundary_blocks},
                             {"solid_blocks", e.solid_blocks},
                             {"plane_blocks", e.plane_blocks},
                             {"trial_voxel_ratio", e.coarse_factor},
                             {"solid_mb", (e.table_bytes + e.leaf_bytes) / 1e6},
                             {"mesh_mb", e.mesh_bytes / 1e6},
                             {"whole_volume_mb", e.dense_bytes / 1e6}};
    const TimeEstimate& t = built.time_estimate;
    r["estimated_seconds"] = clock.total() + t.total();
    r["estimated_time_s"] = {{"spent", clock.total()},
                             {"scene", t.scene_s},
                             {"arrange_and_diagnose", t.arrange_s},
                             {"reconstruct", t.reconstruct_s},
                             {"max_seconds", c.max_seconds}};
    const std::unique_ptr<const Method> method = methodFor(c.reconstruction_method);
    const ArrangeStage arrangement = arrangeStage(c, built.scene, *method);
    const SamplingStage sampling = samplingStage(c, *method, built.scene, arrangement, false);
    r["sampling"] = samplingSummaryJson(sampling);
    verdict = samplingLine(sampling);
    // What a run's topology confidence can say before the solid exists (issue 52): the scale below
    // which its features are in doubt (docs/topology.md, "Topology confidence").
    const double scale = std::max(dataScaleMm(sampling), 2 * built.scene.grid().voxel);
    r["topology"] = {{"confidence", nullptr},
                     {"data_scale_mm", scale},
                     {"text", "not known before the run: features thinner than the run's data scale (half the "
                              "largest cell height, at least 2 voxels; at most " +
                                  jsonNumber(std::round(scale * 100) / 100) +
                                  " mm by the heights bounded here) will be rated medium at best, one voxel thin low"}};
  } else {
    warnings.push_back("no section found in any slice");
  }
  progress.finish();
  r["warnings"] = warnings;
  if (o.json) std::cout << r.dump(2) << "\n";
  else std::cout << checkSummary(r, verdict);
  return 0;
}

}  // namespace xsect

// The one writer of `xsect run` (docs/methods.md stage 8): the stages' typed results turned into the
// output folder, which appears complete or not at all (io/staged_output.h): mesh.<fmt> (and
// mesh_unsmoothed, mesh_label_L), level_set.vdb, labels.nrrd, graph.json and graph.dot,
// conformity.json, sampling.json, sampling.nrrd, advice.yaml (when slices are advised),
// report.json, report.html (report/run/) and manifest.json.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pipeline/arrange_stage.h"
#include "pipeline/commands.h"
#include "pipeline/confidence_stage.h"
#include "pipeline/input_stage.h"
#include "pipeline/mesh_stage.h"
#include "pipeline/methods/method.h"
#include "report/run/section_graph.h"
#include "pipeline/reconstruct_stage.h"
#include "pipeline/sampling_stage.h"
#include "pipeline/scene_stage.h"
#include "pipeline/smooth_stage.h"
#include "pipeline/stage_clock.h"

namespace xsect {

/// Everything the stages produced, read by the writer.
struct RunResults {
  const RunInputs& inputs;
  const Method& method;  ///< the method the configuration names
  const SceneStage& scene_stage;
  const ArrangeStage& arrangement;
  const ReconstructStage& reconstruction;
  const SmoothStage* smooth;  ///< nullptr without smoothing
  const MeshStage& meshes;
  const DiagnoseStage& diagnosis;
  const SamplingStage& sampling;
  const ConfidenceStage& confidence;  ///< topology.confidence (issue 52)
};

/// The run's warnings, gathered from the stages that found them, in the order they ran: loading
/// and the scene (RunInputs), the reconstruction, the smoothing, the meshes.
std::vector<std::string> runWarnings(const RunResults& r);

/// graph.json's nodes and the run's method's edges, as report.html draws them.
SectionGraph sectionGraph(const RunResults& r);
/// graph.json: the sections (nodes) and the edges of G and, for methods 2 and 3, G' (thesis Def. 30)
/// and, for method 3, G'' (Def. 44, `method` "delaunay"), each with the cell of the arrangement
/// where the lifts meet; for method 3 also `delaunay_connections`, the pairs R'' joins per cell.
/// The text nlohmann's dump(2) gives, with the edge lists written directly (io/json_edge_lists.h).
/// @param nodes  sectionGraph(r).nodes
std::string graphJsonText(const RunResults& r, const nlohmann::ordered_json& nodes);
/// graph.dot: the same graph for Graphviz.
std::string graphDot(const RunResults& r);
/// report.json (pipeline/run_report.cpp).
nlohmann::ordered_json reportJson(const RunResults& r, const StageClock& clock);

/// Writes every output into r.inputs.output_dir (replacing an older output folder of xsect there,
/// never anything else: io/staged_output.h).
/// Returns report.json as written.
nlohmann::ordered_json writeRunOutputs(const RunResults& r, const RunOptions& options, const StageClock& clock);

}  // namespace xsect

// The stages of `xsect run` in the order they run, each a function of the results before it
// (docs/methods.md, stages 1-7): the command line and the Python module (pipeline/python/) run
// the same sequence and differ only in what they do with the results.
//   load -> segment -> conform   (input_stage.h, stages 1-3)
//   the scene                    (scene_stage.h: planes and end planes, rasters, grid; built once)
//   arrange                      (arrange_stage.h, stage 4: cells, sub-sections, graphs G / G' / G'')
//   reconstruct                  (reconstruct_stage.h, stage 5: the solid, checked against the graph)
//   smooth                       (smooth_stage.h, stage 6, optional)
//   mesh -> diagnose             (mesh_stage.h, stage 7)
//   sampling                     (sampling_stage.h, stage 7: the sampling conditions, verdict, advice)
//   confidence                   (confidence_stage.h: how far the topology is to be trusted, issue 52)
#pragma once

#include <functional>

#include "pipeline/commands.h"
#include "pipeline/input_stage.h"
#include "pipeline/progress.h"
#include "pipeline/run_outputs.h"
#include "pipeline/stage_clock.h"

namespace xsect {

/// What to do with the stages' results while they exist (they live on runStages' stack).
using RunConsumer = std::function<void(const RunResults& results, StageClock& clock)>;

/// Loads options.config (stages 1-3, loadInputs), runs the stages after it and hands the
/// results to `consume`. Invalid input throws InputError before any long work.
void runStages(const RunOptions& options, Progress& progress, const RunConsumer& consume);

/// The stages from the scene on, for inputs already loaded (sections given in memory).
void runStages(const RunInputs& inputs, Progress& progress, StageClock& clock, const RunConsumer& consume);

}  // namespace xsect

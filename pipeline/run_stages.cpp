// The stages of `xsect run` in the order they run (see run_stages.h).
#include "pipeline/run_stages.h"

#include <memory>
#include <optional>

#include "pipeline/arrange_stage.h"
#include "pipeline/confidence_stage.h"
#include "pipeline/mesh_stage.h"
#include "pipeline/reconstruct_stage.h"
#include "pipeline/sampling_stage.h"
#include "pipeline/scene_stage.h"
#include "pipeline/smooth_stage.h"

namespace xsect {

void runStages(const RunOptions& o, Progress& progress, const RunConsumer& consume) {
  StageClock clock;
  const RunInputs in = loadInputs(o, clock, progress);
  runStages(in, progress, clock, consume);
}

void runStages(const RunInputs& in, Progress& progress, StageClock& clock, const RunConsumer& consume) {
  const RunConfig& c = in.config;
  progress.stage("scene");
  const SceneStage built = sceneStage(in, progress.quiet(), clock.total());
  const SectionScene& scene = built.scene;
  clock.end("scene");

  // The method the configuration names (pipeline/methods/): no stage asks which it is.
  const std::unique_ptr<const Method> method = methodFor(c.reconstruction_method);

  progress.stage("arrange");
  const ArrangeStage arrangement = arrangeStage(c, scene, *method);
  clock.end("arrange");

  progress.stage("reconstruct", method->progressUnit());
  const ReconstructStage reconstruction = reconstructStage(in, built, arrangement, *method, progress);
  clock.end("reconstruct");

  std::optional<SmoothStage> smooth;
  if (c.smoothing_method != SmoothingMethod::none) {
    progress.stage("smooth", "blocks");
    smooth = smoothStage(c, scene, arrangement, reconstruction, progress.counter());
    clock.end("smooth");
  }
  const SmoothStage* smoothed = smooth ? &*smooth : nullptr;

  progress.stage("mesh");
  const MeshStage meshes = meshStage(in, scene, *method, reconstruction, smoothed);
  clock.end("mesh");

  progress.stage("diagnose");
  const DiagnoseStage diagnosis = diagnoseStage(*method, reconstruction, smoothed, meshes);
  clock.end("diagnose");

  progress.stage("sampling");
  const SamplingStage sampling = samplingStage(c, *method, scene, arrangement, true);
  clock.end("sampling");

  progress.stage("confidence");
  const ConfidenceStage confidence = confidenceStage(reconstruction, smoothed, diagnosis.topology.betti, sampling);
  clock.end("confidence");

  consume(RunResults{in, *method, built, arrangement, reconstruction, smoothed, meshes, diagnosis, sampling, confidence},
          clock);
}

}  // namespace xsect

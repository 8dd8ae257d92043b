// Stages 1-3: load, segment, conform (see input_stage.h).
#include "pipeline/input_stage.h"

#include "io/contour_file.h"
#include "io/csl_file.h"
#include "io/input_error.h"
#include "io/slices_file.h"
#include "pipeline/load_sections.h"

namespace xsect {

RunInputs loadInputs(const RunOptions& o, StageClock& clock, Progress& progress) {
  RunInputs in;
  progress.stage("load");
  in.config = readRunConfig(o.config, o.overrides);
  in.warnings = in.config.warnings;
  const RunConfig& c = in.config;
  in.input_files.push_back(c.path);
  in.input_files.push_back(c.input_path);
  std::vector<SliceRecord> slices;
  if (c.input_kind == InputKind::slices) {
    slices = mergeRepeatedSlices(readSlicesFile(c.input_path, &in.warnings), &in.warnings);
    for (const auto& s : slices) {
      in.input_files.push_back(s.image_resolved);
      if (s.fov_resolved) in.input_files.push_back(*s.fov_resolved);
    }
  } else if (c.input_kind == InputKind::csl) {
    in.planes = readCslFile(c.input_path, &in.warnings);
  } else if (c.input_kind == InputKind::contour) {
    ContourFile contours = readContourFile(c.input_path, &in.warnings);
    in.planes = std::move(contours.planes);
    in.labelled = std::move(contours.labelled);  // one solid per material when there are several
  } else {
    in.input_files.push_back(c.plus_config_path);
    in.plus = readPlusSequence(c.input_path, c.plus_config_path, c.reference_frame);
    if (const int skipped = in.plus->skipped_image + in.plus->skipped_transform; skipped > 0)
      in.warnings.push_back(std::to_string(skipped) + " of " + std::to_string(in.plus->header.frames) +
                            " frames skipped (" + std::to_string(in.plus->skipped_image) + " with an image status, " +
                            std::to_string(in.plus->skipped_transform) +
                            " with a transform status other than OK): the others are reconstructed");
  }
  clock.end("load");
  progress.stage("segment", "frames");
  if (c.input_kind == InputKind::slices)
    in.planes = sectionsFromSlices(slices, c.input_path, c.segmentation, &in.warnings, &in.threshold,
                                   &in.labelled, progress.counter());
  else if (c.input_kind == InputKind::plus_sequence)
    in.planes = sectionsFromPlusSequence(*in.plus, c.segmentation, &in.warnings, &in.threshold, &in.labelled,
                                         progress.counter());
  in.slices = int(in.planes.size());
  clock.end("segment");
  in.slice_records = std::move(slices);
  progress.stage("conform", "pairs");
  ConformStage conform = conformStage(c.conformity, std::move(in.planes), std::move(in.labelled), progress.counter());
  in.planes = std::move(conform.planes);
  in.labelled = std::move(conform.labelled);
  in.conformity = std::move(conform.result);
  const std::vector<std::string> warnings = conformityWarnings(c.conformity, in.conformity);
  in.warnings.insert(in.warnings.end(), warnings.begin(), warnings.end());
  clock.end("conform");
  progress.note(conformityTerminalSummary(c.conformity, in.conformity));
  return in;
}

}  // namespace xsect

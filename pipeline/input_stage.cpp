// Stages 1-3: load, segment, conform (see input_stage.h).
#include "pipeline/input_stage.h"

#include "geometry/core/plane_of_pose.h"
#include "geometry/core/polygon.h"
#include "io/contour_file.h"
#include "io/contour_repair.h"
#include "io/csl_file.h"
#include "io/file_checks.h"
#include "io/input_error.h"
#include "io/slices_file.h"
#include "pipeline/load_sections.h"
#include "pipeline/time_budget.h"

namespace xsect {

namespace {

/// The pixels stage 2 will read (from the images' headers, or the recording's).
double pixelsToSegment(const std::vector<ImageHeader>& headers, const std::optional<PlusSequence>& plus) {
  double pixels = 0;
  for (const ImageHeader& h : headers) pixels += double(h.pixels());
  if (plus) pixels += double(plus->frames.size()) * double(plus->header.width) * double(plus->header.height);
  return pixels;
}

}  // namespace

namespace {

/// Stage 3 on the loaded sections (conform_stage.h), its warnings and its line.
void conform(RunInputs& in, StageClock& clock, Progress& progress) {
  const RunConfig& c = in.config;
  progress.stage("conform", "pairs");
  ConformStage conform = conformStage(c.conformity, std::move(in.planes), std::move(in.labelled), progress.counter());
  in.planes = std::move(conform.planes);
  in.labelled = std::move(conform.labelled);
  in.conformity = std::move(conform.result);
  const std::vector<std::string> warnings = conformityWarnings(c.conformity, in.conformity);
  in.warnings.insert(in.warnings.end(), warnings.begin(), warnings.end());
  clock.end("conform");
  progress.note(conformityTerminalSummary(c.conformity, in.conformity));
}

}  // namespace

RunInputs loadInputs(const RunOptions& o, StageClock& clock, Progress& progress) {
  RunInputs in;
  progress.stage("load");
  in.config = o.config_text.empty() ? readRunConfig(o.config, o.overrides) : readRunConfigText(o.config_text, o.config, o.overrides);
  in.warnings = in.config.warnings;
  const RunConfig& c = in.config;
  if (isRegularFile(c.path)) in.input_files.push_back(c.path);  // not a dict given to the Python module
  in.input_files.push_back(c.input_path);
  std::vector<SliceRecord> slices;
  if (c.input_kind == InputKind::slices) {
    slices = mergeRepeatedSlices(readSlicesFile(c.input_path, &in.warnings), &in.warnings);
    for (const auto& s : slices) {
      in.input_files.push_back(s.image_resolved);
      if (s.fov_resolved) in.input_files.push_back(*s.fov_resolved);
    }
  } else if (c.input_kind == InputKind::csl) {
    in.planes = readCslFile(c.input_path, &in.warnings, c.repair_contours);
  } else if (c.input_kind == InputKind::contour) {
    ContourFile contours = readContourFile(c.input_path, &in.warnings, c.repair_contours);
    in.planes = std::move(contours.planes);
    in.labelled = std::move(contours.labelled);  // one solid per material when there are several
  } else {
    in.input_files.push_back(c.plus_config_path);
    in.plus = readPlusSequence(c.input_path, c.plus_config_path, c.reference_frame);
    if (!in.plus->header.data_file.empty()) in.input_files.push_back(in.plus->header.data_file);  // .mhd + .raw
    if (!c.plus_masks_path.empty()) {
      in.input_files.push_back(c.plus_masks_path);
      in.plus->masks = readPlusMasks(c.plus_masks_path, *in.plus);
      if (!in.plus->masks->data_file.empty()) in.input_files.push_back(in.plus->masks->data_file);
    }
    if (const int skipped = in.plus->skipped_image + in.plus->skipped_transform; skipped > 0)
      in.warnings.push_back(std::to_string(skipped) + " of " + std::to_string(in.plus->header.frames) +
                            " frames skipped (" + std::to_string(in.plus->skipped_image) + " with an image status, " +
                            std::to_string(in.plus->skipped_transform) +
                            " with a transform status other than OK): the others are reconstructed");
  }
  // Before any long work: the output folder may not hold the inputs or a user's files.
  in.output_dir = o.out.empty() ? std::filesystem::path(c.output_dir) : std::filesystem::absolute(o.out).lexically_normal();
  in.output_guard = {in.input_files, o.out.empty() ? c.path : std::string("command line"),
                     o.out.empty() ? "output.dir" : "--out"};
  checkOutputDestination(in.output_dir, in.output_guard);
  // ... and the segmentation may not take longer than the run may (its cost follows the pixels
  // and the kernels' sizes): refused here, before it starts.
  const std::vector<ImageHeader> headers = sliceImageHeaders(slices, c.input_path);
  TimeEstimate segment;
  // The first frame's pixel stands for the series' (settings in mm become pixels at it).
  Vec2 spacing = Vec2::Zero();
  if (!slices.empty()) planeOfPose(slices.front().image_to_world, &spacing);
  if (in.plus && !in.plus->image_to_reference.empty()) planeOfPose(in.plus->image_to_reference.front(), &spacing);
  segment.segment_s = segmentSeconds(pixelsToSegment(headers, in.plus), c.segmentation, spacing);
  checkTimeBudget(segment, 0.0, c);
  clock.end("load");
  progress.stage("segment", "frames");
  if (c.input_kind == InputKind::slices || c.input_kind == InputKind::plus_sequence) {
    SegmentedSeries series =
        c.input_kind == InputKind::slices
            ? sectionsFromSlices(slices, c.input_path, c.segmentation, c.path, headers, progress.counter())
            : sectionsFromPlusSequence(*in.plus, c.segmentation, c.path, progress.counter());
    in.planes = std::move(series.planes);
    if (c.segmentation.elevation_median_mm > 0) {  // a grey series' frames vote on each other's regions
      in.elevation_median = elevationMedian(std::move(in.planes), c.segmentation.elevation_median_mm);
      in.planes = std::move(in.elevation_median.planes);
    }
    in.labelled = std::move(series.labelled);
    in.segmentation = series.applied;
    in.warnings.insert(in.warnings.end(), series.warnings.begin(), series.warnings.end());
  }
  in.slices = int(in.planes.size());
  clock.end("segment");
  in.slice_records = std::move(slices);
  conform(in, clock, progress);
  return in;
}

RunInputs inputsFromSections(const RunOptions& o, SectionsInMemory given, StageClock& clock, Progress& progress) {
  RunInputs in;
  progress.stage("load");
  const bool masks = !given.masks.empty();
  if (masks && !given.contours.empty())
    throw InputError("sections", "sections", "give every plane contours, or every plane a mask, not both");
  in.config = readRunConfigText(o.config_text, o.config, o.overrides, masks ? InputKind::slices : InputKind::csl);
  in.warnings = in.config.warnings;
  // Before any long work: the output folder, when one is named, is checked as the command line's.
  if (!o.out.empty()) {
    in.output_dir = std::filesystem::absolute(o.out).lexically_normal();
    in.output_guard = {in.input_files, "the caller", "out"};
    checkOutputDestination(in.output_dir, in.output_guard);
  }
  clock.end("load");
  std::vector<CuttingPlane> planes = std::move(given.contours);
  if (masks) {
    progress.stage("segment", "frames");
    SegmentedSeries series = sectionsFromMasks(given.masks, in.config.segmentation, in.config.path);
    planes = std::move(series.planes);
    in.segmentation = series.applied;
    in.warnings.insert(in.warnings.end(), series.warnings.begin(), series.warnings.end());
    clock.end("segment");
  }
  // Contours: the plane's place, and crossing rings made simple as a contour file's
  // (input.repair_contours). Masks were segmented, and their rings made simple, above.
  for (std::size_t p = 0; p < planes.size() && !masks; ++p) {
    CuttingPlane& cp = planes[p];
    cp.slice = int(p);
    if (!in.config.repair_contours) continue;
    std::vector<Ring> outers, holes;
    for (const Section& sec : cp.sections) {
      outers.push_back(sec.outer);
      holes.insert(holes.end(), sec.holes.begin(), sec.holes.end());
    }
    const RingRepair fixed = repairedOrRefused(outers, holes, "sections", "sections[" + std::to_string(p) + "]", -1);
    if (!fixed.changed) continue;
    in.warnings.push_back(repairWarning("sections[" + std::to_string(p) + "]", fixed));
    cp.sections = sectionsFromRings(fixed.outers, fixed.holes);
  }
  in.planes = std::move(planes);
  in.slices = int(in.planes.size());
  conform(in, clock, progress);
  return in;
}

}  // namespace xsect

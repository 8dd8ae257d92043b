// Stages 1-3 of `xsect run` and `xsect check` (docs/methods.md): load the configuration and its input,
// segment the slices into sections (thesis ch. 1 §1.1: the sections S_i = O ∩ P_i), and conform
// them along the planes' common lines (Introduction §3.1; pipeline/conform_stage.h).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "geometry/core/types.h"
#include "io/output_destination.h"
#include "io/plus_sequence.h"
#include "io/run_config.h"
#include "io/slices_file.h"
#include "pipeline/conform_stage.h"
#include "pipeline/load_sections.h"
#include "pipeline/commands.h"
#include "pipeline/progress.h"
#include "pipeline/stage_clock.h"
#include "segmentation/elevation_median.h"

namespace xsect {

/// What stages 1-3 produce: the cutting planes with their sections, ready for the arrangement.
struct RunInputs {
  RunConfig config;
  std::vector<CuttingPlane> planes;             ///< conformed; coincident observations merged
  std::vector<std::string> input_files;         ///< hashed into the manifest
  /// The output folder (--out, else output.dir), checked before segmentation: xsect may write it
  /// (io/output_destination.h); `output_guard` says what it must not touch and where it was named.
  std::filesystem::path output_dir;
  OutputGuard output_guard;
  std::vector<std::string> warnings;
  int slices = 0;                               ///< planes read (before stage 3 merged or dropped any)
  SegmentationParams segmentation;               ///< as applied to every frame (slices, PLUS input)
  /// segmentation.elevation_median_mm: what the median changed (its `planes` are moved into `planes`).
  ElevationMedian elevation_median;
  std::vector<std::vector<Section>> labelled;   ///< segmentation labels: per plane, per label
  ConformityResult conformity;                  ///< stage 3's measurements (conform_stage.h)
  /// The slices as read (input.slices; repeats merged): CuttingPlane::slice indexes them.
  std::vector<SliceRecord> slice_records;
  /// input.plus_sequence: the recording's header, device set, kept frames and their poses.
  std::optional<PlusSequence> plus;
};

/// Reads options.config (with its overrides) and its input (slices.yaml and images, or a .csl),
/// checks the output folder against the inputs (run and check refuse the same destinations),
/// segments and conforms. Invalid input throws InputError.
RunInputs loadInputs(const RunOptions& options, StageClock& clock, Progress& progress);

/// Sections given in memory: contours on planes, or masks (one of the two).
struct SectionsInMemory {
  std::vector<CuttingPlane> contours;  ///< as a contour file's planes: observed everywhere
  std::vector<PosedMask> masks;        ///< as image slices: observed within their rectangles
};

/// The inputs of sections given in memory (the Python module's reconstruct): the configuration
/// from options.config_text (named options.config, no `input`), then the contours as a contour
/// file's (crossing rings repaired as input.repair_contours says; `slice` set to their place) or
/// the masks segmented (load_sections.h sectionsFromMasks), then stage 3. The output folder only
/// when options.out names one.
RunInputs inputsFromSections(const RunOptions& options, SectionsInMemory given, StageClock& clock, Progress& progress);

}  // namespace xsect

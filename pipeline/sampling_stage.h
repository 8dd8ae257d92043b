// The sampling diagnosis of `xsect run` and `xsect check` (docs/methods.md stage 7; issue 18): the
// thesis' sampling conditions per cell of the arrangement with a verdict
// (geometry/sampling/sampling_conditions.h) and, when the verdict is not `satisfied`, the slices to
// add (geometry/sampling/slice_advice.h). Reads the scene and the arrangement; needs no solid, so
// `xsect check` runs it without reconstructing. Its results become report.json `sampling`,
// sampling.json, sampling.nrrd and advice.yaml (run_outputs.cpp).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "geometry/sampling/sampling_conditions.h"
#include "geometry/sampling/slice_advice.h"
#include "io/run_config.h"
#include "io/slices_file.h"
#include "pipeline/arrange_stage.h"

namespace xsect {

struct SamplingStage {
  /// The run's method. Method 3 (delaunay) has no sampling theorem in the thesis: it is diagnosed
  /// with method 2's conditions (diagnosis.method is section_voronoi), whose connectivity G' it
  /// contains (G' ⊆ G'', Proposition 10), and the report says so.
  ReconstructionMethod run_method = ReconstructionMethod::nearest_plane;
  SamplingDiagnosis diagnosis;
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  ///< the end planes' box, mm
  std::vector<AdvisedSlice> advice;
  std::vector<PoseRecord> advice_poses;      ///< the advice as image poses at the input's pixel size
  double advice_pixel_mm = 0;
  double diagnosis_s = 0, advice_s = 0;      ///< wall time of each part, s
};

/// The prior the configuration gives (sampling.reach_mm fills both reaches unless they are given).
SamplingPrior samplingPrior(const RunConfig& c);

/// @param advise  propose slices when the verdict is not `satisfied`.
/// @param method  the run's: its sampling conditions (Method::samplingConditions) are diagnosed.
SamplingStage samplingStage(const RunConfig& c, const Method& method, const SectionScene& scene,
                            const ArrangeStage& arrangement, bool advise);

/// report.json `sampling` (and `xsect check`'s): the verdict, its conditions and consequences, the
/// prior, what the data bound, the deciding cells.
nlohmann::ordered_json samplingSummaryJson(const SamplingStage& s);
/// sampling.json: every cell, column by column.
nlohmann::ordered_json samplingDetailsJson(const SamplingStage& s);
/// The stderr line: the verdict and why.
std::string samplingLine(const SamplingStage& s);
/// sampling.nrrd's row (0 .. grid.dims[0]-1, j, k) of `grid`: per voxel the ratio h_C / critical
/// value of the cell holding its centre (the nearest lattice point's), −1 where no critical value is
/// known or outside the end planes.
void samplingRatioRow(const SamplingStage& s, const GridSpec& grid, int j, int k, float* row);
/// The cell holding the lattice point nearest to x (mm), as sampling.nrrd takes it; nullptr outside
/// the lattice or where no cell is known.
const CellSampling* samplingCellAt(const SamplingStage& s, const Vec3& x);

}  // namespace xsect

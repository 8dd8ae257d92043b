// The confidence in the run's topology (issue 52; geometry/reconstruction/topology_confidence.h),
// probed on the solid the outputs describe: the smooth solid with smoothing, else the method's.
#pragma once

#include "geometry/reconstruction/topology_confidence.h"
#include "pipeline/mesh_stage.h"
#include "pipeline/reconstruct_stage.h"
#include "pipeline/sampling_stage.h"
#include "pipeline/smooth_stage.h"

namespace xsect {

struct ConfidenceStage {
  TopologyConfidence confidence;
};

/// The data's scale (mm): half the largest height h_C of a cell holding sections (0 without such a
/// cell). A run's second probe closes and opens the solid by it (at least 2 voxels).
double dataScaleMm(const SamplingStage& sampling);

/// @param betti     the solid's Betti numbers as report.json gives them (the mesh's, equal to its voxels').
/// @param sampling  the cells' heights: the data's scale is half the largest of a cell holding sections.
ConfidenceStage confidenceStage(const ReconstructStage& reconstruction, const SmoothStage* smooth, const Betti& betti,
                                const SamplingStage& sampling);

}  // namespace xsect

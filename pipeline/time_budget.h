// The time a run will take, estimated before its long stages, and the refusal of what would take
// longer than `run.max_seconds` (issue 48: no work may grow without bound from a ratio of
// settings, and `check` refuses what `run` would). The estimate counts the quantities each stage's
// cost follows and prices them at rates measured on this project's bench (bench/results.json,
// 2 cores): enough to tell a run of minutes from one of hours, not a promise.
//   segment      pixels read, times the kernels' size (Gaussian: 8 sigma taps per pixel and
//                axis; opening and closing: the disk's pixels, vectorised by OpenCV)
//   scene        contour edges times the raster nodes within the band of each
//   arrange      planes, and pairs of planes meeting in the grid's box (cells, sub-sections and
//                the sampling diagnosis follow them), and the slices of advice.yaml
//   reconstruct  voxels evaluated, meshed, diagnosed and written (the grid's, or for a grid over
//                1e8 voxels the blocks the boundary and the solid fill, from the memory
//                estimate's coarse trial), and pairs of planes for the cells' queries; method 3
//                (tetrahedra per cell) costs more per pair; the writing of the report
// Measured against whole runs of bench scenarios (issue 48's note): between 0.66 and 1.7 times the
// measured time (freehand-400, multiaxial-3x40, random-200 and random-800, methods 1 and 3).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "geometry/core/types.h"
#include "io/run_config.h"

namespace xsect {

struct TimeEstimate {
  double segment_s = 0, scene_s = 0, arrange_s = 0, reconstruct_s = 0;
  double delaunay_s = 0;  ///< method 3's tetrahedra per cell, part of reconstruct_s
  double total() const { return segment_s + scene_s + arrange_s + reconstruct_s; }
};

/// Stage 2 from the images' sizes: `pixels` in all frames read (Otsu's and the minimum-error
/// methods, and inside: auto, read them twice). `spacing`: the series' pixel (mm along u and v), at
/// which lengths given in mm become pixels (segmentation/pixel_settings.h); zero when unknown (no
/// frame), and then only the lengths given in pixels count.
double segmentSeconds(double pixels, const SegmentationParams& params, const Vec2& spacing);

/// The stages after segmentation, on the conformed planes at the resolved voxel size.
/// `voxels`: the voxels the reconstruction evaluates (see above).
TimeEstimate sceneOnwardSeconds(const std::vector<CuttingPlane>& planes, double voxel_mm, double voxels,
                                const RunConfig& c);

/// Throws InputError(c.path, the setting that makes most of the time) when `elapsed_s` (already
/// spent) plus `e` exceeds c.max_seconds; the message gives the estimate by stage and what to
/// change, including `run.max_seconds`.
void checkTimeBudget(const TimeEstimate& e, double elapsed_s, const RunConfig& c);

}  // namespace xsect

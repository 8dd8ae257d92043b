// Acoustic shadows of an ultrasound frame: where a strong reflector or an attenuating structure
// stops the beam, nothing beyond it returns an echo, and the image is dark to the end of the beam.
// Such pixels say nothing about the object (a vessel in a bone's shadow is as dark as the shadow),
// so segmentation.shadows: unobserved removes them from the field of view, as the thesis treats
// any part of a plane the scanner did not see (sections only where the plane was observed).
// Definition: along each beam, the shadow is the run of observed pixels at the beam's far end
// (the last observed pixels from the probe) whose grey is at or below the threshold, when that run
// is at least `min_length_px` long. A dark structure with tissue beyond it (a cyst, a vessel) is
// never a shadow: the beam meets brighter pixels after it.
#pragma once

#include <optional>

#include <opencv2/core.hpp>

#include "geometry/core/types.h"

namespace xsect {

/// @param grey           CV_32F grey field (grey_field.h).
/// @param observed       empty (the whole image) or CV_8U, non-zero where the image holds data.
/// @param threshold      grey level; a shadow's pixels are at or below it.
/// @param apex_px        the beams' origin (x = column, y = row, pixels; may lie outside the image):
///                       beams are rays from it, sampled 1 pixel apart along the ray and at most
///                       1 pixel apart across at the farthest pixel. None: beams are the columns,
///                       going down the rows.
/// @param min_length_px  shortest shadow, pixels along the beam (>= 1).
/// @return CV_8U mask, 255 on shadow pixels (all within `observed`).
cv::Mat acousticShadows(const cv::Mat& grey, const cv::Mat& observed, double threshold,
                        const std::optional<Vec2>& apex_px, int min_length_px);

/// The brightest grey from each observed pixel to the far end of its beam (same beams as
/// acousticShadows; +infinity where unobserved): a pixel is in the shadow of threshold t when this
/// is <= t (the length condition aside). The series threshold leaves shadows out of its histogram
/// with it (pipeline/load_sections.cpp), as the segmentation leaves them out of the view.
cv::Mat beamTailMaximum(const cv::Mat& grey, const cv::Mat& observed, const std::optional<Vec2>& apex_px);

}  // namespace xsect

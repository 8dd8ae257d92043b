// Segmentation of one slice image into sections (docs/methods.md stage 2): Gaussian smoothing, fixed or
// Otsu threshold (or given label masks), field-of-view masking, morphological open/close,
// removal of small components, then sub-pixel section-contours (the iso-line of the smoothed image
// at the threshold) turned into polygons with holes in the plane's (u, v) mm frame.
// Label images (method `labels`, thesis remark after Def. 17: several materials): every distinct
// non-zero value L gets its own sections, Section::label = L, bounded by the 0.5 iso-line of L's
// indicator image (smoothed and cleaned per label); the labels' sections tile the plane, so where
// two labels touch their contours share their vertices (see labelIsoContours).
#pragma once

#include <limits>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "geometry/core/named_choice.h"
#include "geometry/core/types.h"

namespace xsect {

enum class SegmentationMethod {
  threshold,  ///< a grey level
  otsu,       ///< Otsu's threshold (of the series, pipeline/load_sections.cpp; of one image here)
  /// Kittler and Illingworth's minimum-error threshold (series_threshold.h): two classes of
  /// different sizes and spreads, where Otsu's splits the larger one (speckled tissue around a
  /// small dark vessel).
  min_error,
  labels,     ///< every pixel value a material
};
constexpr std::array<NamedChoice<SegmentationMethod>, 4> kSegmentationMethods{{
    {SegmentationMethod::threshold, "threshold"},
    {SegmentationMethod::otsu, "otsu"},
    {SegmentationMethod::min_error, "min_error"},
    {SegmentationMethod::labels, "labels"},
}};

/// Which side of the threshold the object is (threshold, otsu).
enum class InsideSide {
  above,      ///< brighter than the threshold (bone, contrast, a fluorescent organ)
  below,      ///< darker (a vessel, a cyst: hypoechoic structures in ultrasound)
  automatic,  ///< auto: the side that covers less of the border of the observed region over
              ///< the series (pipeline/load_sections.cpp resolves it before any frame is segmented)
};
constexpr std::array<NamedChoice<InsideSide>, 3> kInsideSides{{
    {InsideSide::above, "above"},
    {InsideSide::below, "below"},
    {InsideSide::automatic, "auto"},
}};

/// What acoustic shadows are (segmentation/acoustic_shadows.h).
enum class ShadowRule {
  keep,        ///< pixels like any other
  unobserved,  ///< removed from the field of view: nothing is known there
};
constexpr std::array<NamedChoice<ShadowRule>, 2> kShadowRules{{
    {ShadowRule::keep, "keep"},
    {ShadowRule::unobserved, "unobserved"},
}};

struct SegmentationParams {
  SegmentationMethod method = SegmentationMethod::threshold;
  double threshold = 128.0;          ///< grey level (threshold method)
  InsideSide inside = InsideSide::above;
  double sigma_px = 0.0;             ///< Gaussian smoothing, pixels (0 = none)
  int open_radius_px = 0;            ///< morphological opening radius, pixels
  int close_radius_px = 0;           ///< morphological closing radius, pixels
  /// The same in mm (0 = not given): they transfer between probes and zooms. Converted to pixels
  /// per frame by inPixels (segmentation/pixel_settings.h) before segmentSlice; a key is given in
  /// pixels or in mm, never both.
  double sigma_mm = 0.0;
  double open_radius_mm = 0.0;
  double close_radius_mm = 0.0;
  /// Speckle-reducing median filter, applied first: its diameter in mm (0 = none), and in pixels
  /// as inPixels resolves it (odd, >= 3, or 0 = none).
  double speckle_filter_mm = 0.0;
  int speckle_filter_px = 0;
  /// Grey scale that brings the series to 8 bits (1, or 1/257 for 16-bit series), for the median
  /// filter, which OpenCV computes exactly on 8-bit images only (pipeline/load_sections.cpp sets it).
  double grey_to_8bit = 1.0;
  ShadowRule shadows = ShadowRule::keep;
  /// The beams' common origin in pixels (x = column, y = row: a curved or phased probe's fan
  /// apex, PLUS's FanOriginPixel); none: the beams are the image's columns, depth going down the
  /// rows (a linear probe, PLUS's MF orientation).
  std::optional<Vec2> beam_apex_px;
  /// The object's core (grey units; NaN = none): the object's pixels are kept only within
  /// sigma_px (rounded up, at least a pixel) of the pixels past this level on the object's side
  /// (opened by open_radius_px less that reach), then closed by open_radius_px within the
  /// threshold's mask. Speckle next to the object that is only a little darker (or brighter) than
  /// the threshold then no longer joins it over a neck wider than the opening, while a blurred
  /// step between the classes crosses the core's level within that reach of where it crosses the
  /// threshold, so a true boundary stays where the threshold puts it. Set by the min_error
  /// threshold (coreThresholdOfClasses, series_threshold.h).
  double core_threshold = std::numeric_limits<double>::quiet_NaN();
  double min_area_mm2 = 0.0;         ///< components and holes smaller than this are removed
  /// The elevation median of the series (segmentation/elevation_median.h): neighbours in the input's
  /// order whose planes pass within this distance (mm) vote on a frame's region; 0 = none. Applied
  /// to the series after every frame is segmented (pipeline/input_stage.cpp), not by segmentSlice.
  double elevation_median_mm = 0.0;
  double simplify_mm = 0.0;          ///< Douglas-Peucker tolerance on contours, mm (0 = none)
  /// labels: reconstruct the union of all labels as one material (no per-label solids).
  bool merge_labels = false;
  /// input.repair_contours: rings that simplify_mm made cross themselves or each other are made
  /// simple (geometry/core/ring_repair.h). The iso-contours themselves never cross.
  bool repair_contours = true;
};

struct SegmentedSlice {
  /// One per connected region, holes and islands resolved. threshold / otsu: label 1 each.
  /// labels: label = the pixel value, sorted by label, then in the order the contours are met
  /// scanning the image.
  std::vector<Section> sections;
  double threshold_used = 0.0;     ///< the threshold applied (Otsu's when method = otsu)
  bool touches_fov_edge = false;   ///< a section reaches the edge of the image / field of view
  bool contours_repaired = false;  ///< simplify_mm made rings cross, and they were made simple
  /// shadows: unobserved: the observed pixels (CV_8U, 255) once the shadows are removed, when
  /// they removed any; empty otherwise (the field of view given is the observed region).
  cv::Mat observed;
};

/// @param image    8- or 16-bit single-channel image (row j, column i); for `labels`, the label
///                 of each pixel (0 = background, 1..65535 materials).
/// @param fov      empty, or an 8-bit mask of the same size: non-zero where the image holds data.
/// @param spacing  mm per pixel along i (u) and j (v).
/// Pixel (i, j) has plane coordinates (i * spacing.x, j * spacing.y).
/// With `labels`, smoothing (sigma_px) and cleaning (field of view, opening, closing, min_area_mm2)
/// act on each label's indicator image separately. A pixel claimed by several cleaned labels goes
/// to the label whose smoothed indicator is largest there (pixels that cleaning added count as
/// barely inside, so a closing never takes a pixel another label holds; ties: the smaller label).
/// Contours: label | background at the 0.5 iso-line of the label's indicator, label | label at
/// the iso-line where the two indicators are equal (the same line as either's 0.5 iso-line when
/// no third material is near). In the pixel cells where three materials meet, or two labels
/// form a checkerboard, the cell is split among them so that the labels' sections never overlap
/// and leave no gap: their union is the region where some label's indicator exceeds 0.5, and with
/// sigma_px = 0 and no cleaning their areas sum exactly to the area of "image != 0".
/// simplify_mm simplifies each ring on its own: shared boundaries then no longer coincide.
/// Cost: one pass over the image plus each label's bounding box with a margin of
/// 4 sigma_px + 2 max(open, close radius) + 3 pixels, never one whole-image pass per label.
SegmentedSlice segmentSlice(const cv::Mat& image, const cv::Mat& fov, const Vec2& spacing,
                            const SegmentationParams& params);

}  // namespace xsect

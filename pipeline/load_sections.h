// Stages 1-2 (docs/methods.md): slice records -> cutting planes with their sections (segmentation of each
// image in its plane's (u, v) mm frame), deterministically. The frames are read as a stream, in
// parallel: each decoded, segmented and released by one task (issue 17: loading holds the
// sections, not the series' images).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "geometry/core/types.h"
#include "io/image_header.h"
#include "io/plus_sequence.h"
#include "io/slices_file.h"
#include "segmentation/segment_slice.h"

namespace xsect {

/// Exactly repeated slices (the same image bytes, the same field-of-view mask bytes, the same
/// pose to the last bit: a list concatenated twice, a frame exported twice) kept once, the first
/// of each in the listing's order; `warnings` receives one line naming each slice merged.
/// (Coincident planes with different images are not repeats: both observed the plane.)
std::vector<SliceRecord> mergeRepeatedSlices(std::vector<SliceRecord> slices, std::vector<std::string>* warnings);

/// The headers of every slice's image, in order, each checked (io/image_io.h greyImageHeader; its
/// field of view's too): header errors are reported before any image is decoded, each for the
/// first slice that has one (issue 15, item 3).
std::vector<ImageHeader> sliceImageHeaders(const std::vector<SliceRecord>& slices, const std::string& listing_file);

/// The sections of a series of frames (stage 2) and what segmenting them found.
struct SegmentedSeries {
  std::vector<CuttingPlane> planes;
  /// Method labels (several materials, thesis remark after Def. 17): per plane, the sections of
  /// each label value; the planes then hold the union of all labels (one section per connected
  /// region, label 1), the geometry the reconstruction runs on. Per plane empty with merge_labels
  /// or another method.
  std::vector<std::vector<Section>> labelled;
  /// The settings applied to every frame: the grey threshold (method otsu: one threshold for the
  /// whole series, Otsu's on the pooled histogram, series_threshold.h), the inside side (auto
  /// resolved for the series).
  SegmentationParams applied;
  std::vector<std::string> warnings;  ///< "slice N touches the edge of its field of view" and the like
};

/// @param listing_file  the slices.yaml the records came from (for error messages).
/// @param headers       sliceImageHeaders(slices, listing_file) when the caller has them; empty: read here.
/// @param settings_file where `params` came from (the run configuration, or "command line"): a
///                      setting an image cannot take (segmentation/setting_limits.h, or one OpenCV
///                      refuses) is an InputError naming it there, before any frame is segmented
///                      where the image headers tell.
///                      A series mixing 8- and 16-bit images is brought to the depth most frames
///                      have (the first frame's on a tie), full range to full range, with a warning:
///                      the threshold is in that depth's grey units.
/// @param progress      optional, called with the frames done and the frames in all, from the
///                      threads that segment them, concurrently (with Otsu's method the series is
///                      read twice: a frame counts when both its readings are done, on average).
/// A binary image given in memory (the Python module's reconstruct): non-zero = inside, rows j,
/// columns i, and its pose (pixel (i, j, 0, 1) -> mm, as slices.yaml's image_to_world).
struct PosedMask {
  Mat4 image_to_world;
  cv::Mat mask;  ///< CV_8U
};

/// The sections of masks (stage 2), each segmented as an image slice at 0.5 with the other
/// settings of `params` (smoothing, opening, closing, minimum area): each plane observed within its
/// image's rectangle.
SegmentedSeries sectionsFromMasks(const std::vector<PosedMask>& masks, const SegmentationParams& params,
                                  const std::string& settings_file);

SegmentedSeries sectionsFromSlices(const std::vector<SliceRecord>& slices, const std::string& listing_file,
                                   const SegmentationParams& params, const std::string& settings_file,
                                   std::vector<ImageHeader> headers,
                                   const std::function<void(std::int64_t, std::int64_t)>& progress = {});

/// The same for the kept frames of a PLUS recording (io/plus_sequence.h), in their order: plane k
/// is seq.frames[k], named "frame N", its pose seq.image_to_reference[k], its field of view the
/// device set's. The frames are streamed from the sequence file (one batch held at a time);
/// `progress` counts the kept frames as sectionsFromSlices' does.
SegmentedSeries sectionsFromPlusSequence(const PlusSequence& seq, const SegmentationParams& params,
                                         const std::string& settings_file,
                                         const std::function<void(std::int64_t, std::int64_t)>& progress = {});

}  // namespace xsect

// A PLUS tracked-ultrasound recording as slices (issue 20): the MetaImage sequence
// (meta_image.h) with its device set (plus_device_set.h). Each frame's ImageToReference is the
// chain of the frame's tracked transforms and the device set's static ones (PLUS naming: AToB
// maps points of frame A into frame B; e.g. inverse(ReferenceToTracker) · ProbeToTracker ·
// ImageToProbe), which maps pixel (i, j, 0, 1) to mm as slices.yaml's image_to_world does.
// Frames are oriented MF (the orientation PLUS calibrates in), the field of view is the device
// set's clip rectangle ∩ fan, and a frame whose image or any transform is not OK is skipped.
#pragma once

#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "geometry/core/types.h"
#include "io/meta_image.h"
#include "io/plus_device_set.h"

namespace xsect {

struct PlusSequence {
  MetaImageHeader header;
  PlusDeviceSet device_set;
  std::string image_frame = "Image";         ///< the frame pixels live in
  std::string reference_frame = "Reference"; ///< the frame poses map into
  std::vector<int> frames;                   ///< frames kept (indices into the sequence), ascending
  std::vector<Mat4> image_to_reference;      ///< per kept frame, pixel (i, j, 0, 1) -> mm (MF image)
  int skipped_image = 0;                     ///< frames whose ImageStatus is not OK
  int skipped_transform = 0;                 ///< frames with a transform whose status is not OK
  cv::Mat field_of_view;                     ///< CV_8UC1 (MF) mask, 255 observed; empty: whole frame
  /// input.plus_masks: the mask sequence segmented instead of the frames (readPlusMasks).
  std::optional<MetaImageHeader> masks;
};

/// Reads the sequence's header, the device set and every frame's pose (no pixel data).
/// @param sequence_path   .igs.mha / .seq.mha / .mha / .mhd
/// @param device_set_path the PLUS device-set XML
/// @param reference_frame the coordinate frame the poses map into (`input.reference_frame`); empty:
///                        the device set's ReferenceCoordinateFrame, or `Reference`
/// Throws InputError naming the file and field: malformed header or XML, a frame without one of
/// the transforms the others carry, no chain from the image frame to the reference frame (the
/// message lists the transforms available), a pose whose pixel axes are zero or parallel, or no
/// frame left.
PlusSequence readPlusSequence(const std::string& sequence_path, const std::string& device_set_path,
                              const std::string& reference_frame);

/// Frame `pixels` (as the sequence stores it) in MF orientation: flipped as the header says.
cv::Mat orientedFrame(const PlusSequence& s, const cv::Mat& pixels);

/// The header of a mask sequence made for the recording `s` (input.plus_masks): its frames are the
/// recording's, one for one. Throws InputError naming the mask file and field when its DimSize
/// differs (columns, rows or frame count), or a frame's Seq_Frame<N>_Timestamp differs from the
/// recording's by more than 1 ms where both give one. Its UltrasoundImageOrientation, when given,
/// orients its frames (orientedMask); otherwise they are stored as the recording's.
MetaImageHeader readPlusMasks(const std::string& path, const PlusSequence& s);

/// Mask frame `pixels` in MF orientation (the mask header's orientation, else the recording's).
cv::Mat orientedMask(const PlusSequence& s, const cv::Mat& pixels);

}  // namespace xsect

// PLUS toolkit device-set configuration (PlusDeviceSet_*.xml): the fixed transforms of a tracked
// ultrasound set-up (calibration ImageToProbe, phantom registration, ...) and the region of each
// frame the volume reconstruction uses (clip rectangle, fan).
//
// Format facts relied on (PLUS documentation, "Volume reconstruction" and "Coordinate systems"):
// - Root element PlusConfiguration. CoordinateDefinitions/Transform has From, To and Matrix (16
//   numbers, row-major, whitespace anywhere, possibly spread over several lines); a transform
//   named AToB maps points of frame A to frame B (mm); the last row is 0 0 0 1.
// - VolumeReconstruction (at the root or inside a Device) may give, in pixels of the MF-oriented
//   image (see meta_image.h; column x, row y, pixel centres at integer coordinates):
//   ClipRectangleOrigin "x y" and ClipRectangleSize "w h" (size 0 0 or absent: the whole frame);
//   FanAnglesDeg "a b" (deprecated FanAngles): the directions of the fan's two straight edges in
//   degrees from the +y (depth) axis, positive towards +x; both 0 or absent: no fan clipping;
//   FanOriginPixel "x y" (deprecated FanOrigin; default 0 0); FanRadiusStartPixel (default 0) and
//   FanRadiusStopPixel (deprecated FanDepth; default 500); EnableFanAnglesAutoDetect;
//   ImageCoordinateFrame and ReferenceCoordinateFrame (the frames PLUS reconstructs between).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "geometry/core/types.h"

namespace xsect {

/// A rigid or affine transform between named coordinate frames: matrix maps points of `from` to `to`.
struct PlusTransform {
  std::string from, to;
  Mat4 matrix = Mat4::Identity();
};

/// PLUS's fan-shaped clipping region, in pixels of the MF image.
struct PlusFanMask {
  std::array<double, 2> angles_deg{0.0, 0.0};  ///< edge directions, degrees from +y towards +x; [0] <= [1]
  std::array<double, 2> origin_px{0.0, 0.0};   ///< fan apex (x = column, y = row), pixels
  double radius_start_px = 0.0;                ///< inner radius, pixels
  double radius_stop_px = 500.0;               ///< outer radius, pixels
  /// EnableFanAnglesAutoDetect: PLUS narrows the angles per frame from the image content; not
  /// applied here (angles_deg is the largest fan).
  bool angles_auto_detect = false;
};

struct PlusDeviceSet {
  std::string path;
  std::vector<PlusTransform> transforms;           ///< CoordinateDefinitions, in file order
  std::optional<std::array<int, 2>> clip_origin;   ///< ClipRectangleOrigin (x, y), pixels
  std::optional<std::array<int, 2>> clip_size;     ///< ClipRectangleSize (w, h), pixels; 0 0 = whole frame
  std::optional<PlusFanMask> fan;                  ///< set when FanAnglesDeg is given and not 0 0
  std::string image_frame;      ///< VolumeReconstruction ImageCoordinateFrame; "" when absent
  std::string reference_frame;  ///< VolumeReconstruction ReferenceCoordinateFrame; "" when absent
};

/// Reads the device set at `path`. The first VolumeReconstruction element of the document is used
/// (none: no clip rectangle, no fan). A missing CoordinateDefinitions is not an error here.
/// Throws InputError(file, field, what, line) on malformed XML (pugixml's message, line of its
/// offset), a root other than PlusConfiguration, a Transform without From, To or Matrix, From = To,
/// the same From/To pair given twice, a matrix without 16 finite numbers, a last row other than
/// 0 0 0 1 or a singular linear part (field e.g. "CoordinateDefinitions/Transform[From=Image,To=Probe].Matrix"),
/// and malformed clip or fan attributes (field e.g. "VolumeReconstruction.ClipRectangleSize").
PlusDeviceSet readPlusDeviceSet(const std::string& path);

/// Splits a PLUS transform name "ProbeToTracker" or "ProbeToTrackerTransform" into (Probe, Tracker)
/// at the one "To" that follows a non-empty name and precedes an upper-case letter
/// ("ToolToTracker": (Tool, Tracker)); nullopt when there is no such "To" or more than one.
std::optional<std::pair<std::string, std::string>> splitTransformName(const std::string& name);

/// The transform from frame `from` to frame `to` through a chain of `transforms` (each usable
/// forwards, or backwards by its inverse when that is finite), found breadth-first: the shortest
/// chain, and among equally short ones the one using earlier transforms of the list. With the
/// chain A -> B -> C the result is M(B->C) * M(A->B). Identity when from == to; nullopt when no
/// chain exists. E.g. ImageToReference = inverse(ReferenceToTracker) * ProbeToTracker * ImageToProbe.
std::optional<Mat4> chainTransform(const std::vector<PlusTransform>& transforms, const std::string& from,
                                   const std::string& to);

/// A CV_8UC1 mask, height x width pixels (the frame's size), 255 where the pixel centre is inside
/// both the clip rectangle and the fan (angle of (x - ox, y - oy) from +y within angles_deg,
/// distance from the apex within [radius_start_px, radius_stop_px]), 0 elsewhere; an empty Mat
/// when neither a clip rectangle (with a non-zero size) nor a fan is given. In MF image
/// coordinates: apply it to frames flipped to MF (MetaImageHeader::flip_columns/flip_rows).
/// Throws std::invalid_argument when width or height is not positive.
cv::Mat plusFieldOfView(const PlusDeviceSet& ds, int width, int height);

}  // namespace xsect

// Writers of PLUS toolkit files (for synthetic recordings: `xsect phantom` with `plus: true`, tests,
// the benchmark): a MetaImage image sequence (.igs.mha) laid out as PLUS writes it, and a minimal
// PLUS device-set XML. Both read back with meta_image.h / plus_device_set.h / plus_sequence.h.
//
// The .mha header is PLUS's (ObjectType = Image, NDims = 3, AnatomicalOrientation = RAI,
// BinaryData = True, BinaryDataByteOrderMSB = False, CenterOfRotation, CompressedData,
// CompressedDataSize, DimSize = W H N, Kinds = domain domain list, ElementSpacing = 1 1 1,
// ElementType, Offset, TransformMatrix, UltrasoundImageOrientation = MFA), then the per-frame
// `Seq_Frame<NNNN>_<Name> = value` lines frame after frame, and last `ElementDataFile = LOCAL`
// followed by the pixel bytes. As PLUS does, the CompressedDataSize value is written as a
// space-padded placeholder and filled in once the zlib stream has been written.
#pragma once

#include <array>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "geometry/core/types.h"
#include "io/plus_device_set.h"

namespace xsect {

/// Per-frame fields of one frame: name (the part after `Seq_Frame<NNNN>_`, e.g.
/// "ProbeToTrackerTransform") -> value (written as given). Written in the map's (sorted) order.
using MetaFrameFields = std::map<std::string, std::string>;

/// Writes an image sequence of `count` frames to `path` (.mha, data LOCAL).
/// @param frame            frame(i) for i = 0 .. count-1, called once each, in order (so that a
///                         long recording need not be in memory): CV_8UC1 (MET_UCHAR) or CV_16UC1
///                         (MET_USHORT, written little-endian), every frame of frame(0)'s size and
///                         type, stored as MF (row 0 first, column 0 first; no flip)
/// @param perFrameFields   empty, or `count` maps of per-frame fields
/// @param compressed       one zlib stream (deflate level 1) for the whole volume, as PLUS's
///                         CompressedData = True; otherwise raw bytes
/// Memory: one frame and a 256 KiB output buffer. The file is written under a temporary sibling
/// name and renamed onto `path` when complete. Throws std::invalid_argument (count < 1, a frame of
/// another size or type, a field count other than `count`, a field name or value holding a line
/// break or '=' in the name) and std::runtime_error (I/O or zlib failure, naming the file).
void writeMetaImageSequence(const std::string& path, int count, const std::function<cv::Mat(int)>& frame,
                            const std::vector<MetaFrameFields>& perFrameFields, bool compressed);

/// 16 numbers of `m`, row-major, shortest round-trip text, space separated (PLUS's matrix text).
std::string matrixText(const Mat4& m);

/// Writes a minimal PlusConfiguration (version 2.0) to `path` (atomically: temporary sibling
/// renamed): CoordinateDefinitions with Transform From="Image" To="Probe" Matrix = `imageToProbe`
/// (16 numbers, one row per line), and a VolumeReconstruction element with
/// ImageCoordinateFrame="Image", ReferenceCoordinateFrame="Reference", and, when given,
/// ClipRectangleOrigin/ClipRectangleSize ("x y", "w h", pixels of the MF image) and
/// FanAnglesDeg/FanOriginPixel/FanRadiusStartPixel/FanRadiusStopPixel (the fan's fields).
/// Throws std::runtime_error naming the file when it cannot be written.
void writePlusDeviceSet(const std::string& path, const Mat4& imageToProbe,
                        const std::optional<std::array<int, 2>>& clipOrigin = std::nullopt,
                        const std::optional<std::array<int, 2>>& clipSize = std::nullopt,
                        const std::optional<PlusFanMask>& fan = std::nullopt);

}  // namespace xsect

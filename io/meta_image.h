// MetaImage (ITK MetaIO) image sequences, the format of PLUS toolkit tracked-ultrasound recordings
// (*.igs.mha, *.seq.mha): a text header of `Key = Value` lines, then the pixel data.
//
// Format facts relied on:
// - The header ends with its `ElementDataFile = ...` line. With `LOCAL` (.mha) the pixel data
//   starts right after that line's newline; otherwise the value names the data file, relative to
//   the header's folder (.mhd + .raw/.zraw), whose first HeaderSize bytes are skipped (-1: the data
//   is the end of the file). LIST and file-name patterns are not supported.
// - NDims = 2 or 3; DimSize = columns rows [frames]; pixels row after row, frame after frame, no
//   padding. ElementType MET_UCHAR (8 bits) or MET_USHORT (16 bits), one channel;
//   BinaryDataByteOrderMSB (or ElementByteOrderMSB) True: 16-bit samples are big-endian.
// - CompressedData = True: the whole volume is one zlib (or gzip) stream; CompressedDataSize,
//   when given, is its length in bytes.
// - PLUS writes per-frame fields `Seq_Frame<NNNN>_<Name> = value` (frame number zero-padded to at
//   least 4 digits): `<A>To<B>Transform` (16 numbers, a row-major 4x4 matrix mapping points of
//   frame A to frame B, mm), `<A>To<B>TransformStatus` (OK, INVALID, MISSING, ...), `ImageStatus`,
//   `Timestamp` (s).
// - UltrasoundImageOrientation (PLUS): first letter M/U: the image's column axis points towards the
//   Marked/Unmarked side of the transducer; second letter F/N: the row axis points Far from/Near to
//   the transducer; an optional third letter (A/D) orders the slices of a volume and is irrelevant
//   to 2D frames. PLUS calibrations (ImageToProbe) and clip rectangles/fans assume MF images: a
//   frame stored UF must be flipped left-right (columns reversed) to be MF, one stored MN
//   up-down (rows reversed), one stored UN both ways (flip_columns, flip_rows below).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "geometry/core/types.h"

namespace xsect {

enum class MetaPixelType { uint8, uint16 };  ///< MET_UCHAR, MET_USHORT

struct MetaImageHeader {
  std::string path;                   ///< the header file
  int width = 0;                      ///< DimSize[0], pixels (columns)
  int height = 0;                     ///< DimSize[1], pixels (rows)
  int frames = 1;                     ///< DimSize[2] (1 when NDims = 2)
  MetaPixelType pixel = MetaPixelType::uint8;
  bool compressed = false;            ///< CompressedData
  std::int64_t compressed_size = -1;  ///< CompressedDataSize in bytes; -1 when not given
  bool msb = false;                   ///< 16-bit samples stored big-endian
  std::string data_file;              ///< resolved path of the pixel data; "" = this file (LOCAL)
  std::int64_t data_offset = 0;       ///< byte offset of the pixel data in that file
  std::int64_t data_bytes = 0;        ///< bytes of (compressed or raw) pixel data from data_offset
  std::string orientation;            ///< UltrasoundImageOrientation as written; "" when absent
  bool flip_columns = false;          ///< first orientation letter U: reverse columns to get MF
  bool flip_rows = false;             ///< second orientation letter N: reverse rows to get MF
  std::map<std::string, std::string> fields;  ///< every `Key = Value` line, key and value trimmed
  std::map<std::string, int> field_lines;     ///< 1-based line of each key

  /// The value of `key`, "" when absent.
  std::string field(const std::string& key) const;
  bool has(const std::string& key) const { return fields.count(key) != 0; }
  /// The 1-based header line of `key`, -1 when absent.
  int line(const std::string& key) const;
  /// The file the pixel data is read from (data_file, or path when LOCAL).
  const std::string& pixelFile() const { return data_file.empty() ? path : data_file; }
  /// Bytes per sample (1 or 2).
  int bytesPerPixel() const { return pixel == MetaPixelType::uint8 ? 1 : 2; }
  /// Bytes of one frame, uncompressed.
  std::int64_t frameBytes() const { return std::int64_t(width) * height * bytesPerPixel(); }
};

/// Reads and validates the header of the .mha/.mhd at `path` (nothing of the pixel data is read;
/// the data file's size is checked against DimSize and ElementType, or CompressedDataSize).
/// Throws InputError(file, field, what, line) naming the field: NDims, DimSize, ElementType,
/// ElementNumberOfChannels, BinaryData, CompressedData, CompressedDataSize, HeaderSize,
/// BinaryDataByteOrderMSB, ElementDataFile, UltrasoundImageOrientation, ObjectType.
MetaImageHeader readMetaImageHeader(const std::string& path);

/// Reads the frames of a MetaImage in order without holding the volume: raw data is read frame by
/// frame; compressed data is inflated in chunks of 256 KiB (zlib with window 15+32: zlib or gzip).
/// Move-only (it owns the open file and the inflate state).
class MetaImageFrames {
 public:
  /// Opens the pixel data of `h` (a header from readMetaImageHeader). Throws InputError naming
  /// ElementDataFile when the data file cannot be opened.
  explicit MetaImageFrames(const MetaImageHeader& h);
  ~MetaImageFrames();
  MetaImageFrames(MetaImageFrames&&) noexcept;
  MetaImageFrames& operator=(MetaImageFrames&&) noexcept;

  /// The next frame (0, 1, 2, ...): CV_8UC1 or CV_16UC1, height x width, as stored (not flipped to
  /// MF), 16-bit samples in host order. Truncated or corrupt data: InputError naming CompressedData
  /// (compressed) or ElementDataFile (raw) and the frame. The compressed stream's checksum is
  /// verified with the last frame, and a stream holding more than DimSize says is refused then.
  /// Throws std::out_of_range when every frame has been read.
  cv::Mat next();
  /// Index of the frame next() returns.
  int index() const;
  /// Number of frames (DimSize[2]).
  int frames() const;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

/// Frame indices below are 0-based (frame 0 is the first next() returns); names are the part after
/// `Seq_Frame<NNNN>_`.
///
/// The key PLUS writes for frame `frame`'s field `name`: "Seq_Frame0012_" + name.
std::string frameFieldKey(int frame, const std::string& name);

/// The value of `Seq_Frame<frame>_<name>`; nullopt when absent.
std::optional<std::string> frameField(const MetaImageHeader& h, int frame, const std::string& name);

/// Parses 16 finite numbers (whitespace separated) as a row-major 4x4 matrix. Anything else is an
/// InputError(file, field, what, line).
Mat4 parseMatrix4RowMajor(const std::string& text, const std::string& file, const std::string& field,
                          int line = -1);

/// The matrix of frame `frame`'s field `name` (e.g. "ProbeToTrackerTransform"); nullopt when the
/// field is absent; InputError naming the field (e.g. "Seq_Frame0012_ProbeToTrackerTransform") when
/// it is not 16 finite numbers. The last row is not checked (a caller using the matrix should).
std::optional<Mat4> frameMatrix(const MetaImageHeader& h, int frame, const std::string& name);

/// Whether frame `frame`'s status field `statusName` (e.g. "ProbeToTrackerTransformStatus",
/// "ImageStatus") is OK; an absent status counts as OK, any other value (INVALID, MISSING,
/// OUT_OF_VIEW, ...) as not OK.
bool frameStatusOk(const MetaImageHeader& h, int frame, const std::string& statusName);

/// Frame `frame`'s field `name` as a finite number (e.g. "Timestamp", seconds); nullopt when absent;
/// InputError naming the field when it is not a number.
std::optional<double> frameNumber(const MetaImageHeader& h, int frame, const std::string& name);

/// The distinct transform names of the per-frame fields (`<X>To<Y>Transform`, e.g.
/// "ProbeToTrackerTransform"; status fields excluded), sorted.
std::vector<std::string> frameTransformNames(const MetaImageHeader& h);

}  // namespace xsect

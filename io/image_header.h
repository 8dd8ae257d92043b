// The size of a PNG or TIFF image from its header, read before the image is decoded so that a
// corrupt or huge frame is refused before memory is taken for it (issue 15, item 3).
#pragma once

#include <cstdint>
#include <string>

namespace xsect {

struct ImageHeader {
  std::string format;           ///< "png" or "tiff"
  std::uint64_t width = 0;      ///< pixels
  std::uint64_t height = 0;     ///< pixels
  int channels = 1;             ///< samples per pixel as decoded (PNG and TIFF palettes: 3)
  int bits_per_sample = 8;      ///< of the first sample

  std::uint64_t pixels() const { return width * height; }
};

/// Reads the header of the PNG or (classic or Big) TIFF file at `path`: the IHDR chunk of a PNG,
/// the first image directory of a TIFF. Throws std::runtime_error saying what is wrong when the file
/// cannot be read, is neither format, or its header is truncated or gives a zero size.
ImageHeader readImageHeader(const std::string& path);

}  // namespace xsect

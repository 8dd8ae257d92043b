// Slice images: 8- or 16-bit single-channel PNG/TIFF (docs/methods.md), read with OpenCV and validated.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>

#include "io/image_header.h"

namespace xsect {

/// The most pixels one slice image may have (16384 x 16384). Checked from the file's header before
/// the image is decoded, so that a corrupt header cannot make the reader take gigabytes.
constexpr std::uint64_t kMaxImagePixels = std::uint64_t(1) << 28;

/// Reads a grey image. Throws InputError(listing_file, key, ...) if it cannot be read, is not a
/// PNG or TIFF file, its header gives more than kMaxImagePixels, or it is not an 8- or 16-bit
/// single-channel image (colour images are rejected, not silently converted). Size, channels and
/// depth are checked from the header, before the image is decoded.
cv::Mat readGreyImage(const std::string& path, const std::string& listing_file,
                      const std::string& key);

/// The header of the grey image at `path` (image_header.h), checked as readGreyImage checks it:
/// InputError(listing_file, key, ...) for a file that is not a PNG or TIFF, has a corrupt header,
/// is larger than kMaxImagePixels, has several channels or more than 16 bits.
ImageHeader greyImageHeader(const std::string& path, const std::string& listing_file, const std::string& key);

/// The bytes readGreyImage will take for the image at `path`, from its header (see
/// image_header.h). Throws InputError(listing_file, key, ...) as readGreyImage does for a file that
/// is not a PNG or TIFF, has a corrupt header or is larger than kMaxImagePixels.
std::uint64_t greyImageBytes(const std::string& path, const std::string& listing_file,
                             const std::string& key);

/// `image` (8-bit, 1 or 3 channels) as the bytes of a PNG file; deterministic (OpenCV's encoder at
/// a fixed compression level).
std::string pngBytes(const cv::Mat& image);

}  // namespace xsect

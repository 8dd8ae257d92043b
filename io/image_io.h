// Slice images: 8- or 16-bit single-channel PNG/TIFF (GUIDE.md), read with OpenCV and validated.
#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace xsect {

/// Reads a grey image. Throws InputError(listing_file, key, ...) if it cannot be read or is not
/// an 8- or 16-bit single-channel image (colour images are rejected, not silently converted).
cv::Mat readGreyImage(const std::string& path, const std::string& listing_file,
                      const std::string& key);

}  // namespace xsect

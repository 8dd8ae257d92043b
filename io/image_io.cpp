// Grey image reader (see image_io.h).
#include "io/image_io.h"

#include <opencv2/imgcodecs.hpp>

#include "io/input_error.h"

namespace xsect {

cv::Mat readGreyImage(const std::string& path, const std::string& listing_file,
                      const std::string& key) {
  cv::Mat m;
  try {
    m = cv::imread(path, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    throw InputError(listing_file, key, "cannot read image " + path + ": " + e.what());
  }
  if (m.empty()) throw InputError(listing_file, key, "cannot read image " + path + " (not a PNG/TIFF image?)");
  if (m.channels() != 1)
    throw InputError(listing_file, key,
                     "image " + path + " has " + std::to_string(m.channels()) +
                         " channels; a single-channel grey image is required");
  if (m.depth() != CV_8U && m.depth() != CV_16U)
    throw InputError(listing_file, key, "image " + path + " is not 8- or 16-bit");
  return m;
}

}  // namespace xsect

// Grey image reader (see image_io.h).
#include "io/image_io.h"

#include <opencv2/imgcodecs.hpp>

#include <algorithm>

#include "io/image_header.h"
#include "io/input_error.h"

namespace xsect {

ImageHeader greyImageHeader(const std::string& path, const std::string& listing_file, const std::string& key) {
  ImageHeader h;
  try {
    h = readImageHeader(path);
  } catch (const std::runtime_error& e) {
    throw InputError(listing_file, key, "cannot read image " + path + ": " + e.what());
  }
  if (h.pixels() > kMaxImagePixels)
    throw InputError(listing_file, key,
                     "image " + path + " is " + std::to_string(h.width) + " x " + std::to_string(h.height) +
                         " pixels, more than the " + std::to_string(kMaxImagePixels) + " a slice may have");
  // Colour and deep images are refused here, before the decoder allocates for them.
  if (h.channels != 1)
    throw InputError(listing_file, key,
                     "image " + path + " has " + std::to_string(h.channels) +
                         " channels; a single-channel grey image is required");
  if (h.bits_per_sample > 16) throw InputError(listing_file, key, "image " + path + " is not 8- or 16-bit");
  return h;
}

std::uint64_t greyImageBytes(const std::string& path, const std::string& listing_file,
                             const std::string& key) {
  const ImageHeader h = greyImageHeader(path, listing_file, key);
  return h.pixels() * std::uint64_t(h.bits_per_sample > 8 ? 2 : 1);
}

cv::Mat readGreyImage(const std::string& path, const std::string& listing_file,
                      const std::string& key) {
  greyImageBytes(path, listing_file, key);
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

std::string pngBytes(const cv::Mat& image) {
  std::vector<uchar> bytes;
  if (!cv::imencode(".png", image, bytes, {cv::IMWRITE_PNG_COMPRESSION, 6}))
    throw std::runtime_error("cannot encode a PNG image");
  return std::string(bytes.begin(), bytes.end());
}

}  // namespace xsect

// PLUS file writers (see meta_image_writer.h).
#include "io/meta_image_writer.h"

#include <unistd.h>
#include <zlib.h>

#include <atomic>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "io/meta_image.h"
#include "io/text_file.h"
#include "io/yaml_number.h"

namespace xsect {

namespace {

namespace fs = std::filesystem;

/// A fresh name next to `path` (same folder, so the final rename stays on one file system).
std::string temporarySibling(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  const fs::path p(path);
  return (p.parent_path() / ("." + p.filename().string() + ".partial-" + std::to_string(::getpid()) + "-" +
                             std::to_string(counter++)))
      .string();
}

/// Width of the CompressedDataSize placeholder (PLUS pads its header values with spaces too).
constexpr int kSizeField = 20;

bool hostIsBigEndian() {
  const std::uint16_t one = 1;
  unsigned char b;
  std::memcpy(&b, &one, 1);
  return b == 0;
}

/// The bytes of row `r` of `m` as stored (16-bit: little-endian).
const char* rowBytes(const cv::Mat& m, int r, std::string* swapped) {
  const char* p = reinterpret_cast<const char*>(m.ptr(r));
  if (m.depth() != CV_16U || !hostIsBigEndian()) return p;
  const std::size_t n = std::size_t(m.cols) * 2;
  swapped->assign(p, n);
  for (std::size_t i = 0; i + 1 < n; i += 2) std::swap((*swapped)[i], (*swapped)[i + 1]);
  return swapped->data();
}

void checkText(const std::string& s, const std::string& what, bool isName) {
  if (s.find_first_of("\r\n") != std::string::npos || (isName && (s.empty() || s.find('=') != std::string::npos ||
                                                                   s.find_first_of(" \t") != std::string::npos)))
    throw std::invalid_argument("writeMetaImageSequence: invalid " + what + " '" + s + "'");
}

/// Streams deflate output into `out`, counting the bytes.
class Deflater {
 public:
  Deflater(std::ostream& out, const std::string& path) : out_(out), path_(path), buf_(256 * 1024) {
    std::memset(&z_, 0, sizeof z_);
    if (deflateInit(&z_, 1) != Z_OK) throw std::runtime_error(path + ": zlib deflateInit failed");
  }
  ~Deflater() { deflateEnd(&z_); }
  void add(const char* data, std::size_t n) { run(data, n, Z_NO_FLUSH); }
  void finish() { run(nullptr, 0, Z_FINISH); }
  std::int64_t bytes() const { return bytes_; }

 private:
  void run(const char* data, std::size_t n, int flush) {
    z_.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data));
    z_.avail_in = uInt(n);
    for (;;) {
      z_.next_out = reinterpret_cast<Bytef*>(buf_.data());
      z_.avail_out = uInt(buf_.size());
      const int rc = deflate(&z_, flush);
      if (rc == Z_STREAM_ERROR) throw std::runtime_error(path_ + ": zlib deflate failed");
      const std::size_t have = buf_.size() - z_.avail_out;
      if (have) {
        out_.write(buf_.data(), std::streamsize(have));
        if (!out_) throw std::runtime_error("write failed: " + path_);
        bytes_ += std::int64_t(have);
      }
      if (flush == Z_FINISH ? rc == Z_STREAM_END : (z_.avail_in == 0 && z_.avail_out != 0)) break;
    }
  }
  std::ostream& out_;
  std::string path_;
  std::vector<char> buf_;
  z_stream z_;
  std::int64_t bytes_ = 0;
};

}  // namespace

std::string matrixText(const Mat4& m) {
  std::string s;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) s += (s.empty() ? "" : " ") + yamlNumberText(m(r, c));
  return s;
}

void writeMetaImageSequence(const std::string& path, int count, const std::function<cv::Mat(int)>& frame,
                            const std::vector<MetaFrameFields>& perFrameFields, bool compressed) {
  if (count < 1) throw std::invalid_argument("writeMetaImageSequence: no frame");
  if (!perFrameFields.empty() && int(perFrameFields.size()) != count)
    throw std::invalid_argument("writeMetaImageSequence: " + std::to_string(perFrameFields.size()) +
                                " sets of per-frame fields for " + std::to_string(count) + " frames");
  for (const MetaFrameFields& fields : perFrameFields)
    for (const auto& [name, value] : fields) {
      checkText(name, "field name", true);
      checkText(value, "value of " + name, false);
    }

  cv::Mat first = frame(0);
  if (first.empty() || first.channels() != 1 || (first.depth() != CV_8U && first.depth() != CV_16U))
    throw std::invalid_argument("writeMetaImageSequence: frame 0 must be a non-empty CV_8UC1 or CV_16UC1 image");
  const int width = first.cols, height = first.rows, type = first.type();

  const std::string tmp = temporarySibling(path);
  try {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) throw std::runtime_error("cannot write " + path);
    std::ostringstream h;
    h << "ObjectType = Image\n"
      << "NDims = 3\n"
      << "AnatomicalOrientation = RAI\n"
      << "BinaryData = True\n"
      << "BinaryDataByteOrderMSB = False\n"
      << "CenterOfRotation = 0 0 0\n"
      << "CompressedData = " << (compressed ? "True" : "False") << "\n";
    f << h.str();
    std::streampos sizeAt = -1;
    if (compressed) {
      f << "CompressedDataSize = ";
      sizeAt = f.tellp();
      f << std::string(kSizeField, ' ') << "\n";
    }
    h.str("");
    h << "DimSize = " << width << " " << height << " " << count << "\n"
      << "Kinds = domain domain list\n"
      << "ElementSpacing = 1 1 1\n"
      << "ElementType = " << (first.depth() == CV_8U ? "MET_UCHAR" : "MET_USHORT") << "\n"
      << "Offset = 0 0 0\n"
      << "TransformMatrix = 1 0 0 0 1 0 0 0 1\n"
      << "UltrasoundImageOrientation = MFA\n";
    for (int i = 0; i < int(perFrameFields.size()); ++i)
      for (const auto& [name, value] : perFrameFields[std::size_t(i)])
        h << frameFieldKey(i, name) << " = " << value << "\n";
    h << "ElementDataFile = LOCAL\n";
    f << h.str();
    if (!f) throw std::runtime_error("write failed: " + path);

    std::optional<Deflater> z;
    if (compressed) z.emplace(f, path);
    std::string swapped;
    const std::size_t rowSize = std::size_t(width) * first.elemSize();
    for (int i = 0; i < count; ++i) {
      cv::Mat m = i == 0 ? first : frame(i);
      if (m.rows != height || m.cols != width || m.type() != type)
        throw std::invalid_argument("writeMetaImageSequence: frame " + std::to_string(i) + " is " +
                                    std::to_string(m.cols) + "x" + std::to_string(m.rows) + " of type " +
                                    std::to_string(m.type()) + ", frame 0 " + std::to_string(width) + "x" +
                                    std::to_string(height) + " of type " + std::to_string(type));
      if (m.isContinuous() && !(m.depth() == CV_16U && hostIsBigEndian())) {
        const char* p = reinterpret_cast<const char*>(m.data);
        const std::size_t n = rowSize * std::size_t(height);
        if (z)
          z->add(p, n);
        else
          f.write(p, std::streamsize(n));
      } else {
        for (int r = 0; r < height; ++r) {
          const char* p = rowBytes(m, r, &swapped);
          if (z)
            z->add(p, rowSize);
          else
            f.write(p, std::streamsize(rowSize));
        }
      }
      if (!f) throw std::runtime_error("write failed: " + path);
      if (i == 0) first.release();
    }
    if (z) {
      z->finish();
      const std::string n = std::to_string(z->bytes());
      f.seekp(sizeAt);
      f << n;
      if (!f) throw std::runtime_error("write failed: " + path);
    }
    f.close();
    if (!f) throw std::runtime_error("write failed: " + path);
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) throw std::runtime_error("cannot move " + tmp + " to " + path + ": " + ec.message());
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
}

void writePlusDeviceSet(const std::string& path, const Mat4& imageToProbe,
                        const std::optional<std::array<int, 2>>& clipOrigin,
                        const std::optional<std::array<int, 2>>& clipSize, const std::optional<PlusFanMask>& fan) {
  std::ostringstream x;
  x << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<PlusConfiguration version=\"2.0\">\n"
    << "  <CoordinateDefinitions>\n"
    << "    <Transform From=\"Image\" To=\"Probe\"\n"
    << "      Matrix=\"";
  for (int r = 0; r < 4; ++r) {
    x << (r ? "\n              " : "");
    for (int c = 0; c < 4; ++c) x << (c ? " " : "") << yamlNumberText(imageToProbe(r, c));
  }
  x << "\" />\n"
    << "  </CoordinateDefinitions>\n"
    << "  <VolumeReconstruction ImageCoordinateFrame=\"Image\" ReferenceCoordinateFrame=\"Reference\"";
  if (clipOrigin) x << "\n    ClipRectangleOrigin=\"" << (*clipOrigin)[0] << " " << (*clipOrigin)[1] << "\"";
  if (clipSize) x << "\n    ClipRectangleSize=\"" << (*clipSize)[0] << " " << (*clipSize)[1] << "\"";
  if (fan) {
    x << "\n    FanAnglesDeg=\"" << yamlNumberText(fan->angles_deg[0]) << " " << yamlNumberText(fan->angles_deg[1])
      << "\"\n    FanOriginPixel=\"" << yamlNumberText(fan->origin_px[0]) << " " << yamlNumberText(fan->origin_px[1])
      << "\"\n    FanRadiusStartPixel=\"" << yamlNumberText(fan->radius_start_px)
      << "\" FanRadiusStopPixel=\"" << yamlNumberText(fan->radius_stop_px) << "\"";
    if (fan->angles_auto_detect) x << " EnableFanAnglesAutoDetect=\"TRUE\"";
  }
  x << " />\n"
    << "</PlusConfiguration>\n";
  writeTextFileAtomically(path, x.str());
}

}  // namespace xsect

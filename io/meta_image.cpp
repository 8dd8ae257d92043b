// MetaImage header, streamed frames and PLUS per-frame fields (see meta_image.h).
#include "io/meta_image.h"

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "io/file_checks.h"
#include "io/header_text.h"
#include "io/coordinate_limit.h"
#include "io/input_error.h"

namespace xsect {

namespace {

constexpr std::size_t kMaxLine = 1 << 20;                 // bytes of one header line
constexpr std::int64_t kMaxVolumeBytes = std::int64_t(1) << 40;
constexpr std::int64_t kMaxInflateRatio = 1032;            // deflate's largest expansion
constexpr std::size_t kChunk = 1 << 18;                    // compressed bytes read at once




/// A whole-token integer, or nullopt.
std::optional<long long> toInteger(const std::string& t) {
  if (t.empty()) return std::nullopt;
  errno = 0;
  char* end = nullptr;
  const long long v = std::strtoll(t.c_str(), &end, 10);
  if (errno != 0 || *end != '\0' || end == t.c_str()) return std::nullopt;
  return v;
}

/// A whole-token finite number, or nullopt.
std::optional<double> toNumber(const std::string& t) {
  if (t.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (*end != '\0' || end == t.c_str() || !std::isfinite(v)) return std::nullopt;
  return v;
}

bool hostIsBigEndian() {
  const std::uint16_t one = 1;
  unsigned char first;
  std::memcpy(&first, &one, 1);
  return first == 0;
}

/// The value of a True/False field; `fallback` when absent.
bool booleanField(const MetaImageHeader& h, const std::string& key, bool fallback) {
  if (!h.has(key)) return fallback;
  const std::string v = lowercase(h.field(key));
  if (v == "true") return true;
  if (v == "false") return false;
  throw InputError(h.path, key, "expected True or False, got '" + h.field(key) + "'", h.line(key));
}

/// Reads the `Key = Value` lines up to and including ElementDataFile; returns the offset of the
/// byte after that line.
std::int64_t readHeaderLines(std::istream& in, MetaImageHeader& h) {
  std::streambuf* sb = in.rdbuf();
  std::string line;
  std::int64_t offset = 0;
  for (int ln = 1;; ++ln) {
    line.clear();
    bool newline = false;
    for (int c; (c = sb->sbumpc()) != std::char_traits<char>::eof();) {
      ++offset;
      if (c == '\n') {
        newline = true;
        break;
      }
      if (line.size() >= kMaxLine)
        throw InputError(h.path, "", "header line longer than " + std::to_string(kMaxLine) +
                                         " bytes (not a MetaImage header?)", ln);
      line.push_back(char(c));
    }
    if (!newline && line.empty())
      throw InputError(h.path, "ElementDataFile",
                       "missing: a MetaImage header ends with an ElementDataFile line", ln - 1);
    const std::string t = trimmed(line);
    if (t.empty()) {
      if (!newline)
        throw InputError(h.path, "ElementDataFile",
                         "missing: a MetaImage header ends with an ElementDataFile line", ln);
      continue;
    }
    const auto eq = t.find('=');
    if (eq == std::string::npos)
      throw InputError(h.path, "", "expected 'Key = Value' (the header ends with ElementDataFile)", ln);
    const std::string key = trimmed(t.substr(0, eq)), value = trimmed(t.substr(eq + 1));
    if (key.empty()) throw InputError(h.path, "", "a header line has no key before '='", ln);
    if (h.fields.count(key))
      throw InputError(h.path, key, "given twice (first on line " + std::to_string(h.line(key)) + ")", ln);
    h.fields[key] = value;
    h.field_lines[key] = ln;
    if (key == "ElementDataFile") return offset;
    if (!newline)
      throw InputError(h.path, "ElementDataFile",
                       "missing: a MetaImage header ends with an ElementDataFile line", ln);
  }
}

void readDimensions(MetaImageHeader& h) {
  if (!h.has("NDims")) throw InputError(h.path, "NDims", "missing");
  const auto nd = toInteger(h.field("NDims"));
  if (!nd || (*nd != 2 && *nd != 3))
    throw InputError(h.path, "NDims", "expected 2 or 3 (a frame or a sequence of frames), got '" +
                                          h.field("NDims") + "'", h.line("NDims"));
  if (!h.has("DimSize")) throw InputError(h.path, "DimSize", "missing");
  const auto dims = words(h.field("DimSize"));
  if (static_cast<long long>(dims.size()) != *nd)
    throw InputError(h.path, "DimSize", std::to_string(dims.size()) + " sizes given but NDims = " +
                                            std::to_string(*nd), h.line("DimSize"));
  std::vector<int> d;
  for (const auto& t : dims) {
    const auto v = toInteger(t);
    if (!v || *v < 1 || *v > 0x7fffffffLL)
      throw InputError(h.path, "DimSize", "expected positive integers, got '" + t + "'", h.line("DimSize"));
    d.push_back(int(*v));
  }
  h.width = d[0];
  h.height = d[1];
  h.frames = d.size() > 2 ? d[2] : 1;
}

void readPixelType(MetaImageHeader& h) {
  if (!h.has("ElementType")) throw InputError(h.path, "ElementType", "missing");
  const std::string type = h.field("ElementType");
  if (type == "MET_UCHAR") h.pixel = MetaPixelType::uint8;
  else if (type == "MET_USHORT") h.pixel = MetaPixelType::uint16;
  else
    throw InputError(h.path, "ElementType", "'" + type + "' is not supported (MET_UCHAR or MET_USHORT)",
                     h.line("ElementType"));
  if (h.has("ElementNumberOfChannels") && h.field("ElementNumberOfChannels") != "1")
    throw InputError(h.path, "ElementNumberOfChannels",
                     "only single-channel (grey) images are supported, got '" +
                         h.field("ElementNumberOfChannels") + "'", h.line("ElementNumberOfChannels"));
  if (!booleanField(h, "BinaryData", true))
    throw InputError(h.path, "BinaryData", "ASCII pixel data is not supported", h.line("BinaryData"));
  const bool a = booleanField(h, "BinaryDataByteOrderMSB", false);
  const bool b = booleanField(h, "ElementByteOrderMSB", a);
  if (h.has("BinaryDataByteOrderMSB") && h.has("ElementByteOrderMSB") && a != b)
    throw InputError(h.path, "ElementByteOrderMSB", "disagrees with BinaryDataByteOrderMSB",
                     h.line("ElementByteOrderMSB"));
  h.msb = h.has("BinaryDataByteOrderMSB") ? a : b;
}

void readOrientation(MetaImageHeader& h) {
  const std::string key = "UltrasoundImageOrientation";
  if (!h.has(key)) return;
  const std::string o = h.field(key);
  const bool ok = (o.size() == 2 || o.size() == 3) && (o[0] == 'M' || o[0] == 'U') &&
                  (o[1] == 'F' || o[1] == 'N') && (o.size() == 2 || o[2] == 'A' || o[2] == 'D');
  if (!ok)
    throw InputError(h.path, key, "'" + o + "' is not supported: expected M or U (marked/unmarked side), "
                                  "then F or N (far/near), optionally A or D (e.g. MF, UN, MFA)",
                     h.line(key));
  h.orientation = o;
  h.flip_columns = o[0] == 'U';
  h.flip_rows = o[1] == 'N';
}

std::int64_t fileSize(const std::string& path) {
  std::error_code ec;
  const auto n = std::filesystem::file_size(path, ec);
  return ec ? -1 : std::int64_t(n);
}

/// Resolves the data file and checks its size against the header.
void locateData(MetaImageHeader& h, std::int64_t headerEnd) {
  const std::string key = "ElementDataFile";
  const int ln = h.line(key);
  const std::string v = h.field(key);
  if (v.empty()) throw InputError(h.path, key, "empty: expected LOCAL or a data file name", ln);
  const std::string lv = lowercase(v);
  std::int64_t headerSize = 0;
  if (h.has("HeaderSize")) {
    const auto hs = toInteger(h.field("HeaderSize"));
    if (!hs || *hs < -1)
      throw InputError(h.path, "HeaderSize", "expected an integer >= -1, got '" + h.field("HeaderSize") + "'",
                       h.line("HeaderSize"));
    headerSize = *hs;
  }
  if (lv == "local") {
    if (headerSize != 0)
      throw InputError(h.path, "HeaderSize", "not supported with ElementDataFile = LOCAL", h.line("HeaderSize"));
    h.data_file.clear();
    h.data_offset = headerEnd;
  } else {
    if (lv == "list" || lv.rfind("list ", 0) == 0 || v.find('%') != std::string::npos)
      throw InputError(h.path, key, "file lists and file-name patterns are not supported ('" + v + "')", ln);
    std::filesystem::path p(v);
    if (p.is_relative()) p = std::filesystem::path(h.path).parent_path() / p;
    h.data_file = p.string();
    if (!isRegularFile(h.data_file))
      throw InputError(h.path, key, "data file '" + h.data_file + "' not found or not a file", ln);
    if (headerSize == -1 && h.compressed)
      throw InputError(h.path, "HeaderSize", "-1 (data at the end of the file) needs uncompressed data",
                       h.line("HeaderSize"));
    h.data_offset = headerSize;
  }
  const std::int64_t size = fileSize(h.pixelFile());
  if (size < 0) throw InputError(h.path, key, "cannot read the size of '" + h.pixelFile() + "'", ln);
  const std::int64_t raw = h.frameBytes() * h.frames;  // checked <= 2^40 by the caller
  if (headerSize == -1) h.data_offset = std::max<std::int64_t>(0, size - raw);
  const std::int64_t available = std::max<std::int64_t>(0, size - h.data_offset);
  const std::string where = h.data_file.empty() ? "after the header" : "in '" + h.data_file + "'";
  if (!h.compressed) {
    if (available != raw)
      throw InputError(h.path, key,
                       "the pixel data holds " + std::to_string(available) + " bytes " + where + " but DimSize and "
                       "ElementType need " + std::to_string(raw) + (available < raw ? " (truncated)" : ""), ln);
    h.data_bytes = raw;
    return;
  }
  if (h.compressed_size >= 0) {
    if (available < h.compressed_size)
      throw InputError(h.path, "CompressedDataSize",
                       "compressed pixel data is truncated: " + std::to_string(h.compressed_size) +
                           " bytes announced, " + std::to_string(available) + " " + where,
                       h.line("CompressedDataSize"));
    h.data_bytes = h.compressed_size;
  } else {
    h.data_bytes = available;
  }
  if (h.data_bytes == 0)
    throw InputError(h.path, "CompressedData", "no compressed pixel data " + where, h.line("CompressedData"));
  if (raw / kMaxInflateRatio > h.data_bytes)
    throw InputError(h.path, "DimSize",
                     std::to_string(raw) + " bytes of pixels cannot come from " + std::to_string(h.data_bytes) +
                         " bytes of compressed data", h.line("DimSize"));
}

}  // namespace

std::string MetaImageHeader::field(const std::string& key) const {
  const auto it = fields.find(key);
  return it == fields.end() ? std::string() : it->second;
}

int MetaImageHeader::line(const std::string& key) const {
  const auto it = field_lines.find(key);
  return it == field_lines.end() ? -1 : it->second;
}

MetaImageHeader readMetaImageHeader(const std::string& path) {
  MetaImageHeader h;
  h.path = path;
  if (!isRegularFile(path)) throw InputError(path, "", "not found or not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", "cannot open file");
  const std::int64_t headerEnd = readHeaderLines(in, h);
  if (h.has("ObjectType") && h.field("ObjectType") != "Image")
    throw InputError(path, "ObjectType", "expected Image, got '" + h.field("ObjectType") + "'", h.line("ObjectType"));
  readDimensions(h);
  readPixelType(h);
  if (double(h.frameBytes()) * h.frames > double(kMaxVolumeBytes))
    throw InputError(path, "DimSize", "the volume would exceed 2^40 bytes", h.line("DimSize"));
  h.compressed = booleanField(h, "CompressedData", false);
  if (h.has("CompressedDataSize")) {
    const auto n = toInteger(h.field("CompressedDataSize"));
    if (!n || *n < 1)
      throw InputError(path, "CompressedDataSize", "expected a positive integer, got '" +
                                                       h.field("CompressedDataSize") + "'", h.line("CompressedDataSize"));
    h.compressed_size = *n;
  }
  readOrientation(h);
  locateData(h, headerEnd);
  return h;
}

// ---------------------------------------------------------------------------------------------
// Frames

struct MetaImageFrames::State {
  MetaImageHeader h;  // without the fields (copied small)
  std::ifstream in;
  int next = 0;
  std::int64_t left = 0;  // bytes of pixel data not yet read from the file
  bool inflating = false, ended = false;
  z_stream z{};
  std::vector<unsigned char> buf;

  ~State() {
    if (inflating) inflateEnd(&z);
  }

  [[noreturn]] void fail(const std::string& what) const {
    const std::string key = h.compressed ? "CompressedData" : "ElementDataFile";
    throw InputError(h.path, key, what, h.line(key));
  }

  /// Feeds more compressed bytes; false when none is left.
  bool refill() {
    const std::int64_t want = std::min<std::int64_t>(std::int64_t(buf.size()), left);
    if (want <= 0) return false;
    in.read(reinterpret_cast<char*>(buf.data()), want);
    const std::int64_t got = in.gcount();
    if (got <= 0) return false;
    left -= got;
    z.next_in = buf.data();
    z.avail_in = uInt(got);
    return true;
  }

  /// Inflates `n` bytes into `dst`; with `dst` null, drains the stream to its end (checksum)
  /// and refuses any further output.
  void inflateInto(unsigned char* dst, std::int64_t n, int frame) {
    const std::string at = " at frame " + std::to_string(frame);
    if (ended) {
      if (dst == nullptr) return;  // the stream ended exactly with the last frame
      fail("compressed pixel data is truncated" + at + " (the stream ended before it)");
    }
    unsigned char scratch[64];
    std::int64_t done = 0;
    while (dst == nullptr || done < n) {
      if (z.avail_in == 0 && !refill() && dst == nullptr)
        fail("compressed pixel data is truncated" + at + " (the end of the stream and its checksum are missing)");
      if (z.avail_in == 0)
        fail("compressed pixel data is truncated" + at + " (" + std::to_string(done) + " of " +
             std::to_string(n) + " bytes decoded)");
      const std::int64_t room = dst ? std::min<std::int64_t>(n - done, 1 << 30) : std::int64_t(sizeof scratch);
      z.next_out = dst ? dst + done : scratch;
      z.avail_out = uInt(room);
      const int rc = ::inflate(&z, Z_NO_FLUSH);
      const std::int64_t produced = room - z.avail_out;
      if (dst) done += produced;
      else if (produced > 0)
        fail("compressed pixel data is corrupt" + at + " (the stream holds more data than DimSize and ElementType say)");
      if (rc == Z_STREAM_END) {
        ended = true;
        if (dst && done < n)
          fail("compressed pixel data is truncated" + at + " (the stream ends after " + std::to_string(done) +
               " of " + std::to_string(n) + " bytes)");
        return;
      }
      if (rc == Z_DATA_ERROR || rc == Z_NEED_DICT || rc == Z_STREAM_ERROR)
        fail("compressed pixel data is corrupt" + at + " (zlib: " + std::string(z.msg ? z.msg : "invalid data") + ")");
      if (rc == Z_MEM_ERROR) throw std::bad_alloc();
      // Z_OK, or Z_BUF_ERROR (no progress possible: more input needed, read above).
      if (rc == Z_BUF_ERROR && z.avail_in != 0 && z.avail_out != 0)
        fail("compressed pixel data is corrupt" + at);
    }
  }
};

MetaImageFrames::MetaImageFrames(const MetaImageHeader& h) : s_(std::make_unique<State>()) {
  State& s = *s_;
  s.h = h;
  s.h.fields.clear();
  s.h.field_lines.clear();
  for (const char* k : {"CompressedData", "ElementDataFile"})
    if (h.line(k) > 0) s.h.field_lines[k] = h.line(k);
  s.in.open(h.pixelFile(), std::ios::binary);
  if (!s.in) throw InputError(h.path, "ElementDataFile", "cannot open '" + h.pixelFile() + "'", h.line("ElementDataFile"));
  s.in.seekg(h.data_offset);
  if (!s.in) s.fail("cannot seek to the pixel data (offset " + std::to_string(h.data_offset) + ")");
  s.left = h.data_bytes;
  if (h.compressed) {
    s.buf.resize(kChunk);
    if (inflateInit2(&s.z, 15 + 32) != Z_OK) throw std::runtime_error("zlib inflateInit2 failed");
    s.inflating = true;
  }
}

MetaImageFrames::~MetaImageFrames() = default;
MetaImageFrames::MetaImageFrames(MetaImageFrames&&) noexcept = default;
MetaImageFrames& MetaImageFrames::operator=(MetaImageFrames&&) noexcept = default;

int MetaImageFrames::index() const { return s_->next; }
int MetaImageFrames::frames() const { return s_->h.frames; }

cv::Mat MetaImageFrames::next() {
  State& s = *s_;
  if (s.next >= s.h.frames)
    throw std::out_of_range("MetaImageFrames::next: all " + std::to_string(s.h.frames) + " frames were read");
  const int frame = s.next;
  cv::Mat m(s.h.height, s.h.width, s.h.pixel == MetaPixelType::uint8 ? CV_8UC1 : CV_16UC1);
  const std::int64_t n = s.h.frameBytes();
  if (s.h.compressed) {
    s.inflateInto(m.data, n, frame);
    if (frame + 1 == s.h.frames) s.inflateInto(nullptr, 0, frame);  // checksum, nothing more
  } else {
    s.in.read(reinterpret_cast<char*>(m.data), n);
    if (s.in.gcount() != n)
      s.fail("pixel data is truncated at frame " + std::to_string(frame) + " (" + std::to_string(s.in.gcount()) +
             " of " + std::to_string(n) + " bytes)");
  }
  if (s.h.pixel == MetaPixelType::uint16 && s.h.msb != hostIsBigEndian()) {
    unsigned char* p = m.data;
    for (std::int64_t i = 0; i < n; i += 2) std::swap(p[i], p[i + 1]);
  }
  ++s.next;
  return m;
}

// ---------------------------------------------------------------------------------------------
// Per-frame fields

std::string frameFieldKey(int frame, const std::string& name) {
  char num[32];
  std::snprintf(num, sizeof num, "%04d", frame);
  return "Seq_Frame" + std::string(num) + "_" + name;
}

std::optional<std::string> frameField(const MetaImageHeader& h, int frame, const std::string& name) {
  const auto it = h.fields.find(frameFieldKey(frame, name));
  if (it == h.fields.end()) return std::nullopt;
  return it->second;
}

Mat4 parseMatrix4RowMajor(const std::string& text, const std::string& file, const std::string& field, int line) {
  const auto t = words(text);
  if (t.size() != 16)
    throw InputError(file, field, "expected 16 numbers (a row-major 4x4 matrix), got " + std::to_string(t.size()),
                     line);
  Mat4 m;
  for (int i = 0; i < 16; ++i) {
    const auto v = toNumber(t[i]);
    if (!v) throw InputError(file, field, "'" + t[i] + "' is not a finite number", line);
    if (std::abs(*v) > kMaxCoordinate) throw InputError(file, field, coordinateRangeMessage(*v), line);
    m(i / 4, i % 4) = *v;
  }
  return m;
}

std::optional<Mat4> frameMatrix(const MetaImageHeader& h, int frame, const std::string& name) {
  const std::string key = frameFieldKey(frame, name);
  const auto it = h.fields.find(key);
  if (it == h.fields.end()) return std::nullopt;
  return parseMatrix4RowMajor(it->second, h.path, key, h.line(key));
}

bool frameStatusOk(const MetaImageHeader& h, int frame, const std::string& statusName) {
  const auto v = frameField(h, frame, statusName);
  return !v || *v == "OK";
}

std::optional<double> frameNumber(const MetaImageHeader& h, int frame, const std::string& name) {
  const std::string key = frameFieldKey(frame, name);
  const auto it = h.fields.find(key);
  if (it == h.fields.end()) return std::nullopt;
  const auto v = toNumber(it->second);
  if (!v) throw InputError(h.path, key, "expected a finite number, got '" + it->second + "'", h.line(key));
  return v;
}

std::vector<std::string> frameTransformNames(const MetaImageHeader& h) {
  static const std::string prefix = "Seq_Frame", suffix = "Transform";
  std::set<std::string> names;
  for (auto it = h.fields.lower_bound(prefix); it != h.fields.end(); ++it) {
    const std::string& k = it->first;
    if (k.compare(0, prefix.size(), prefix) != 0) break;
    std::size_t p = prefix.size();
    while (p < k.size() && std::isdigit(static_cast<unsigned char>(k[p]))) ++p;
    if (p == prefix.size() || p >= k.size() || k[p] != '_') continue;
    const std::string name = k.substr(p + 1);
    if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0 &&
        name.find("To") != std::string::npos)
      names.insert(name);
  }
  return {names.begin(), names.end()};
}

}  // namespace xsect

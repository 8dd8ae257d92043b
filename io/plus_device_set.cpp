// PLUS device-set reader, transform chains and field-of-view mask (see plus_device_set.h).
// pugixml is confined to this file.
#include "io/plus_device_set.h"

#include <pugixml.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include <Eigen/LU>

#include "io/file_checks.h"
#include "io/coordinate_limit.h"
#include "io/input_error.h"
#include "io/meta_image.h"

namespace xsect {

namespace {

/// The document's text and the 1-based line of a byte offset in it.
struct Source {
  std::string path, text;
  int lineAt(std::ptrdiff_t offset) const {
    if (offset < 0) return -1;
    const auto end = text.begin() + std::min<std::ptrdiff_t>(offset, std::ptrdiff_t(text.size()));
    return 1 + int(std::count(text.begin(), end, '\n'));
  }
  int lineOf(const pugi::xml_node& n) const { return lineAt(n.offset_debug()); }
};

std::vector<std::string> tokens(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> out;
  for (std::string t; in >> t;) out.push_back(t);
  return out;
}

/// Exactly `count` finite numbers from an attribute value.
std::vector<double> numbers(const Source& src, const std::string& field, const std::string& value,
                            std::size_t count, int line) {
  const auto t = tokens(value);
  if (t.size() != count)
    throw InputError(src.path, field, "expected " + std::to_string(count) + " numbers, got '" + value + "'", line);
  std::vector<double> v;
  for (const auto& s : t) {
    char* end = nullptr;
    const double x = std::strtod(s.c_str(), &end);
    if (end == s.c_str() || *end != '\0' || !std::isfinite(x))
      throw InputError(src.path, field, "'" + s + "' is not a finite number", line);
    if (std::abs(x) > kMaxCoordinate) throw InputError(src.path, field, coordinateRangeMessage(x), line);
    v.push_back(x);
  }
  return v;
}

/// Exactly two integers >= 0 from an attribute value.
std::array<int, 2> pixelPair(const Source& src, const std::string& field, const std::string& value, int line) {
  const auto t = tokens(value);
  if (t.size() != 2)
    throw InputError(src.path, field, "expected two integers (pixels), got '" + value + "'", line);
  std::array<int, 2> v{};
  for (int i = 0; i < 2; ++i) {
    errno = 0;
    char* end = nullptr;
    const long x = std::strtol(t[i].c_str(), &end, 10);
    if (errno != 0 || end == t[i].c_str() || *end != '\0' || x < 0 || x > 1000000000L)
      throw InputError(src.path, field, "expected a non-negative integer (pixels), got '" + t[i] + "'", line);
    v[i] = int(x);
  }
  return v;
}

void collect(const pugi::xml_node& n, const char* name, std::vector<pugi::xml_node>* out) {
  for (pugi::xml_node c = n.first_child(); c; c = c.next_sibling()) {
    if (c.type() != pugi::node_element) continue;
    if (std::strcmp(c.name(), name) == 0) out->push_back(c);
    collect(c, name, out);
  }
}

void readTransforms(const Source& src, const pugi::xml_node& root, PlusDeviceSet* ds) {
  std::vector<pugi::xml_node> defs;
  if (std::strcmp(root.name(), "CoordinateDefinitions") == 0) defs.push_back(root);
  collect(root, "CoordinateDefinitions", &defs);
  std::map<std::pair<std::string, std::string>, int> seen;  // (from, to) -> line
  int k = 0;
  for (const auto& d : defs)
    for (pugi::xml_node t = d.child("Transform"); t; t = t.next_sibling("Transform")) {
      ++k;
      const int line = src.lineOf(t);
      const pugi::xml_attribute from = t.attribute("From"), to = t.attribute("To"), mat = t.attribute("Matrix");
      const std::string indexed = "CoordinateDefinitions/Transform[" + std::to_string(k) + "]";
      if (!from || std::string(from.value()).empty()) throw InputError(src.path, indexed + ".From", "missing", line);
      if (!to || std::string(to.value()).empty()) throw InputError(src.path, indexed + ".To", "missing", line);
      PlusTransform pt{from.value(), to.value(), Mat4::Identity()};
      const std::string base = "CoordinateDefinitions/Transform[From=" + pt.from + ",To=" + pt.to + "]";
      if (pt.from == pt.to) throw InputError(src.path, base, "From and To name the same frame", line);
      const auto key = std::make_pair(pt.from, pt.to), back = std::make_pair(pt.to, pt.from);
      for (const auto& other : {key, back})
        if (seen.count(other))
          throw InputError(src.path, base, "the transform between " + pt.from + " and " + pt.to +
                                               " is already defined on line " + std::to_string(seen[other]), line);
      seen[key] = line;
      const std::string field = base + ".Matrix";
      if (!mat) throw InputError(src.path, field, "missing", line);
      pt.matrix = parseMatrix4RowMajor(mat.value(), src.path, field, line);
      const Eigen::RowVector4d last = pt.matrix.row(3);
      if ((last - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9)
        throw InputError(src.path, field, "the last row must be 0 0 0 1", line);
      const Eigen::Matrix3d a = pt.matrix.topLeftCorner<3, 3>();
      const double scale = a.norm();
      if (!(std::abs(a.determinant()) > 1e-10 * scale * scale * scale))
        throw InputError(src.path, field, "the matrix is singular (its 3x3 part has no inverse)", line);
      ds->transforms.push_back(pt);
    }
}

void readVolumeReconstruction(const Source& src, const pugi::xml_node& root, PlusDeviceSet* ds) {
  std::vector<pugi::xml_node> found;
  if (std::strcmp(root.name(), "VolumeReconstruction") == 0) found.push_back(root);
  collect(root, "VolumeReconstruction", &found);
  if (found.empty()) return;
  const pugi::xml_node v = found.front();
  const int line = src.lineOf(v);
  const auto attr = [&](const char* name) -> std::optional<std::string> {
    const pugi::xml_attribute a = v.attribute(name);
    if (!a) return std::nullopt;
    return std::string(a.value());
  };
  const auto key = [](const std::string& name) { return "VolumeReconstruction." + name; };
  ds->image_frame = attr("ImageCoordinateFrame").value_or("");
  ds->reference_frame = attr("ReferenceCoordinateFrame").value_or("");
  if (auto s = attr("ClipRectangleOrigin")) ds->clip_origin = pixelPair(src, key("ClipRectangleOrigin"), *s, line);
  if (auto s = attr("ClipRectangleSize")) ds->clip_size = pixelPair(src, key("ClipRectangleSize"), *s, line);

  // Each fan attribute under its current name, else its deprecated one.
  const auto either = [&](const char* current, const char* old) -> std::pair<std::string, std::optional<std::string>> {
    if (auto s = attr(current)) return {current, s};
    if (auto s = attr(old)) return {old, s};
    return {current, std::nullopt};
  };
  const auto [anglesName, angles] = either("FanAnglesDeg", "FanAngles");
  if (!angles) return;
  const auto a = numbers(src, key(anglesName), *angles, 2, line);
  if (a[0] == 0.0 && a[1] == 0.0) return;  // PLUS: both 0 = no fan clipping
  PlusFanMask fan;
  for (double x : a)
    if (!(std::abs(x) < 90.0))
      throw InputError(src.path, key(anglesName), "fan angles must lie strictly between -90 and 90 degrees", line);
  fan.angles_deg = {std::min(a[0], a[1]), std::max(a[0], a[1])};
  const auto [originName, origin] = either("FanOriginPixel", "FanOrigin");
  if (origin) {
    const auto o = numbers(src, key(originName), *origin, 2, line);
    fan.origin_px = {o[0], o[1]};
  }
  if (auto s = attr("FanRadiusStartPixel")) fan.radius_start_px = numbers(src, key("FanRadiusStartPixel"), *s, 1, line)[0];
  const auto [stopName, stop] = either("FanRadiusStopPixel", "FanDepth");
  if (stop) fan.radius_stop_px = numbers(src, key(stopName), *stop, 1, line)[0];
  if (fan.radius_start_px < 0.0)
    throw InputError(src.path, key("FanRadiusStartPixel"), "must not be negative", line);
  if (!(fan.radius_stop_px > fan.radius_start_px))
    throw InputError(src.path, key(stopName), "must exceed FanRadiusStartPixel", line);
  if (auto s = attr("EnableFanAnglesAutoDetect")) {
    std::string b = *s;
    for (char& c : b) c = char(std::toupper(static_cast<unsigned char>(c)));
    if (b != "TRUE" && b != "FALSE")
      throw InputError(src.path, key("EnableFanAnglesAutoDetect"), "expected TRUE or FALSE, got '" + *s + "'", line);
    fan.angles_auto_detect = b == "TRUE";
  }
  ds->fan = fan;
}

}  // namespace

PlusDeviceSet readPlusDeviceSet(const std::string& path) {
  Source src{path, {}};
  if (!isRegularFile(path)) throw InputError(path, "", "not found or not a file");
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path, "", "cannot open file");
    std::ostringstream s;
    s << in.rdbuf();
    src.text = s.str();
  }
  pugi::xml_document doc;
  const pugi::xml_parse_result r = doc.load_buffer(src.text.data(), src.text.size());
  if (!r) throw InputError(path, "", std::string("malformed XML: ") + r.description(), src.lineAt(r.offset));
  const pugi::xml_node root = doc.document_element();
  if (!root || std::strcmp(root.name(), "PlusConfiguration") != 0)
    throw InputError(path, "PlusConfiguration",
                     "the root element is '" + std::string(root ? root.name() : "") + "', expected PlusConfiguration",
                     root ? src.lineOf(root) : -1);
  PlusDeviceSet ds;
  ds.path = path;
  readTransforms(src, root, &ds);
  readVolumeReconstruction(src, root, &ds);
  return ds;
}

std::optional<std::pair<std::string, std::string>> splitTransformName(const std::string& name) {
  std::string n = name;
  const std::string suffix = "Transform";
  if (n.size() > suffix.size() && n.compare(n.size() - suffix.size(), suffix.size(), suffix) == 0)
    n.resize(n.size() - suffix.size());
  std::optional<std::pair<std::string, std::string>> out;
  for (std::size_t p = 1; p + 2 < n.size(); ++p)
    if (n.compare(p, 2, "To") == 0 && std::isupper(static_cast<unsigned char>(n[p + 2]))) {
      if (out) return std::nullopt;  // ambiguous
      out = std::make_pair(n.substr(0, p), n.substr(p + 2));
    }
  return out;
}

std::optional<Mat4> chainTransform(const std::vector<PlusTransform>& transforms, const std::string& from,
                                   const std::string& to) {
  if (from == to) return Mat4::Identity();
  // Edges in list order, each transform forwards then backwards.
  struct Edge {
    std::string a, b;
    Mat4 m;
  };
  std::vector<Edge> edges;
  for (const auto& t : transforms) {
    edges.push_back({t.from, t.to, t.matrix});
    const Mat4 inv = t.matrix.inverse();
    if (inv.allFinite()) edges.push_back({t.to, t.from, inv});
  }
  std::map<std::string, int> via;  // frame -> edge reaching it (-1: the start)
  via[from] = -1;
  std::deque<std::string> queue{from};
  while (!queue.empty() && !via.count(to)) {
    const std::string at = queue.front();
    queue.pop_front();
    for (int e = 0; e < int(edges.size()); ++e)
      if (edges[e].a == at && !via.count(edges[e].b)) {
        via[edges[e].b] = e;
        queue.push_back(edges[e].b);
      }
  }
  if (!via.count(to)) return std::nullopt;
  Mat4 m = Mat4::Identity();
  for (std::string f = to; via[f] >= 0; f = edges[via[f]].a) m = m * edges[via[f]].m;
  return m;
}

cv::Mat plusFieldOfView(const PlusDeviceSet& ds, int width, int height) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("plusFieldOfView: the frame size must be positive");
  const bool clip = ds.clip_size && (*ds.clip_size)[0] > 0 && (*ds.clip_size)[1] > 0;
  if (!clip && !ds.fan) return cv::Mat();
  cv::Mat mask(height, width, CV_8UC1, cv::Scalar(clip ? 0 : 255));
  if (clip) {
    const std::array<int, 2> o = ds.clip_origin.value_or(std::array<int, 2>{0, 0});
    const cv::Rect r = cv::Rect(o[0], o[1], (*ds.clip_size)[0], (*ds.clip_size)[1]) & cv::Rect(0, 0, width, height);
    if (r.area() > 0) mask(r).setTo(255);
  }
  if (ds.fan) {
    const PlusFanMask& f = *ds.fan;
    constexpr double kRadPerDeg = 3.14159265358979323846 / 180.0;
    const double lo = f.angles_deg[0] * kRadPerDeg, hi = f.angles_deg[1] * kRadPerDeg;
    for (int y = 0; y < height; ++y) {
      unsigned char* row = mask.ptr<unsigned char>(y);
      const double dy = y - f.origin_px[1];
      for (int x = 0; x < width; ++x) {
        if (!row[x]) continue;
        const double dx = x - f.origin_px[0];
        const double r = std::hypot(dx, dy), angle = std::atan2(dx, dy);
        if (angle < lo || angle > hi || r < f.radius_start_px || r > f.radius_stop_px) row[x] = 0;
      }
    }
  }
  return mask;
}

}  // namespace xsect

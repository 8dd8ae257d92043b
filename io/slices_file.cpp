// Reader and writer of slices.yaml (docs/inputs.md), validated where the file enters.
#include "io/slices_file.h"

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "geometry/core/plane_of_pose.h"
#include "io/file_checks.h"
#include "io/coordinate_limit.h"
#include "io/input_error.h"
#include "io/text_file.h"
#include "io/yaml_fields.h"
#include "io/yaml_number.h"

namespace xsect {
namespace fs = std::filesystem;

namespace {

Mat4 readPose(const YAML::Node& n, const std::string& file, const std::string& key) {
  if (!n) throw InputError(file, key, "missing (a 4x4 row-major matrix is required)");
  if (!n.IsSequence() || n.size() != 4)
    throw InputError(file, key, "must be a 4x4 matrix: a list of 4 rows", yamlLine(n));
  Mat4 m;
  for (int r = 0; r < 4; ++r) {
    const YAML::Node row = n[r];
    const std::string rk = key + "[" + std::to_string(r) + "]";
    if (!row.IsSequence() || row.size() != 4)
      throw InputError(file, rk, "must be a row of 4 numbers", yamlLine(row));
    for (int c = 0; c < 4; ++c) {
      const std::string ck = rk + "[" + std::to_string(c) + "]";
      m(r, c) = yamlNumber(row[c], file, ck);
      if (std::abs(m(r, c)) > kMaxCoordinate) throw InputError(file, ck, coordinateRangeMessage(m(r, c)), yamlLine(row[c]));
    }
  }
  if (const std::string problem = poseProblem(m); !problem.empty()) throw InputError(file, key, problem, yamlLine(n));
  return m;
}

std::string resolve(const fs::path& base, const std::string& p) {
  fs::path q(p);
  if (q.is_relative()) q = base / q;
  return q.lexically_normal().string();
}

/// The file's non-empty list `slices:`.
YAML::Node sliceList(const std::string& path) {
  const YAML::Node root = loadYamlFile(path);
  if (!root.IsMap()) throw InputError(path, "", "top level must be a map with key 'slices'");
  const YAML::Node list = root["slices"];
  if (!list) throw InputError(path, "slices", "missing");
  if (!list.IsSequence() || list.size() == 0)
    throw InputError(path, "slices", "must be a non-empty list", yamlLine(list));
  return list;
}

}  // namespace

std::vector<SliceRecord> readSlicesFile(const std::string& path, std::vector<std::string>* warnings) {
  const YAML::Node list = sliceList(path);
  const fs::path base = fs::absolute(fs::path(path)).parent_path();
  std::vector<SliceRecord> out;
  out.reserve(list.size());
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YAML::Node s = list[i];
    const std::string key = "slices[" + std::to_string(i) + "]";
    if (!s.IsMap()) throw InputError(path, key, "must be a map", yamlLine(s));
    for (const auto& kv : s) {
      const std::string k = kv.first.Scalar();
      if (k != "image" && k != "image_to_world" && k != "fov" && warnings)
        warnings->push_back(path + ":" + std::to_string(yamlLine(kv.first)) + ": unknown key '" +
                            key + "." + k + "' ignored" + didYouMean(k, {"image", "image_to_world", "fov"}));
    }
    SliceRecord r;
    if (!s["image"]) throw InputError(path, key + ".image", "missing", yamlLine(s));
    r.image = yamlString(s["image"], path, key + ".image");
    r.image_resolved = resolve(base, r.image);
    if (!isRegularFile(r.image_resolved))
      throw InputError(path, key + ".image", "file not found: " + r.image_resolved,
                       yamlLine(s["image"]));
    r.image_to_world = readPose(s["image_to_world"], path, key + ".image_to_world");
    if (s["fov"]) {
      r.fov = yamlString(s["fov"], path, key + ".fov");
      r.fov_resolved = resolve(base, *r.fov);
      if (!isRegularFile(*r.fov_resolved))
        throw InputError(path, key + ".fov", "file not found: " + *r.fov_resolved,
                         yamlLine(s["fov"]));
    }
    out.push_back(std::move(r));
  }
  return out;
}

std::vector<PoseRecord> readPosesFile(const std::string& path) {
  const YAML::Node list = sliceList(path);
  std::vector<PoseRecord> out;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YAML::Node s = list[i];
    const std::string key = "slices[" + std::to_string(i) + "]";
    if (!s.IsMap()) throw InputError(path, key, "must be a map", yamlLine(s));
    PoseRecord r;
    r.image_to_world = readPose(s["image_to_world"], path, key + ".image_to_world");
    if (s["width"]) r.width = yamlInteger(s["width"], path, key + ".width", 1, 1 << 20);
    if (s["height"]) r.height = yamlInteger(s["height"], path, key + ".height", 1, 1 << 20);
    out.push_back(r);
  }
  return out;
}

namespace {
void writeMatrix(std::ostringstream& os, const Mat4& m) {
  os << "    image_to_world:\n";
  for (int r = 0; r < 4; ++r) {
    os << "      - [";
    for (int c = 0; c < 4; ++c) os << (c ? ", " : "") << yamlNumberText(m(r, c));
    os << "]\n";
  }
}
}  // namespace

void writePosesFile(const std::string& path, const std::vector<PoseRecord>& poses, const std::string& header,
                    const std::vector<std::string>& notes) {
  std::ostringstream os;
  if (!header.empty()) os << "# " << header << "\n";
  os << "slices:" << (poses.empty() ? " []" : "") << "\n";
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (i < notes.size() && !notes[i].empty()) os << "  # " << notes[i] << "\n";
    os << "  - width: " << poses[i].width << "\n";
    os << "    height: " << poses[i].height << "\n";
    writeMatrix(os, poses[i].image_to_world);
  }
  writeTextFile(path, std::string(os.str()));
}

void writeSlicesFile(const std::string& path, const std::vector<SliceRecord>& slices) {
  std::ostringstream os;
  os << "slices:\n";
  for (const auto& s : slices) {
    os << "  - image: " << s.image << "\n";
    writeMatrix(os, s.image_to_world);
    if (s.fov) os << "    fov: " << *s.fov << "\n";
  }
  writeTextFile(path, std::string(os.str()));
}

}  // namespace xsect

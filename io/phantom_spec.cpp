// Reader of the phantom SPEC.yaml (format in phantom_spec.h). Strict: unknown keys are errors,
// since a misspelt key would otherwise silently fall back to a default.
#include "io/phantom_spec.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>

#include "io/input_error.h"
#include "io/yaml_fields.h"
#include "io/yaml_number.h"

namespace xsect {
namespace {

int lineOf(const YAML::Node& n) { return n ? yamlLine(n) : -1; }

struct Reader {
  std::string file;

  void keys(const YAML::Node& map, const std::string& prefix,
            const std::set<std::string>& allowed) const {
    for (const auto& kv : map) {
      const std::string k = kv.first.Scalar();
      if (!allowed.count(k)) {
        std::string list;
        for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
        throw InputError(file, prefix + k, "unknown key (expected one of: " + list + ")",
                         lineOf(kv.first));
      }
    }
  }
  YAML::Node map(const YAML::Node& parent, const std::string& key, const std::string& path,
                 bool required) const {
    const YAML::Node n = parent[key];
    if (!n) {
      if (required) throw InputError(file, path, "missing", lineOf(parent));
      return YAML::Node(YAML::NodeType::Map);
    }
    if (!n.IsMap()) throw InputError(file, path, "must be a map", lineOf(n));
    return n;
  }
  double number(const YAML::Node& parent, const std::string& key, const std::string& path,
                std::optional<double> def, double lo = -INFINITY, bool loOpen = false,
                double hi = INFINITY) const {
    const YAML::Node n = parent[key];
    if (!n) {
      if (!def) throw InputError(file, path, "missing", lineOf(parent));
      return *def;
    }
    const double v = yamlNumber(n, file, path);
    if (v < lo || (loOpen && v == lo) || v > hi) {
      std::string range = loOpen ? "> " : ">= ";
      range += yamlNumberText(lo);
      if (std::isfinite(hi)) range += " and <= " + yamlNumberText(hi);
      throw InputError(file, path, "must be " + range + " (got " + n.Scalar() + ")", lineOf(n));
    }
    return v;
  }
  int integer(const YAML::Node& parent, const std::string& key, const std::string& path,
              std::optional<int> def, int lo, int hi) const {
    const YAML::Node n = parent[key];
    if (!n) {
      if (!def) throw InputError(file, path, "missing", lineOf(parent));
      return *def;
    }
    return yamlInteger(n, file, path, lo, hi);
  }
  Vec3 vec3(const YAML::Node& parent, const std::string& key, const std::string& path,
            const Vec3& def, bool unit = false) const {
    const YAML::Node n = parent[key];
    if (!n) return def;
    if (!n.IsSequence() || n.size() != 3)
      throw InputError(file, path, "must be a list of 3 numbers", lineOf(n));
    Vec3 v;
    for (int i = 0; i < 3; ++i) v[i] = yamlNumber(n[i], file, path + "[" + std::to_string(i) + "]");
    if (unit) {
      if (v.norm() < 1e-12) throw InputError(file, path, "must be a non-zero vector", lineOf(n));
      v.normalize();
    }
    return v;
  }
  /// An integer, or the word "auto" (returned as 0).
  int sizeOrAuto(const YAML::Node& parent, const std::string& key, const std::string& path) const {
    const YAML::Node n = parent[key];
    if (n && n.IsScalar() && n.Scalar() == "auto") return 0;
    return integer(parent, key, path, 0, 0, 20000);
  }
};

PhantomShape readShape(const Reader& r, const YAML::Node& root) {
  const YAML::Node sh = r.map(root, "shape", "shape", true);
  r.keys(sh, "shape.", {"kind", "params", "centre", "rotation_deg", "label_split"});
  PhantomShape s;
  if (!sh["kind"]) throw InputError(r.file, "shape.kind", "missing", lineOf(sh));
  s.kind = yamlChoice(sh["kind"], r.file, "shape.kind", kShapeKinds, "shape kind");
  const auto spec = phantomShapeParams(s.kind);
  const YAML::Node params = r.map(sh, "params", "shape.params", false);
  for (const auto& kv : params) {
    const std::string k = kv.first.Scalar();
    if (!spec.count(k)) {
      std::string list;
      for (const auto& [name, def] : spec) list += (list.empty() ? "" : ", ") + name;
      throw InputError(r.file, "shape.params." + k,
                       "unknown parameter for " + std::string(nameOf(kShapeKinds, s.kind)) + " (expected: " + list + ")",
                       lineOf(kv.first));
    }
    s.params[k] = yamlNumber(kv.second, r.file, "shape.params." + k);
  }
  if (const auto problem = checkPhantomShape(s)) {
    const YAML::Node at = params[problem->param];
    throw InputError(r.file, "shape.params." + problem->param, problem->message,
                     at ? lineOf(at) : lineOf(sh));
  }
  s.centre = r.vec3(sh, "centre", "shape.centre", Vec3::Zero());
  s.rotation = rotationFromEulerXyzDeg(r.vec3(sh, "rotation_deg", "shape.rotation_deg", Vec3::Zero()));
  if (sh["label_split"]) {
    const YAML::Node ls = r.map(sh, "label_split", "shape.label_split", true);
    r.keys(ls, "shape.label_split.", {"point", "normal"});
    if (!ls["normal"]) throw InputError(r.file, "shape.label_split.normal", "missing", lineOf(ls));
    PhantomShape::LabelSplit split;
    split.point = r.vec3(ls, "point", "shape.label_split.point", Vec3::Zero());
    split.normal = r.vec3(ls, "normal", "shape.label_split.normal", Vec3::UnitX(), true);
    s.label_split = split;
  }
  try {
    return completePhantomShape(std::move(s));
  } catch (const std::runtime_error& e) {
    throw InputError(r.file, "shape.params", e.what(), lineOf(params));
  }
}

SlicingPattern readPattern(const Reader& r, const YAML::Node& root) {
  const YAML::Node pn = r.map(root, "pattern", "pattern", true);
  SlicingPattern p;
  if (!pn["kind"]) throw InputError(r.file, "pattern.kind", "missing", lineOf(pn));
  p.kind = yamlChoice(pn["kind"], r.file, "pattern.kind", kPatternKinds, "pattern");
  const int maxCount = 10000;
  if (p.kind == PatternKind::parallel) {
    r.keys(pn, "pattern.", {"kind", "extra_planes", "count", "direction", "spacing_mm", "span_mm",
                            "positions_mm", "tilt_deg"});
    p.direction = r.vec3(pn, "direction", "pattern.direction", Vec3::UnitZ(), true);
    if (const YAML::Node pos = pn["positions_mm"]) {
      if (!pos.IsSequence() || pos.size() == 0)
        throw InputError(r.file, "pattern.positions_mm", "must be a non-empty list of numbers",
                         lineOf(pos));
      for (std::size_t i = 0; i < pos.size(); ++i)
        p.positions_mm.push_back(
            yamlNumber(pos[i], r.file, "pattern.positions_mm[" + std::to_string(i) + "]"));
      if (pn["count"] || pn["spacing_mm"] || pn["span_mm"])
        throw InputError(r.file, "pattern.positions_mm",
                         "excludes count, spacing_mm and span_mm", lineOf(pos));
      p.count = int(p.positions_mm.size());
    } else {
      p.count = r.integer(pn, "count", "pattern.count", std::nullopt, 1, maxCount);
      if (pn["spacing_mm"] && pn["span_mm"])
        throw InputError(r.file, "pattern.span_mm", "give spacing_mm or span_mm, not both",
                         lineOf(pn["span_mm"]));
      if (pn["spacing_mm"])
        p.spacing_mm = r.number(pn, "spacing_mm", "pattern.spacing_mm", std::nullopt, 0, true);
      if (pn["span_mm"]) p.span_mm = r.number(pn, "span_mm", "pattern.span_mm", std::nullopt, 0);
    }
    p.tilt_deg = r.number(pn, "tilt_deg", "pattern.tilt_deg", 0.0, 0, false, 89);
  } else if (p.kind == PatternKind::multiaxial) {
    r.keys(pn, "pattern.", {"kind", "extra_planes", "count", "counts"});
    if (const YAML::Node cs = pn["counts"]) {
      if (pn["count"])
        throw InputError(r.file, "pattern.counts", "give count or counts, not both", lineOf(cs));
      if (!cs.IsSequence() || cs.size() != 3)
        throw InputError(r.file, "pattern.counts", "must be a list of 3 integers [nx, ny, nz]",
                         lineOf(cs));
      for (int i = 0; i < 3; ++i) {
        YAML::Node wrap;
        wrap["v"] = cs[i];
        p.counts[i] = r.integer(wrap, "v", "pattern.counts[" + std::to_string(i) + "]",
                                std::nullopt, 0, maxCount);
      }
      if (p.counts[0] + p.counts[1] + p.counts[2] == 0)
        throw InputError(r.file, "pattern.counts", "at least one plane is required", lineOf(cs));
    } else {
      p.count = r.integer(pn, "count", "pattern.count", std::nullopt, 1, maxCount);
      p.counts = {p.count, p.count, p.count};
    }
  } else if (p.kind == PatternKind::random) {
    r.keys(pn, "pattern.", {"kind", "extra_planes", "count"});
    p.count = r.integer(pn, "count", "pattern.count", std::nullopt, 1, maxCount);
  } else if (p.kind == PatternKind::fan) {
    r.keys(pn, "pattern.", {"kind", "extra_planes", "count", "axis", "span_deg"});
    p.count = r.integer(pn, "count", "pattern.count", std::nullopt, 1, maxCount);
    p.axis = r.vec3(pn, "axis", "pattern.axis", Vec3::UnitZ(), true);
    p.span_deg = r.number(pn, "span_deg", "pattern.span_deg", 180.0, 0, true, 180);
  } else if (p.kind == PatternKind::freehand) {
    r.keys(pn, "pattern.", {"kind", "extra_planes", "count", "direction", "span_mm", "tilt_deg",
                            "drift_mm", "sector", "sector_angle_deg", "apex_px"});
    p.count = r.integer(pn, "count", "pattern.count", std::nullopt, 1, maxCount);
    p.direction = r.vec3(pn, "direction", "pattern.direction", Vec3::UnitZ(), true);
    if (pn["span_mm"]) p.span_mm = r.number(pn, "span_mm", "pattern.span_mm", std::nullopt, 0, true);
    p.tilt_deg = r.number(pn, "tilt_deg", "pattern.tilt_deg", 3.0, 0, false, 30);
    p.drift_mm = r.number(pn, "drift_mm", "pattern.drift_mm", 1.0, 0);
    if (pn["sector"]) p.sector = yamlBool(pn["sector"], r.file, "pattern.sector");
    p.sector_angle_deg =
        r.number(pn, "sector_angle_deg", "pattern.sector_angle_deg", 0.0, 0, false, 170);
    p.apex_px = r.number(pn, "apex_px", "pattern.apex_px", 0.0, 0);
  }
  return p;
}

std::vector<PhantomPlane> readExtraPlanes(const Reader& r, const YAML::Node& root) {
  std::vector<PhantomPlane> out;
  const YAML::Node list = root["pattern"]["extra_planes"];
  if (!list) return out;
  if (!list.IsSequence() || list.size() == 0 || list.size() > 1000)
    throw InputError(r.file, "pattern.extra_planes",
                     "must be a list of 1 to 1000 planes {point: [x, y, z], normal: [x, y, z]}",
                     lineOf(list));
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string key = "pattern.extra_planes[" + std::to_string(i) + "]";
    const YAML::Node pl = list[i];
    if (!pl.IsMap())
      throw InputError(r.file, key, "must be a map {point: [x, y, z], normal: [x, y, z]}",
                       lineOf(pl));
    r.keys(pl, key + ".", {"point", "normal", "image_centre"});
    for (const char* k : {"point", "normal"})
      if (!pl[k]) throw InputError(r.file, key + "." + k, "missing", lineOf(pl));
    PhantomPlane p;
    p.point = r.vec3(pl, "point", key + ".point", Vec3::Zero());
    p.normal = r.vec3(pl, "normal", key + ".normal", Vec3::UnitZ(), true);
    if (pl["image_centre"]) p.image_centre = r.vec3(pl, "image_centre", key + ".image_centre", Vec3::Zero());
    out.push_back(p);
  }
  return out;
}

}  // namespace

PhantomSpec readPhantomSpec(const std::string& path) {
  const Reader r{path};
  const YAML::Node root = loadYamlFile(path);
  if (!root.IsMap()) throw InputError(path, "", "top level must be a map (keys shape, pattern, ...)");
  r.keys(root, "", {"seed", "shape", "pattern", "image", "degradations", "config", "plus"});
  PhantomSpec s;
  s.path = path;
  if (root["seed"]) {
    const double v = yamlNumber(root["seed"], path, "seed");
    if (v < 0 || v != std::floor(v) || v > 9007199254740992.0)
      throw InputError(path, "seed", "must be a non-negative integer", lineOf(root["seed"]));
    s.seed = std::uint64_t(v);
  }
  s.shape = readShape(r, root);
  s.pattern = readPattern(r, root);
  s.extra_planes = readExtraPlanes(r, root);

  const YAML::Node im = r.map(root, "image", "image", false);
  r.keys(im, "image.", {"pixel_mm", "width", "height", "margin_px"});
  Vec3 bmin, bmax;
  bounds(s.shape, &bmin, &bmax);
  const YAML::Node px = im["pixel_mm"];
  if (px && !(px.IsScalar() && px.Scalar() == "auto"))
    s.image.pixel_mm = r.number(im, "pixel_mm", "image.pixel_mm", std::nullopt, 0, true);
  else
    s.image.pixel_mm = (bmax - bmin).norm() / 160.0;
  s.image.width = r.sizeOrAuto(im, "width", "image.width");
  s.image.height = r.sizeOrAuto(im, "height", "image.height");
  s.image.margin_px = r.integer(im, "margin_px", "image.margin_px", 4, 0, 1000);
  const double diameter = (bmax - bmin).norm();
  const double autoPixels = diameter / s.image.pixel_mm;
  if ((s.image.width == 0 || s.image.height == 0) && autoPixels > 8000)
    throw InputError(path, "image.pixel_mm",
                     "too small for the shape: the automatic image would exceed 8000 pixels",
                     lineOf(px));

  const YAML::Node dg = r.map(root, "degradations", "degradations", false);
  r.keys(dg, "degradations.", {"noise_sigma", "speckle", "blur_sigma_px", "pose_jitter_mm",
                               "pose_jitter_deg", "drop_probability", "ultrasound"});
  auto& d = s.degradations;
  if (dg && dg["ultrasound"]) {
    const YAML::Node us = r.map(dg, "ultrasound", "degradations.ultrasound", false);
    r.keys(us, "degradations.ultrasound.", {"object_echo", "grain_mm", "reflectors"});
    d.ultrasound.enabled = true;
    d.ultrasound.object_echo =
        r.number(us, "object_echo", "degradations.ultrasound.object_echo", 0.25, 0, false, 10);
    d.ultrasound.grain_mm = r.number(us, "grain_mm", "degradations.ultrasound.grain_mm", 0.3, 0, true, 1e6);
    d.ultrasound.reflectors = r.integer(us, "reflectors", "degradations.ultrasound.reflectors", 2, 0, 20);
    if (s.shape.label_split)
      throw InputError(path, "degradations.ultrasound",
                       "a two-label phantom (shape.label_split) is rendered as label images, not echoes",
                       lineOf(dg["ultrasound"]));
  }
  d.noise_sigma = r.number(dg, "noise_sigma", "degradations.noise_sigma", 0.0, 0);
  d.speckle = r.number(dg, "speckle", "degradations.speckle", 0.0, 0);
  d.blur_sigma_px = r.number(dg, "blur_sigma_px", "degradations.blur_sigma_px", 0.0, 0, false, 50);
  d.pose_jitter_mm = r.number(dg, "pose_jitter_mm", "degradations.pose_jitter_mm", 0.0, 0);
  d.pose_jitter_deg =
      r.number(dg, "pose_jitter_deg", "degradations.pose_jitter_deg", 0.0, 0, false, 45);
  d.drop_probability =
      r.number(dg, "drop_probability", "degradations.drop_probability", 0.0, 0, false, 0.99);
  if (s.shape.label_split)
    for (const char* key : {"noise_sigma", "speckle", "blur_sigma_px"})
      if (dg[key] && r.number(dg, key, std::string("degradations.") + key, 0.0) > 0)
        throw InputError(path, std::string("degradations.") + key,
                         "must be 0 for a two-label phantom (shape.label_split): its pixel values "
                         "are material labels",
                         lineOf(dg[key]));

  if (root["plus"]) s.plus = yamlBool(root["plus"], path, "plus");

  const YAML::Node cfg = r.map(root, "config", "config", false);
  YAML::Emitter out;
  out << cfg;
  s.config_yaml = cfg.size() ? out.c_str() : "{}";
  return s;
}

}  // namespace xsect

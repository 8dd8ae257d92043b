// Run configuration reader (see run_config.h). The accepted keys and their types are listed once,
// in kKnownKeys; any other key is refused before the work starts.
#include "io/run_config.h"

#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "io/closest_name.h"
#include "io/file_checks.h"
#include "io/input_error.h"
#include "io/yaml_fields.h"

namespace xsect {
namespace fs = std::filesystem;

namespace {

/// segmentation.preset: ultrasound, under the keys `s` leaves out (a length counts as given in
/// pixels or in mm). Starting values for B-mode frames in mm, so that they transfer between
/// probes and depths: the minimum-error threshold of the series, the object on the side that
/// covers less of the sector's border (a vessel, a cyst, a bone), a median of 1 mm against the
/// speckle (a few grains of a clinical probe), smoothing 0.3 mm, opening 0.75 mm, parts and holes
/// under 8 mm² removed (a 3 mm disk: dark speckle blobs reach 5 mm² on the phantoms of
/// tests/test_ultrasound_segmentation.cpp), acoustic shadows unobserved. No closing: the holes
/// under 8 mm² already fill the speckle inside a lumen, and a closing joined dark blobs near the
/// object to it through necks thinner than a voxel, which the solid then kept as separate specks
/// (9 freehand phantoms, seeds 1-3: truth topology on 3 with a 0.5 mm closing, on 7-8 without;
/// bench/ultrasound_family.py). Opening 0.75 mm, not 0.5: dark speckle joined to a lumen's edge
/// through necks under 1.5 mm made bumps of 2-3 mm and extra tunnels (the same 18 phantoms, seeds
/// 1-6: truth topology on 14 with 0.5 mm, 16 with 0.75 mm, at 0.4 mm voxels and at the automatic
/// one; Hausdorff 1.06-2.90 mm -> 0.80-2.74 mm). Not 1 mm: 16-17 of 18, but on the 200-frame
/// sweep of configs/phantoms/torus-ultrasound-plus.yaml a blob the opening cut off a lumen became
/// a 2-voxel component of its own. Structures under 1.5 mm across go with it.
/// docs/ultrasound.md says how to tune them.
void applyUltrasoundPreset(const YAML::Node& s, SegmentationParams& p) {
  const auto given = [&](const char* k) { return bool(s[k]); };
  p.method = SegmentationMethod::min_error;
  p.inside = InsideSide::automatic;
  p.shadows = ShadowRule::unobserved;
  if (!given("speckle_filter_mm")) p.speckle_filter_mm = 1.0;
  if (!given("sigma_px") && !given("sigma_mm")) p.sigma_mm = 0.3;
  if (!given("open_radius_px") && !given("open_radius_mm")) p.open_radius_mm = 0.75;
  if (!given("min_area_mm2")) p.min_area_mm2 = 8.0;
  if (!given("elevation_median_mm")) p.elevation_median_mm = 1.0;
}

const std::set<std::string> kKnownKeys = {
    "input", "input.slices", "input.csl", "input.contour", "input.plus_sequence", "input.plus_config",
    "input.reference_frame", "input.repair_contours", "input.plus_masks",
    "segmentation", "segmentation.method", "segmentation.threshold", "segmentation.sigma_px",
    "segmentation.open_radius_px", "segmentation.close_radius_px", "segmentation.min_area_mm2",
    "segmentation.preset", "segmentation.inside", "segmentation.sigma_mm", "segmentation.open_radius_mm",
    "segmentation.close_radius_mm", "segmentation.speckle_filter_mm", "segmentation.shadows",
    "segmentation.beam_apex_px", "segmentation.elevation_median_mm",
    "segmentation.simplify_mm", "segmentation.merge_labels", "conformity", "conformity.enforce",
    "conformity.mode", "conformity.max_correction_mm", "conformity.band_mm", "conformity.min_angle_deg",
    "conformity.flag_mm", "conformity.drop_flagged", "conformity.drop_unplaced", "conformity.drop_unreconciled",
    "conformity.pose_smoothing_frames",
    "conformity.pose_correction",
    "conformity.pose_sigma_mm", "conformity.pose_sigma_deg", "reconstruction",
    "reconstruction.method", "reconstruction.voxel_size_mm", "reconstruction.voxel_budget", "reconstruction.end_margin_mm",
    "reconstruction.conformal_mesh", "reconstruction.planes", "reconstruction.cell_tunnels",
    "reconstruction.topology", "reconstruction.min_feature_mm",
    "smoothing", "smoothing.method", "smoothing.exponent", "smoothing.cap_mm",
    "smoothing.adaptivity", "smoothing.keep_connectivity", "smoothing.iterations", "sampling", "sampling.reach_mm",
    "sampling.reach_interior_mm", "sampling.reach_exterior_mm", "sampling.max_angle_deg", "sampling.advice_count",
    "output", "output.dir", "output.mesh", "run", "run.max_seconds"};

/// An override `--set key=value`: the key it sets and the option as typed.
struct Override {
  std::string key, text;
};

/// The override that gave `field` (the key itself, a key below it, or a map it created), if any.
const Override* overrideOf(const std::string& field, const std::vector<Override>& overrides) {
  const auto below = [](const std::string& a, const std::string& b) {
    return a.size() > b.size() && a.compare(0, b.size(), b) == 0 && (a[b.size()] == '.' || a[b.size()] == '[');
  };
  // The last override of a key is the one in force.
  for (auto it = overrides.rbegin(); it != overrides.rend(); ++it)
    if (field == it->key || below(field, it->key) || below(it->key, field)) return &*it;
  return nullptr;
}

/// An error about `field` (file `file`, line `line`) as the user wrote it: in the file, or in the
/// --set option that gave it.
InputError keyError(const std::string& file, const std::string& field, const std::string& what, int line,
                    const std::vector<Override>& overrides) {
  if (const Override* o = overrideOf(field, overrides))
    return InputError("--set " + o->text, field == o->key ? "" : field, what);
  return InputError(file, field, what, line);
}

/// The known key an unknown `key` was most likely meant to be: a sibling spelled alike, else a key
/// of another section with the same or a like-spelled last name (`voxel_size_mm` at the top level).
std::string suggestionFor(const std::string& key) {
  const auto dot = key.rfind('.');
  const std::string prefix = dot == std::string::npos ? "" : key.substr(0, dot + 1);
  const std::string leaf = key.substr(prefix.size());
  std::vector<std::string> siblings, leaves, elsewhere;
  for (const std::string& k : kKnownKeys) {
    const auto d = k.rfind('.');
    const std::string kp = d == std::string::npos ? "" : k.substr(0, d + 1);
    if (kp == prefix) siblings.push_back(k.substr(kp.size()));
    else {
      leaves.push_back(k.substr(kp.size()));
      elsewhere.push_back(k);
    }
  }
  if (const auto s = closestName(leaf, siblings)) return prefix + *s;
  for (std::size_t i = 0; i < leaves.size(); ++i)
    if (leaves[i] == leaf) return elsewhere[i];
  if (const auto s = closestName(leaf, leaves))
    for (std::size_t i = 0; i < leaves.size(); ++i)
      if (leaves[i] == *s) return elsewhere[i];
  return "";
}

/// Every key of `n` below `prefix` that the configuration does not know, with its line.
void collectUnknown(const YAML::Node& n, const std::string& prefix, std::vector<std::pair<std::string, int>>& unknown) {
  if (!n.IsMap()) return;
  for (const auto& kv : n) {
    const std::string key = prefix.empty() ? kv.first.Scalar() : prefix + "." + kv.first.Scalar();
    if (!kKnownKeys.count(key)) {
      unknown.emplace_back(key, yamlLine(kv.first));
      continue;
    }
    collectUnknown(kv.second, key, unknown);
  }
}

/// Unknown keys are refused before any work (a typo would otherwise run at a default), each with
/// the key it was likely meant to be.
void refuseUnknownKeys(const YAML::Node& root, const std::string& file, const std::vector<Override>& overrides) {
  std::vector<std::pair<std::string, int>> unknown;
  collectUnknown(root, "", unknown);
  if (unknown.empty()) return;
  const auto describe = [](const std::string& key) { return didYouMeanText(suggestionFor(key)); };
  std::string what = "unknown key" + describe(unknown[0].first);
  for (std::size_t i = 1; i < unknown.size(); ++i)
    what += "; also unknown: '" + unknown[i].first + "'" +
            (unknown[i].second > 0 ? " (line " + std::to_string(unknown[i].second) + ")" : "") +
            describe(unknown[i].first);
  throw keyError(file, unknown[0].first, what, unknown[0].second, overrides);
}

void applyOverride(YAML::Node& root, const std::string& text, const std::string& file) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("--set", text, "expected key.path=value");
  const std::string key = text.substr(0, eq), value = text.substr(eq + 1);
  YAML::Node parsed;
  try {
    parsed = YAML::Load(value);
  } catch (const YAML::Exception& e) {
    throw InputError("--set", key, "value is not valid YAML: " + e.msg);
  }
  checkNoDuplicateKeys(value, "--set " + key);
  std::vector<std::string> parts;
  std::stringstream ss(key);
  for (std::string p; std::getline(ss, p, '.');) {
    if (p.empty()) throw InputError("--set", key, "empty component in key path");
    parts.push_back(p);
  }
  // Walk down by reassigning copies of handles (yaml-cpp nodes are references).
  std::vector<YAML::Node> chain{root};
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    YAML::Node child = chain.back()[parts[i]];
    if (child && !child.IsMap())
      throw InputError("--set", key, "'" + parts[i] + "' is not a map in " + file);
    if (!child) {
      chain.back()[parts[i]] = YAML::Node(YAML::NodeType::Map);
      child = chain.back()[parts[i]];
    }
    chain.push_back(child);
  }
  chain.back()[parts.back()] = parsed;
}

std::string resolvePath(const fs::path& base, const std::string& p) {
  fs::path q(p);
  if (q.is_relative()) q = base / q;
  return q.lexically_normal().string();
}

/// The `segmentation:` block `s` of `path` into c.segmentation (and the preset, and warnings for
/// keys given that their method does not use).
void readSegmentation(const YAML::Node& s, const std::string& path, RunConfig& c) {
  auto& p = c.segmentation;
  if (s["preset"])
    c.segmentation_preset = yamlChoice(s["preset"], path, "segmentation.preset", kSegmentationPresets, "preset");
  if (c.segmentation_preset == SegmentationPreset::ultrasound) applyUltrasoundPreset(s, p);
  if (s["method"]) {
    p.method = yamlChoice(s["method"], path, "segmentation.method", kSegmentationMethods, "method");
  }
  if (c.segmentation_preset != SegmentationPreset::none && p.method == SegmentationMethod::labels)
    throw InputError(path, "segmentation.preset",
                     "a preset sets how grey images are segmented; label images (method: labels) take none: remove "
                     "segmentation.preset",
                     yamlLine(s["preset"]));
  if (s["inside"]) p.inside = yamlChoice(s["inside"], path, "segmentation.inside", kInsideSides, "side");
  if (s["shadows"]) p.shadows = yamlChoice(s["shadows"], path, "segmentation.shadows", kShadowRules, "rule");
  if (s["beam_apex_px"]) {
    const YAML::Node a = s["beam_apex_px"];
    if (!a.IsSequence() || a.size() != 2)
      throw InputError(path, "segmentation.beam_apex_px", "expected [column, row] in pixels", yamlLine(a));
    p.beam_apex_px = Vec2(yamlNumber(a[0], path, "segmentation.beam_apex_px"),
                          yamlNumber(a[1], path, "segmentation.beam_apex_px"));
    if (!std::isfinite(p.beam_apex_px->x()) || !std::isfinite(p.beam_apex_px->y()) ||
        p.beam_apex_px->cwiseAbs().maxCoeff() > 1e7)
      throw InputError(path, "segmentation.beam_apex_px", "must be finite, within 1e7 pixels", yamlLine(a));
  }
  // A length is given in pixels or in mm, not both.
  for (const char* k : {"sigma", "open_radius", "close_radius"})
    if (s[std::string(k) + "_px"] && s[std::string(k) + "_mm"])
      throw InputError(path, std::string("segmentation.") + k + "_mm",
                       std::string("given with segmentation.") + k + "_px: keep one of the two",
                       yamlLine(s[std::string(k) + "_mm"]));
  const auto num = [&](const char* k, double lo, double* out) {
    if (!s[k]) return;
    const double v = yamlNumber(s[k], path, std::string("segmentation.") + k);
    if (v < lo)
      throw InputError(path, std::string("segmentation.") + k,
                       "must be >= " + std::to_string(lo), yamlLine(s[k]));
    *out = v;
  };
  if (s["merge_labels"]) p.merge_labels = yamlBool(s["merge_labels"], path, "segmentation.merge_labels");
  num("threshold", -1e300, &p.threshold);
  num("sigma_px", 0, &p.sigma_px);
  // Radii are whole pixels (a fraction is dropped); past a million pixels no image holds the disk
  // (the images' own limits are checked against their sizes: segmentation/setting_limits.h).
  for (const auto& [k, out] : {std::pair{"open_radius_px", &p.open_radius_px}, std::pair{"close_radius_px", &p.close_radius_px}}) {
    double r = 0;
    num(k, 0, &r);
    if (r > 1e6)
      throw InputError(path, std::string("segmentation.") + k, "a radius of " + s[k].Scalar() + " pixels is larger than any image",
                       yamlLine(s[k]));
    *out = int(r);
  }
  num("min_area_mm2", 0, &p.min_area_mm2);
  num("simplify_mm", 0, &p.simplify_mm);
  for (const auto& [k, out] : {std::pair{"sigma_mm", &p.sigma_mm}, std::pair{"open_radius_mm", &p.open_radius_mm},
                               std::pair{"close_radius_mm", &p.close_radius_mm},
                               std::pair{"speckle_filter_mm", &p.speckle_filter_mm},
                               std::pair{"elevation_median_mm", &p.elevation_median_mm}}) {
    num(k, 0, out);
    if (!std::isfinite(*out))
      throw InputError(path, std::string("segmentation.") + k, "must be finite", yamlLine(s[k]));
  }
  if (p.method == SegmentationMethod::labels) {
    for (const char* k : {"inside", "shadows", "speckle_filter_mm", "beam_apex_px", "elevation_median_mm"})
      if (s[k])
        throw InputError(path, std::string("segmentation.") + k,
                         "label images are not thresholded: segmentation.inside, shadows, speckle_filter_mm, "
                         "beam_apex_px and elevation_median_mm apply to grey images only",
                         yamlLine(s[k]));
  }
  // A threshold given with a rule that computes its own is not used: said, not silently dropped.
  if (s["threshold"] && p.method != SegmentationMethod::threshold)
    c.warnings.push_back(path + ": segmentation.threshold is not used with method " +
                         std::string(nameOf(kSegmentationMethods, p.method)) +
                         " (the series' own threshold is applied; report.json's segmentation.threshold_used)");
  if (s["beam_apex_px"] && p.shadows != ShadowRule::unobserved)
    c.warnings.push_back(path + ": segmentation.beam_apex_px is used only with shadows: unobserved");
}

/// input: exactly one source (slices, csl, contour or plus_sequence), its file, and the keys of
/// that source.
void readInput(const YAML::Node& input, const fs::path& base, const std::string& path, RunConfig& c) {
  int sources = 0;
  for (const NamedChoice<InputKind>& kind : kInputKinds) {
    const char* k = kind.name;
    if (!input[k]) continue;
    ++sources;
    c.input_kind = kind.value;
    c.input_path = resolvePath(base, yamlString(input[k], path, std::string("input.") + k));
  }
  if (sources != 1)
    throw InputError(path, "input", "exactly one of slices, csl, contour, plus_sequence is required",
                     yamlLine(input));
  if (!isRegularFile(c.input_path))
    throw InputError(path, std::string("input.") + nameOf(kInputKinds, c.input_kind), "file not found: " + c.input_path,
                     yamlLine(input[nameOf(kInputKinds, c.input_kind)]));
  if (input["repair_contours"]) {
    c.repair_contours = yamlBool(input["repair_contours"], path, "input.repair_contours");
    c.segmentation.repair_contours = c.repair_contours;
  }
  if (c.input_kind == InputKind::plus_sequence) {
    // A PLUS recording: the device set's calibration and field of view are needed to place and
    // mask its frames.
    if (!input["plus_config"])
      throw InputError(path, "input.plus_config",
                       "missing: input.plus_sequence needs the device-set XML (calibration, clip rectangle)",
                       yamlLine(input));
    c.plus_config_path = resolvePath(base, yamlString(input["plus_config"], path, "input.plus_config"));
    if (!isRegularFile(c.plus_config_path))
      throw InputError(path, "input.plus_config", "file not found: " + c.plus_config_path,
                       yamlLine(input["plus_config"]));
    if (input["reference_frame"]) {
      c.reference_frame = yamlString(input["reference_frame"], path, "input.reference_frame");
      if (c.reference_frame.empty())
        throw InputError(path, "input.reference_frame", "must name a coordinate frame", yamlLine(input["reference_frame"]));
    }
    if (input["plus_masks"]) {
      c.plus_masks_path = resolvePath(base, yamlString(input["plus_masks"], path, "input.plus_masks"));
      if (!isRegularFile(c.plus_masks_path))
        throw InputError(path, "input.plus_masks", "file not found: " + c.plus_masks_path, yamlLine(input["plus_masks"]));
    }
  } else {
    for (const char* k : {"plus_config", "reference_frame", "plus_masks"})
      if (input[k])
        throw InputError(path, std::string("input.") + k, "only for input.plus_sequence", yamlLine(input[k]));
  }
}

/// conformity: stage 3's settings.
void readConformity(const YAML::Node& s, const std::string& path, RunConfig& c) {
  RunConfig::Conformity& f = c.conformity;
  if (s["enforce"]) f.enforce = yamlBool(s["enforce"], path, "conformity.enforce");
  if (s["drop_flagged"]) f.drop_flagged = yamlBool(s["drop_flagged"], path, "conformity.drop_flagged");
  if (s["drop_unplaced"]) f.drop_unplaced = yamlBool(s["drop_unplaced"], path, "conformity.drop_unplaced");
  if (s["drop_unreconciled"])
    f.drop_unreconciled = yamlBool(s["drop_unreconciled"], path, "conformity.drop_unreconciled");
  if (s["mode"]) {
    f.mode = yamlChoice(s["mode"], path, "conformity.mode", kConsensusModes, "mode");
  }
  const auto positive = [&](const char* k, double* out) {
    if (!s[k]) return;
    const double v = yamlNumber(s[k], path, std::string("conformity.") + k);
    if (!(v > 0) || !std::isfinite(v))
      throw InputError(path, std::string("conformity.") + k, "must be a positive number of mm",
                       yamlLine(s[k]));
    *out = v;
  };
  positive("max_correction_mm", &f.max_correction_mm);
  positive("band_mm", &f.band_mm);
  positive("flag_mm", &f.flag_mm);
  if (s["pose_correction"])
    f.pose_correction = yamlChoice(s["pose_correction"], path, "conformity.pose_correction",
                                   kPoseCorrectionKinds, "pose correction");
  for (const auto& [k, out] : {std::pair{"pose_sigma_mm", &f.pose_sigma_mm}, std::pair{"pose_sigma_deg", &f.pose_sigma_deg}}) {
    const YAML::Node v = s[k];
    if (!v || (v.IsScalar() && v.Scalar() == "auto")) continue;
    const double x = yamlNumber(v, path, std::string("conformity.") + k);
    if (!(x > 0) || !std::isfinite(x))
      throw InputError(path, std::string("conformity.") + k, "must be a positive number or 'auto'", yamlLine(v));
    *out = x;
  }
  if (const YAML::Node n = s["pose_smoothing_frames"]) {
    f.pose_smoothing_frames = yamlInteger(n, path, "conformity.pose_smoothing_frames", 0, 1000);
    if (f.pose_smoothing_frames > 0 && c.input_kind != InputKind::slices && c.input_kind != InputKind::plus_sequence)
      throw InputError(path, "conformity.pose_smoothing_frames",
                       std::string("smooths a tracked sweep's poses: only for input.slices, not input.") + nameOf(kInputKinds, c.input_kind),
                       yamlLine(n));
  }
  if (s["min_angle_deg"]) {
    f.min_angle_deg = yamlNumber(s["min_angle_deg"], path, "conformity.min_angle_deg");
    if (!(f.min_angle_deg >= 0 && f.min_angle_deg < 90))
      throw InputError(path, "conformity.min_angle_deg", "must lie in [0, 90) degrees",
                       yamlLine(s["min_angle_deg"]));
  }
}

/// reconstruction.topology: free | simplest | [b0, b1, b2]; reconstruction.min_feature_mm (simplest).
void readTopologyGoal(const YAML::Node& s, const std::string& path, RunConfig& c) {
  TopologyGoal& t = c.topology;
  if (const YAML::Node n = s["topology"]) {
    if (n.IsSequence()) {
      if (n.size() != 3)
        throw InputError(path, "reconstruction.topology",
                         "a target is three Betti numbers [b0, b1, b2] (components, tunnels, cavities)", yamlLine(n));
      for (std::size_t i = 0; i < 3; ++i)
        t.target[i] = yamlInteger(n[i], path, "reconstruction.topology[" + std::to_string(i) + "]", i == 0 ? 1 : 0,
                                  100000);
      t.mode = TopologyMode::target;
    } else {
      t.mode = yamlChoice(n, path, "reconstruction.topology", kTopologyModes,
                          "topology (or a target [b0, b1, b2])");
    }
  }
  if (const YAML::Node m = s["min_feature_mm"]) {
    t.min_feature_mm = yamlNumber(m, path, "reconstruction.min_feature_mm");
    if (!(t.min_feature_mm >= 0) || !std::isfinite(t.min_feature_mm))
      throw InputError(path, "reconstruction.min_feature_mm", "must be a size in mm, 0 or more", yamlLine(m));
    if (t.mode != TopologyMode::simplest)
      throw InputError(path, "reconstruction.min_feature_mm",
                       "keeps the joins wider than it when reconstruction.topology is simplest; set that too",
                       yamlLine(m));
  }
  if (t.mode == TopologyMode::free) return;
  const YAML::Node at = s["topology"];
  if (c.reconstruction_method == ReconstructionMethod::delaunay)
    throw InputError(path, "reconstruction.topology",
                     "is available for methods 1 (nearest_plane) and 2 (section_voronoi); method 3 (delaunay) has "
                     "reconstruction.cell_tunnels for the tunnels inside a cell",
                     yamlLine(at));
}

/// reconstruction: the method, the voxel size, the grid's margins, the planes' extent.
void readReconstruction(const YAML::Node& s, const std::string& path, RunConfig& c) {
  if (s["method"]) {
    c.reconstruction_method =
        yamlChoice(s["method"], path, "reconstruction.method", kReconstructionMethods, "method");
  }
  if (const YAML::Node v = s["voxel_size_mm"]) {
    if (!(v.IsScalar() && v.Scalar() == "auto")) {
      c.voxel_size_mm = yamlNumber(v, path, "reconstruction.voxel_size_mm");
      if (!(c.voxel_size_mm > 0) || !std::isfinite(c.voxel_size_mm))
        throw InputError(path, "reconstruction.voxel_size_mm", "must be a positive size in mm or 'auto'",
                         yamlLine(v));
      c.voxel_size_auto = false;
    }
  }
  if (const YAML::Node n = s["voxel_budget"])
    c.voxel_budget = yamlInteger(n, path, "reconstruction.voxel_budget", 1000, 2000000000);
  if (s["conformal_mesh"])
    c.conformal_mesh = yamlBool(s["conformal_mesh"], path, "reconstruction.conformal_mesh");
  if (s["cell_tunnels"])
    c.cell_tunnels = yamlChoice(s["cell_tunnels"], path, "reconstruction.cell_tunnels", kCellTunnels, "cell tunnels choice");
  readTopologyGoal(s, path, c);
  if (s["planes"]) {
    c.planes = yamlChoice(s["planes"], path, "reconstruction.planes", kPlaneExtents, "plane extent");
    c.planes_default = false;
    if (c.planes == PlaneExtent::observed && c.reconstruction_method == ReconstructionMethod::delaunay)
      throw InputError(path, "reconstruction.planes",
                       "observed pieces are available for methods 1 (nearest_plane) and 2 (section_voronoi); method 3 "
                       "(delaunay) runs on whole planes",
                       yamlLine(s["planes"]));
  }
  if (const YAML::Node m = s["end_margin_mm"]) {
    if (!(m.IsScalar() && m.Scalar() == "auto")) {
      const double v = yamlNumber(m, path, "reconstruction.end_margin_mm");
      if (v <= 0)
        throw InputError(path, "reconstruction.end_margin_mm", "must be positive or 'auto'",
                         yamlLine(m));
      c.end_margin_mm = v;
    }
  }
}

/// smoothing: the method and its parameters.
void readSmoothing(const YAML::Node& s, const std::string& path, RunConfig& c) {
  if (s["method"]) {
    c.smoothing_method = yamlChoice(s["method"], path, "smoothing.method", kSmoothingMethods, "method");
  }
  if (s["exponent"]) {
    const YAML::Node e = s["exponent"];
    if (e.IsScalar() && (e.Scalar() == "inf" || e.Scalar() == ".inf"))
      c.smoothing_exponent = std::numeric_limits<double>::infinity();
    else
      c.smoothing_exponent = yamlNumber(e, path, "smoothing.exponent");
    if (!(c.smoothing_exponent > 0))
      throw InputError(path, "smoothing.exponent", "must be positive", yamlLine(e));
  }
  if (const YAML::Node m = s["cap_mm"]) {
    if (!(m.IsScalar() && m.Scalar() == "auto")) {
      const double v = yamlNumber(m, path, "smoothing.cap_mm");
      if (!(v > 0) || !std::isfinite(v))
        throw InputError(path, "smoothing.cap_mm", "must be positive or 'auto'", yamlLine(m));
      c.smoothing_cap_mm = v;
    }
  }
  if (const YAML::Node a = s["adaptivity"]) {
    c.smoothing_adaptivity = yamlNumber(a, path, "smoothing.adaptivity");
    if (!(c.smoothing_adaptivity >= 0 && c.smoothing_adaptivity <= 1))
      throw InputError(path, "smoothing.adaptivity", "must lie in [0, 1]", yamlLine(a));
  }
  if (s["keep_connectivity"])
    c.smoothing_keep_connectivity =
        yamlBool(s["keep_connectivity"], path, "smoothing.keep_connectivity");
  if (const YAML::Node n = s["iterations"]) {
    c.smoothing_iterations = yamlInteger(n, path, "smoothing.iterations", 0, 1000);
  }
}

/// sampling: what is known of the object (reach, angle) and how much advice to give.
void readSampling(const YAML::Node& s, const std::string& path, RunConfig& c) {
  const auto length = [&](const char* key, std::optional<double>* to) {
    if (const YAML::Node v = s[key]) {
      const std::string name = std::string("sampling.") + key;
      const double x = yamlNumber(v, path, name);
      if (!(x > 0) || !std::isfinite(x)) throw InputError(path, name, "must be a positive length", yamlLine(v));
      *to = x;
    }
  };
  length("reach_mm", &c.sampling.reach_mm);
  length("reach_interior_mm", &c.sampling.reach_interior_mm);
  length("reach_exterior_mm", &c.sampling.reach_exterior_mm);
  if (const YAML::Node a = s["max_angle_deg"]) {
    const double x = yamlNumber(a, path, "sampling.max_angle_deg");
    if (!(x >= 0 && x < 90)) throw InputError(path, "sampling.max_angle_deg", "must lie in [0, 90) degrees", yamlLine(a));
    c.sampling.max_angle_deg = x;
  }
  if (const YAML::Node n = s["advice_count"])
    // Each advised slice re-measures the cells it splits (5-30 ms on the bench's scenes): a
    // thousand is more slices than any acquisition adds, and keeps the advice within a minute.
    c.sampling.advice_count = int(yamlInteger(n, path, "sampling.advice_count", 0, 1000));
}

/// run: the time budget.
void readRun(const YAML::Node& s, const std::string& path, RunConfig& c) {
  if (const YAML::Node v = s["max_seconds"]) {
    c.max_seconds = yamlNumber(v, path, "run.max_seconds");
    if (!(c.max_seconds > 0)) throw InputError(path, "run.max_seconds", "must be a positive number of seconds", yamlLine(v));
  }
}

/// output: the folder and the mesh formats.
void readOutput(const YAML::Node& s, const fs::path& base, const std::string& path, RunConfig& c) {
  if (s["dir"]) c.output_dir = resolvePath(base, yamlString(s["dir"], path, "output.dir"));
  if (const YAML::Node m = s["mesh"]) {
    c.mesh_formats.clear();
    const auto add = [&](const YAML::Node& f) {
      const std::string v = yamlString(f, path, "output.mesh");
      if (v != "ply" && v != "stl" && v != "obj")
        throw InputError(path, "output.mesh", "unknown mesh format '" + v + "' (ply | stl | obj)",
                         yamlLine(f));
      c.mesh_formats.push_back(v);
    };
    if (m.IsSequence())
      for (const auto& f : m) add(f);
    else
      add(m);
  }
}

/// The keys of `root` into c (its sections in the order they depend on each other).
void readKnownKeys(const YAML::Node& root, const std::string& path, RunConfig& c) {
  const fs::path base = fs::path(c.path).parent_path();
  const auto section = [&](const char* name) -> YAML::Node {
    YAML::Node n = root[name];
    if (n && !n.IsMap()) throw InputError(path, name, "must be a map", yamlLine(n));
    return n;
  };

  const YAML::Node input = section("input");
  if (c.sections_in_memory) {
    // Sections handed over in memory (the Python module's reconstruct): contours as a contour
    // file's (input_kind csl), masks as images (slices); set by the caller.
    if (input) throw InputError(path, "input", "not used: the sections are given in memory", yamlLine(input));
    c.input_path.clear();
  } else {
    if (!input) throw InputError(path, "input", "missing (input.slices, input.csl, ...)");
    readInput(input, base, path, c);
  }
  if (const YAML::Node s = section("segmentation")) readSegmentation(s, path, c);
  if (const YAML::Node s = section("conformity")) readConformity(s, path, c);
  if (const YAML::Node s = section("reconstruction")) readReconstruction(s, path, c);
  if (const YAML::Node s = section("smoothing")) readSmoothing(s, path, c);
  if (c.topology.mode != TopologyMode::free && c.smoothing_method != SmoothingMethod::none)
    throw InputError(path, "reconstruction.topology",
                     "is not yet available with smoothing (the smooth surface is not held to the chosen "
                     "topology): use smoothing.method: none, or reconstruction.topology: free",
                     yamlLine(root["reconstruction"]["topology"]));
  if (const YAML::Node s = section("sampling")) readSampling(s, path, c);
  if (const YAML::Node s = section("run")) readRun(s, path, c);
  c.output_dir = resolvePath(base, "out");
  if (const YAML::Node s = section("output")) readOutput(s, base, path, c);
  // Observed pieces by default where a slice is an image (its rectangle and field of view say where
  // it was seen); contour files give all of O ∩ P on each plane. Method 3 runs on whole planes.
  if (c.planes_default)
    c.planes = c.reconstruction_method != ReconstructionMethod::delaunay &&
                       (c.input_kind == InputKind::slices || c.input_kind == InputKind::plus_sequence)
                   ? PlaneExtent::observed
                   : PlaneExtent::whole;
}

}  // namespace

const std::set<std::string>& runConfigKeys() { return kKnownKeys; }

namespace {

RunConfig configOf(YAML::Node root, const std::string& path, const std::vector<std::string>& overrides,
                   std::optional<InputKind> sections_given_as) {
  RunConfig c;
  c.path = fs::absolute(path).lexically_normal().string();
  c.sections_in_memory = sections_given_as.has_value();
  if (sections_given_as) c.input_kind = *sections_given_as;
  if (!root.IsMap()) throw InputError(path, "", "top level must be a map");
  std::vector<Override> given;
  for (const auto& o : overrides) {
    applyOverride(root, o, path);
    given.push_back({o.substr(0, o.find('=')), o});
  }
  refuseUnknownKeys(root, path, given);
  try {
    readKnownKeys(root, path, c);
  } catch (const InputError& e) {
    if (e.file() != path) throw;
    throw keyError(path, e.field(), e.reason(), e.line(), given);
  }
  YAML::Emitter em;
  em << root;
  c.resolved_yaml = em.c_str();
  return c;
}

}  // namespace

RunConfig readRunConfig(const std::string& path, const std::vector<std::string>& overrides) {
  if (!isRegularFile(path)) throw InputError(path, "", "configuration file not found");
  return configOf(loadYamlFile(path), path, overrides, std::nullopt);
}

RunConfig readRunConfigText(const std::string& text, const std::string& path, const std::vector<std::string>& overrides,
                            std::optional<InputKind> sections_given_as) {
  return configOf(loadYamlText(text, path), path, overrides, sections_given_as);
}


}  // namespace xsect

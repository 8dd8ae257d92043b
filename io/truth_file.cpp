// truth.yaml writer and validating reader (see truth_file.h). Format:
//   shape:
//     kind: torus
//     params: {major_radius: 12, minor_radius: 4}     # mm / degrees, per kind (phantom_shape.cpp)
//     centre: [0, 0, 0]                               # mm, world position of the shape origin
//     rotation: [[1, 0, 0], [0, 1, 0], [0, 0, 1]]     # rows of R, world = centre + R * shape
//     tubes: [{a: [x, y, z], b: [x, y, z], radius: r}] # vessel_tree only, shape frame, mm
//     label_split: {point: [0, 0, 0], normal: [1, 0, 0]}  # two-label phantoms only, shape frame
//   betti: [1, 1, 0]                                  # the whole solid (all materials)
//   labels: {1: {betti: [1, 0, 0]}, 2: {betti: [1, 0, 0]}}  # two-label phantoms only
//   reach_mm: 4                                       # min(reach_interior_mm, reach_exterior_mm)
//   reach_interior_mm: 4                              # lower bounds, mm (.inf: no medial axis on
//   reach_exterior_mm: 8                              #   that side); optional when reading
//   exact_distance: true
#include "io/truth_file.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include "io/input_error.h"
#include "io/text_file.h"
#include "io/yaml_fields.h"
#include "io/yaml_number.h"

namespace xsect {
namespace {

int lineOf(const YAML::Node& n) { return n ? yamlLine(n) : -1; }

void emitVector(YAML::Emitter& out, const double* v, int n) {
  out << YAML::Flow << YAML::BeginSeq;
  for (int i = 0; i < n; ++i) out << yamlNumberText(v[i]);
  out << YAML::EndSeq;
}

YAML::Node required(const YAML::Node& parent, const std::string& key, const std::string& file,
                    const std::string& path) {
  const YAML::Node n = parent[key];
  if (!n) throw InputError(file, path, "missing", lineOf(parent));
  return n;
}

Vec3 readVec3(const YAML::Node& n, const std::string& file, const std::string& key) {
  if (!n.IsSequence() || n.size() != 3)
    throw InputError(file, key, "must be a list of 3 numbers", lineOf(n));
  return Vec3(yamlNumber(n[0], file, key + "[0]"), yamlNumber(n[1], file, key + "[1]"),
              yamlNumber(n[2], file, key + "[2]"));
}

/// A reach value: a number >= 0 or .inf.
double readReach(const YAML::Node& n, const std::string& file, const std::string& key) {
  if (n.IsScalar() && (n.Scalar() == ".inf" || n.Scalar() == ".Inf" || n.Scalar() == ".INF"))
    return std::numeric_limits<double>::infinity();
  const double v = yamlNumber(n, file, key);
  if (!(v >= 0)) throw InputError(file, key, "must be >= 0 (or .inf)", lineOf(n));
  return v;
}

Betti readBetti(const YAML::Node& betti, const std::string& file, const std::string& key) {
  if (!betti.IsSequence() || betti.size() != 3)
    throw InputError(file, key, "must be a list of 3 integers", lineOf(betti));
  Betti b;
  for (int i = 0; i < 3; ++i) {
    const std::string k = key + "[" + std::to_string(i) + "]";
    const double v = yamlNumber(betti[i], file, k);
    if (v < 0 || v != std::floor(v) || v > 1e9)
      throw InputError(file, k, "must be a non-negative integer", lineOf(betti[i]));
    b[i] = int(v);
  }
  return b;
}

void emitBetti(YAML::Emitter& out, const Betti& b) {
  out << YAML::Flow << YAML::BeginSeq << b[0] << b[1] << b[2] << YAML::EndSeq;
}

}  // namespace

void writeTruthFile(const std::string& path, const PhantomShape& shape) {
  YAML::Emitter out;
  out << YAML::BeginMap << YAML::Key << "shape" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "kind" << YAML::Value << nameOf(kShapeKinds, shape.kind);
  out << YAML::Key << "params" << YAML::Value << YAML::BeginMap;
  for (const auto& [k, v] : shape.params) out << YAML::Key << k << YAML::Value << yamlNumberText(v);
  out << YAML::EndMap;
  out << YAML::Key << "centre" << YAML::Value;
  emitVector(out, shape.centre.data(), 3);
  out << YAML::Key << "rotation" << YAML::Value << YAML::BeginSeq;
  for (int r = 0; r < 3; ++r) {
    const Vec3 row = shape.rotation.row(r).transpose();
    emitVector(out, row.data(), 3);
  }
  out << YAML::EndSeq;
  if (!shape.tubes.empty()) {
    out << YAML::Key << "tubes" << YAML::Value << YAML::BeginSeq;
    for (const auto& t : shape.tubes) {
      out << YAML::Flow << YAML::BeginMap;
      out << YAML::Key << "a" << YAML::Value;
      emitVector(out, t.a.data(), 3);
      out << YAML::Key << "b" << YAML::Value;
      emitVector(out, t.b.data(), 3);
      out << YAML::Key << "radius" << YAML::Value << yamlNumberText(t.radius);
      out << YAML::EndMap;
    }
    out << YAML::EndSeq;
  }
  if (shape.label_split) {
    out << YAML::Key << "label_split" << YAML::Value << YAML::Flow << YAML::BeginMap;
    out << YAML::Key << "point" << YAML::Value;
    emitVector(out, shape.label_split->point.data(), 3);
    out << YAML::Key << "normal" << YAML::Value;
    emitVector(out, shape.label_split->normal.data(), 3);
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
  out << YAML::Key << "betti" << YAML::Value;
  emitBetti(out, bettiNumbers(shape));
  if (shape.label_split) {
    out << YAML::Key << "labels" << YAML::Value << YAML::BeginMap;
    for (const auto& [label, b] : labelBettiNumbers(shape)) {
      out << YAML::Key << label << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
          << "betti" << YAML::Value;
      emitBetti(out, b);
      out << YAML::EndMap;
    }
    out << YAML::EndMap;
  }
  out << YAML::Key << "reach_mm" << YAML::Value << yamlNumberText(reach(shape));
  out << YAML::Key << "reach_interior_mm" << YAML::Value << yamlNumberText(reachInterior(shape));
  out << YAML::Key << "reach_exterior_mm" << YAML::Value << yamlNumberText(reachExterior(shape));
  out << YAML::Key << "exact_distance" << YAML::Value << hasExactDistance(shape);
  out << YAML::EndMap;
  writeTextFile(path, std::string(out.c_str()) + "\n");
}

PhantomShape readTruthFile(const std::string& path) {
  const YAML::Node root = loadYamlFile(path);
  if (!root.IsMap()) throw InputError(path, "", "top level must be a map with key 'shape'");
  const YAML::Node sh = required(root, "shape", path, "shape");
  if (!sh.IsMap()) throw InputError(path, "shape", "must be a map", lineOf(sh));
  PhantomShape s;
  s.kind = yamlChoice(required(sh, "kind", path, "shape.kind"), path, "shape.kind", kShapeKinds, "shape kind");
  const auto spec = phantomShapeParams(s.kind);
  const YAML::Node params = required(sh, "params", path, "shape.params");
  if (!params.IsMap()) throw InputError(path, "shape.params", "must be a map", lineOf(params));
  for (const auto& kv : params) {
    const std::string k = kv.first.Scalar();
    if (!spec.count(k) && !(s.kind == ShapeKind::vessel_tree && k == "nominal_reach"))
      throw InputError(path, "shape.params." + k, "unknown parameter for " + std::string(nameOf(kShapeKinds, s.kind)),
                       lineOf(kv.first));
    s.params[k] = yamlNumber(kv.second, path, "shape.params." + k);
  }
  s.centre = readVec3(required(sh, "centre", path, "shape.centre"), path, "shape.centre");
  const YAML::Node rot = required(sh, "rotation", path, "shape.rotation");
  if (!rot.IsSequence() || rot.size() != 3)
    throw InputError(path, "shape.rotation", "must be 3 rows of 3 numbers", lineOf(rot));
  for (int r = 0; r < 3; ++r)
    s.rotation.row(r) =
        readVec3(rot[r], path, "shape.rotation[" + std::to_string(r) + "]").transpose();
  if ((s.rotation * s.rotation.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() >
          1e-6 ||
      s.rotation.determinant() < 0)
    throw InputError(path, "shape.rotation", "must be a rotation (orthonormal, determinant +1)",
                     lineOf(rot));
  if (const auto problem = checkPhantomShape(s))
    throw InputError(path, "shape.params." + problem->param, problem->message,
                     lineOf(params[problem->param]));
  if (const YAML::Node tubes = sh["tubes"]) {
    if (!tubes.IsSequence()) throw InputError(path, "shape.tubes", "must be a list", lineOf(tubes));
    for (std::size_t i = 0; i < tubes.size(); ++i) {
      const std::string key = "shape.tubes[" + std::to_string(i) + "]";
      const YAML::Node t = tubes[i];
      if (!t.IsMap()) throw InputError(path, key, "must be a map {a, b, radius}", lineOf(t));
      PhantomShape::Tube tube;
      tube.a = readVec3(required(t, "a", path, key + ".a"), path, key + ".a");
      tube.b = readVec3(required(t, "b", path, key + ".b"), path, key + ".b");
      tube.radius = yamlNumber(required(t, "radius", path, key + ".radius"), path, key + ".radius");
      if (!(tube.radius > 0)) throw InputError(path, key + ".radius", "must be positive", lineOf(t));
      s.tubes.push_back(tube);
    }
  }
  if (const YAML::Node ls = sh["label_split"]) {
    if (!ls.IsMap())
      throw InputError(path, "shape.label_split", "must be a map {point, normal}", lineOf(ls));
    for (const auto& kv : ls)
      if (kv.first.Scalar() != "point" && kv.first.Scalar() != "normal")
        throw InputError(path, "shape.label_split." + kv.first.Scalar(),
                         "unknown key (expected point, normal)", lineOf(kv.first));
    PhantomShape::LabelSplit split;
    if (ls["point"]) split.point = readVec3(ls["point"], path, "shape.label_split.point");
    const Vec3 n = readVec3(required(ls, "normal", path, "shape.label_split.normal"), path,
                            "shape.label_split.normal");
    if (!(n.norm() > 1e-12))
      throw InputError(path, "shape.label_split.normal", "must be a non-zero vector",
                       lineOf(ls["normal"]));
    split.normal = n.normalized();
    s.label_split = split;
  }
  readBetti(required(root, "betti", path, "betti"), path, "betti");
  if (const YAML::Node labels = root["labels"]) {
    if (!s.label_split)
      throw InputError(path, "labels", "only for a two-label phantom (shape.label_split)",
                       lineOf(labels));
    if (!labels.IsMap())
      throw InputError(path, "labels", "must be a map {label: {betti}}", lineOf(labels));
    std::map<int, Betti> lb;
    for (const auto& kv : labels) {
      const std::string key = "labels." + kv.first.Scalar();
      const double l = yamlNumber(kv.first, path, key);
      if (l != 1 && l != 2) throw InputError(path, key, "the labels are 1 and 2", lineOf(kv.first));
      if (!kv.second.IsMap())
        throw InputError(path, key, "must be a map {betti: [...]}", lineOf(kv.second));
      lb[int(l)] =
          readBetti(required(kv.second, "betti", path, key + ".betti"), path, key + ".betti");
    }
    s.label_betti = lb;
  }
  if (!(yamlNumber(required(root, "reach_mm", path, "reach_mm"), path, "reach_mm") >= 0))
    throw InputError(path, "reach_mm", "must be >= 0", lineOf(root["reach_mm"]));
  if (const YAML::Node n = root["reach_interior_mm"])
    s.reach_interior_mm = readReach(n, path, "reach_interior_mm");
  if (const YAML::Node n = root["reach_exterior_mm"])
    s.reach_exterior_mm = readReach(n, path, "reach_exterior_mm");
  yamlBool(required(root, "exact_distance", path, "exact_distance"), path, "exact_distance");
  if (s.kind == ShapeKind::vessel_tree) {
    // Files written before blending existed describe the plain union of the capsules.
    if (!s.params.count("blend_mm")) s.params["blend_mm"] = 0.0;
    try {
      s = completePhantomShape(std::move(s));  // junctions (tubes given: no regrowth), reach
    } catch (const std::runtime_error& e) {
      throw InputError(path, "shape.params", e.what(), lineOf(params));
    }
  } else {
    for (const auto& [key, def] : spec)
      if (def && !s.params.count(key)) s.params[key] = *def;
  }
  return s;
}

}  // namespace xsect

// truth.yaml writer and validating reader (see truth_file.h). Format:
//   shape:
//     kind: torus
//     params: {major_radius: 12, minor_radius: 4}     # mm / degrees, per kind (phantom_shape.cpp)
//     centre: [0, 0, 0]                               # mm, world position of the shape origin
//     rotation: [[1, 0, 0], [0, 1, 0], [0, 0, 1]]     # rows of R, world = centre + R * shape
//     tubes: [{a: [x, y, z], b: [x, y, z], radius: r}] # vessel_tree only, shape frame, mm
//   betti: [1, 1, 0]
//   reach_mm: 4
//   exact_distance: true
#include "io/truth_file.h"

#include <yaml-cpp/yaml.h>

#include <fstream>
#include <set>
#include <sstream>

#include "io/input_error.h"
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

}  // namespace

void writeTruthFile(const std::string& path, const PhantomShape& shape) {
  YAML::Emitter out;
  out << YAML::BeginMap << YAML::Key << "shape" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "kind" << YAML::Value << shape.kind;
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
  out << YAML::EndMap;
  const Betti b = bettiNumbers(shape);
  out << YAML::Key << "betti" << YAML::Value << YAML::Flow << YAML::BeginSeq << b[0] << b[1]
      << b[2] << YAML::EndSeq;
  out << YAML::Key << "reach_mm" << YAML::Value << yamlNumberText(reach(shape));
  out << YAML::Key << "exact_distance" << YAML::Value << hasExactDistance(shape);
  out << YAML::EndMap;
  std::ofstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error("cannot write " + path);
  f << out.c_str() << "\n";
  if (!f) throw std::runtime_error("write failed: " + path);
}

PhantomShape readTruthFile(const std::string& path) {
  const YAML::Node root = loadYamlFile(path);
  if (!root.IsMap()) throw InputError(path, "", "top level must be a map with key 'shape'");
  const YAML::Node sh = required(root, "shape", path, "shape");
  if (!sh.IsMap()) throw InputError(path, "shape", "must be a map", lineOf(sh));
  PhantomShape s;
  s.kind = yamlString(required(sh, "kind", path, "shape.kind"), path, "shape.kind");
  const auto spec = phantomShapeParams(s.kind);
  if (spec.empty()) {
    const auto problem = checkPhantomShape(s);
    throw InputError(path, "shape.kind", problem ? problem->message : "unknown kind",
                     lineOf(sh["kind"]));
  }
  const YAML::Node params = required(sh, "params", path, "shape.params");
  if (!params.IsMap()) throw InputError(path, "shape.params", "must be a map", lineOf(params));
  for (const auto& kv : params) {
    const std::string k = kv.first.Scalar();
    if (!spec.count(k) && !(s.kind == "vessel_tree" && k == "nominal_reach"))
      throw InputError(path, "shape.params." + k, "unknown parameter for " + s.kind,
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
  if (s.kind == "vessel_tree" && s.tubes.empty()) {
    try {
      s = completePhantomShape(std::move(s));
    } catch (const std::runtime_error& e) {
      throw InputError(path, "shape.params", e.what(), lineOf(params));
    }
  } else if (s.kind != "vessel_tree") {
    for (const auto& [key, def] : spec)
      if (def && !s.params.count(key)) s.params[key] = *def;
  }
  const YAML::Node betti = required(root, "betti", path, "betti");
  if (!betti.IsSequence() || betti.size() != 3)
    throw InputError(path, "betti", "must be a list of 3 integers", lineOf(betti));
  for (int i = 0; i < 3; ++i) {
    const double v = yamlNumber(betti[i], path, "betti[" + std::to_string(i) + "]");
    if (v < 0 || v != std::floor(v))
      throw InputError(path, "betti[" + std::to_string(i) + "]", "must be a non-negative integer",
                       lineOf(betti[i]));
  }
  if (!(yamlNumber(required(root, "reach_mm", path, "reach_mm"), path, "reach_mm") >= 0))
    throw InputError(path, "reach_mm", "must be >= 0", lineOf(root["reach_mm"]));
  yamlBool(required(root, "exact_distance", path, "exact_distance"), path, "exact_distance");
  return s;
}

}  // namespace xsect

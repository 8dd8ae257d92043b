// `xsect phantom SPEC.yaml --out DIR` (docs/commands.md): renders a synthetic
// phantom into DIR, written through StagedOutput so that DIR appears complete or not at all:
//   images/NNN.png     8-bit slice images (NNN = frame index; dropped frames are not written);
//                      two-label phantoms (shape.label_split): label images, pixel = 0, 1 or 2
//   images/fov.png     the shared sector field of view (freehand with sector: true)
//   slices.yaml        the slices with their RECORDED poses (true pose + tracking jitter)
//   true_poses.yaml    the same slices with their true poses (what the images were rendered from)
//   truth.yaml         the analytic shape, its Betti numbers (and each material's) and reach
//   config.yaml        a run configuration for `xsect run`, merged with the spec's `config:` map
// and with `plus: true` in the spec, the same slices as a PLUS recording (io/meta_image_writer.h):
//   sequence.igs.mha   the written frames in order (zlib), per frame ProbeToTrackerTransform (the
//                      recorded pose without its pixel scaling), ReferenceToTrackerTransform
//                      (identity), their statuses, ImageStatus (all OK) and Timestamp
//   deviceset.xml      ImageToProbe = diag(pixel_mm, pixel_mm, pixel_mm, 1), the sector as PLUS fan
//   config_plus.yaml   config.yaml with input: {plus_sequence: ..., plus_config: ...}
#include <yaml-cpp/yaml.h>

#include <atomic>
#include <functional>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <tbb/parallel_for.h>

#include "io/input_error.h"
#include "io/meta_image_writer.h"
#include "io/text_file.h"
#include "io/phantom_spec.h"
#include "io/slices_file.h"
#include "io/staged_output.h"
#include "io/truth_file.h"
#include "io/yaml_number.h"
#include "pipeline/commands.h"
#include "pipeline/output_manifest.h"
#include "pipeline/phantom_render.h"

namespace xsect {
namespace {

namespace fs = std::filesystem;

/// Deep merge of `over` into `base` (maps merge key by key; anything else replaces). Keys with
/// dots ("reconstruction.voxel_size_mm") address nested maps. (yaml-cpp nodes are handles:
/// assigning one Node variable to another rebinds the data, so the walk recurses instead.)
void mergeValue(YAML::Node base, const std::string& key, const YAML::Node& value,
                const std::string& file, const std::string& fullKey);

void mergeInto(YAML::Node base, const YAML::Node& over, const std::string& file,
               const std::string& prefix) {
  for (const auto& kv : over) {
    const std::string key = kv.first.Scalar();
    mergeValue(base, key, kv.second, file, prefix + key);
  }
}

void mergeValue(YAML::Node base, const std::string& key, const YAML::Node& value,
                const std::string& file, const std::string& fullKey) {
  const auto dot = key.find('.');
  const std::string head = key.substr(0, dot);
  if (head.empty()) throw InputError(file, fullKey, "empty component in key path");
  if (dot != std::string::npos) {
    if (!base[head] || !base[head].IsMap()) base[head] = YAML::Node(YAML::NodeType::Map);
    mergeValue(base[head], key.substr(dot + 1), value, file, fullKey);
  } else if (value.IsMap() && base[head] && base[head].IsMap()) {
    mergeInto(base[head], value, file, fullKey + ".");
  } else {
    base[head] = YAML::Clone(value);
  }
}

/// The run configuration; with `plus`, reading the PLUS recording instead of slices.yaml.
std::string configYaml(const PhantomSpec& spec, const SlicePlan& plan, bool plus = false) {
  YAML::Node c(YAML::NodeType::Map);
  c["input"]["slices"] = "slices.yaml";
  const auto& d = spec.degradations;
  if (spec.shape.label_split) {
    // Label images are not anti-aliased: traced as they are, each material's contour is a pixel
    // staircase, and method 3 joins the steps of neighbouring planes into tunnels (the split torus:
    // Betti (1, 5, 0) against (1, 1, 0); with 1.5 px, the truth's, and each half (1, 0, 0)).
    c["segmentation"]["method"] = "labels";
    c["segmentation"]["sigma_px"] = "1.5";
  } else if (d.ultrasound.enabled) {
    c["segmentation"]["preset"] = "ultrasound";  // B-mode frames: its starting values
    if (plan.sector) {  // the beams' origin (a PLUS recording's device set says it as the fan's)
      YAML::Node apex(YAML::NodeType::Sequence);
      apex.SetStyle(YAML::EmitterStyle::Flow);
      apex.push_back(plan.sector->apex_i);
      apex.push_back(plan.sector->apex_j);
      c["segmentation"]["beam_apex_px"] = apex;
    }
  } else if (d.noise_sigma > 0 || d.speckle > 0) {
    c["segmentation"]["method"] = "otsu";
    c["segmentation"]["sigma_px"] = "1.5";
  } else {
    c["segmentation"]["method"] = "threshold";
    c["segmentation"]["threshold"] = "128";
  }
  c["conformity"]["enforce"] = false;
  c["reconstruction"]["method"] = "nearest_plane";
  c["reconstruction"]["voxel_size_mm"] = "auto";  // chosen from the sections (automatic_voxel_size.h)
  c["reconstruction"]["end_margin_mm"] = "auto";
  c["smoothing"]["method"] = "none";
  c["output"]["dir"] = "out";
  YAML::Node mesh(YAML::NodeType::Sequence);
  mesh.push_back("ply");
  c["output"]["mesh"] = mesh;
  mergeInto(c, YAML::Load(spec.config_yaml), spec.path, "config.");
  if (plus) {
    YAML::Node in(YAML::NodeType::Map);
    in["plus_sequence"] = "sequence.igs.mha";
    in["plus_config"] = "deviceset.xml";
    c["input"] = in;
  }
  YAML::Emitter out;
  out << c;
  return std::string(out.c_str()) + "\n";
}


/// The pattern's poses, plus the spec's extra planes imaged around the projection of the bounds'
/// centre, as the patterns do.
SlicePlan phantomPlan(const PhantomSpec& spec) {
  Vec3 bmin, bmax;
  bounds(spec.shape, &bmin, &bmax);
  SlicePlan plan = planSlices(spec.pattern, spec.image, bmin, bmax, spec.seed);
  for (const PhantomPlane& p : spec.extra_planes) {
    Vec3 u, v;
    planeFrame(p.normal, &u, &v);
    const Vec3 n = u.cross(v), c = p.image_centre ? *p.image_centre : Vec3(0.5 * (bmin + bmax));
    plan.poses.push_back(
        centredPose(c - (c - p.point).dot(n) * n, u, v, plan.pixel_mm, plan.width, plan.height));
  }
  return plan;
}

/// The images rendered into out/images/ (and the sector mask, when the pattern has one).
struct RenderedSeries {
  std::vector<char> dropped, clipped;  ///< per pose
  std::optional<std::string> fov_name;
  std::function<std::string(int)> image_name;
};

RenderedSeries renderSeries(const PhantomSpec& spec, const PhantomShape& shape, const SlicePlan& plan,
                            const StagedOutput& out, bool quiet) {
  const int n = int(plan.poses.size());
  RenderedSeries s;
  fs::create_directories(out.file("images"));
  cv::Mat fov;
  if (plan.sector) {
    fov = sectorMask(*plan.sector, plan.width, plan.height);
    s.fov_name = "images/fov.png";
    if (!cv::imwrite(out.file(*s.fov_name).string(), fov))
      throw std::runtime_error("cannot write " + out.file(*s.fov_name).string());
  }
  const int digits = std::max(3, int(std::to_string(std::max(0, n - 1)).size()));
  s.image_name = [digits](int i) {
    std::ostringstream os;
    os << "images/" << std::setw(digits) << std::setfill('0') << i << ".png";
    return os.str();
  };
  s.dropped.resize(std::size_t(n));
  s.clipped.resize(std::size_t(n));
  for (int i = 0; i < n; ++i) s.dropped[std::size_t(i)] = dropFrame(spec.degradations.drop_probability, spec.seed, i);
  std::atomic<int> done{0};
  std::mutex progress;
  tbb::parallel_for(0, n, [&](int i) {
    if (!s.dropped[std::size_t(i)]) {
      const RenderedSlice r =
          shape.label_split
              ? renderLabelSlice(shape, plan.poses[std::size_t(i)], plan.width, plan.height, fov)
          : spec.degradations.ultrasound.enabled
              ? renderUltrasoundSlice(shape, plan.poses[std::size_t(i)], plan.width, plan.height, fov, plan.sector,
                                      spec.degradations, spec.seed, i)
              : renderSlice(shape, plan.poses[std::size_t(i)], plan.width, plan.height, fov, spec.degradations,
                            spec.seed, i);
      s.clipped[std::size_t(i)] = r.clipped;
      const fs::path file = out.file(s.image_name(i));
      if (!cv::imwrite(file.string(), r.image)) throw std::runtime_error("cannot write " + file.string());
    }
    const int k = ++done;
    if (!quiet && n >= 20 && k % (n / 10) == 0) {
      std::lock_guard<std::mutex> lock(progress);
      std::cerr << "phantom: rendered " << k << "/" << n << " slices\n";
    }
  });
  return s;
}

/// The slices as recorded (poses with the spec's tracking error) and as they truly were.
void sliceRecords(const PhantomSpec& spec, const SlicePlan& plan, const RenderedSeries& s,
                  std::vector<SliceRecord>* recorded, std::vector<SliceRecord>* truth) {
  for (int i = 0; i < int(plan.poses.size()); ++i) {
    if (s.dropped[std::size_t(i)]) continue;
    SliceRecord r;
    r.image = s.image_name(i);
    r.fov = s.fov_name;
    // "+ 0.0" turns -0 into 0 so the files never show "-0".
    r.image_to_world = plan.poses[std::size_t(i)].array() + 0.0;
    truth->push_back(r);
    r.image_to_world = jitterPose(plan.poses[std::size_t(i)], plan.width, plan.height,
                                  spec.degradations.pose_jitter_mm, spec.degradations.pose_jitter_deg, spec.seed, i)
                           .array() +
                       0.0;
    recorded->push_back(r);
  }
}

/// `x` / p, or a neighbouring double y, chosen so that y * p gives back exactly x when one does
/// (so that ProbeToTracker * ImageToProbe reproduces the recorded pose bit for bit).
double divideExactly(double x, double p) {
  const double y = x / p;
  if (y * p == x) return y;
  for (const double cand : {std::nextafter(y, INFINITY), std::nextafter(y, -INFINITY)})
    if (cand * p == x) return cand;
  return y;
}

/// ProbeToTracker of a recorded pose (pixel (i, j, 0, 1) -> mm) for ImageToProbe = diag(p, p, p, 1):
/// pose * inverse(ImageToProbe), a rigid transform for the phantom's poses (columns u p, v p, n p).
Mat4 probeToTracker(const Mat4& pose, double p) {
  Mat4 m = pose;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m(r, c) = divideExactly(pose(r, c), p) + 0.0;
  const Eigen::Matrix3d R = m.block<3, 3>(0, 0);
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-9 || R.determinant() < 0)
    throw std::logic_error("phantom: a pose without its pixel scaling is not a rotation");
  return m;
}

/// The degrees d with d * (pi / 180) == rad in double arithmetic, as the device-set reader converts.
double degreesExactly(double rad) {
  constexpr double kRadPerDeg = 3.14159265358979323846 / 180.0;
  const double d = rad / kRadPerDeg;
  for (const double cand : {d, std::nextafter(d, INFINITY), std::nextafter(d, -INFINITY)})
    if (cand * kRadPerDeg == rad) return cand;
  return d;
}

/// sequence.igs.mha, deviceset.xml and config_plus.yaml: the written frames (read back from their
/// PNG files, one at a time) with the recorded poses of slices.yaml.
void writePlusRecording(const PhantomSpec& spec, const SlicePlan& plan, const RenderedSeries& series,
                        const std::vector<SliceRecord>& recorded, const StagedOutput& out) {
  const double p = plan.pixel_mm;
  Mat4 imageToProbe = Mat4::Identity();
  imageToProbe.diagonal().head<3>().setConstant(p);
  std::vector<int> index;  // pattern index of each written frame
  for (int i = 0; i < int(plan.poses.size()); ++i)
    if (!series.dropped[std::size_t(i)]) index.push_back(i);
  const std::string identity = matrixText(Mat4::Identity());
  std::vector<MetaFrameFields> fields(recorded.size());
  for (std::size_t k = 0; k < recorded.size(); ++k) {
    const Mat4 probe = probeToTracker(recorded[k].image_to_world, p);
    // Exact in all but rare entries (where no double y has y * p == x: then 1 ulp off).
    if ((probe * imageToProbe - recorded[k].image_to_world).cwiseAbs().maxCoeff() > 1e-9)
      throw std::logic_error("phantom: ProbeToTracker * ImageToProbe does not give back the pose");
    MetaFrameFields& f = fields[k];
    f["ProbeToTrackerTransform"] = matrixText(probe);
    f["ProbeToTrackerTransformStatus"] = "OK";
    f["ReferenceToTrackerTransform"] = identity;
    f["ReferenceToTrackerTransformStatus"] = "OK";
    f["ImageStatus"] = "OK";
    f["Timestamp"] = yamlNumberText(0.05 * index[k]);
  }
  writeMetaImageSequence(
      out.file("sequence.igs.mha").string(), int(recorded.size()),
      [&](int k) {
        const std::string file = out.file(recorded[std::size_t(k)].image).string();
        cv::Mat m = cv::imread(file, cv::IMREAD_UNCHANGED);
        if (m.empty()) throw std::runtime_error("cannot read back " + file);
        return m;
      },
      fields, true);
  std::optional<PlusFanMask> fan;
  if (plan.sector) {
    const SectorFov& s = *plan.sector;
    PlusFanMask f;
    const double deg = degreesExactly(s.half_angle_rad);
    f.angles_deg = {-deg, deg};
    f.origin_px = {s.apex_i, s.apex_j};
    f.radius_start_px = s.near_px;
    f.radius_stop_px = s.far_px;
    fan = f;
  }
  writePlusDeviceSet(out.file("deviceset.xml").string(), imageToProbe, std::nullopt, std::nullopt, fan);
  writeTextFile(out.file("config_plus.yaml").string(), configYaml(spec, plan, true));
}

}  // namespace

int phantomCommand(const PhantomOptions& options) {
  const PhantomSpec spec = readPhantomSpec(options.spec);
  const SlicePlan plan = phantomPlan(spec);
  PhantomShape shape = spec.shape;
  if (shape.label_split) {
    try {
      shape.label_betti = labelBettiNumbers(shape);
    } catch (const std::runtime_error& e) {
      throw InputError(spec.path, "shape.label_split", e.what());
    }
  }
  const int n = int(plan.poses.size());
  if (!options.quiet)
    std::cerr << "phantom: " << nameOf(kShapeKinds, spec.shape.kind) << ", " << nameOf(kPatternKinds, spec.pattern.kind) << " pattern, " << n
              << " slices of " << plan.width << "x" << plan.height << " px at "
              << plan.pixel_mm << " mm\n";

  StagedOutput out(options.out, {{spec.path}, "command line", "--out"});
  const RenderedSeries series = renderSeries(spec, shape, plan, out, options.quiet);
  std::vector<SliceRecord> recorded, truth;
  sliceRecords(spec, plan, series, &recorded, &truth);
  if (recorded.empty())
    throw InputError(spec.path, "degradations.drop_probability", "every frame was dropped");
  writeSlicesFile(out.file("slices.yaml").string(), recorded);
  writeSlicesFile(out.file("true_poses.yaml").string(), truth);
  writeTruthFile(out.file("truth.yaml").string(), shape);
  writeTextFile(out.file("config.yaml").string(), configYaml(spec, plan));
  if (spec.plus) writePlusRecording(spec, plan, series, recorded, out);
  writeTextFile(out.file(kManifestName).string(), outputManifestText(manifestHead("phantom", {spec.path}), out.dir()));
  out.commit();

  const int nClipped = int(std::count(series.clipped.begin(), series.clipped.end(), 1));
  if (!options.quiet) {
    if (nClipped > 0)
      std::cerr << "phantom: warning: in " << nClipped
                << " slices the section reaches the image or field-of-view border\n";
    std::cerr << "phantom: wrote " << recorded.size() << " slices (" << (n - int(recorded.size()))
              << " dropped) to " << out.destination().string() << "\n";
  }
  return 0;
}

}  // namespace xsect

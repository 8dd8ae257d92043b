// Phantom rendering and the `xsect phantom` command: the rendered section matches the analytic
// one, renders and whole output folders are deterministic, degradations act as specified, extra
// planes and two-label phantoms (label images, per-label Betti numbers) are written as specified,
// truth files round-trip (reach interior / exterior, labels; older files still read), and
// malformed specs give an InputError naming the key with no output folder left behind.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <unistd.h>
#include <yaml-cpp/yaml.h>
#include <opencv2/imgcodecs.hpp>

#include "geometry/core/plane_of_pose.h"
#include "geometry/phantoms/slicing_pattern.h"
#include "io/input_error.h"
#include "io/phantom_spec.h"
#include "io/slices_file.h"
#include "io/truth_file.h"
#include "geometry/phantoms/vessel_tree.h"
#include "pipeline/phantom_render.h"

using namespace xsect;
namespace fs = std::filesystem;

namespace {

/// A fresh folder under /tmp, removed at the end of the test.
struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() /
           ("xsect-phantom-test-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name) << text;
    return path / name;
  }
};

std::string readAll(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream os;
  os << f.rdbuf();
  return os.str();
}

struct RunResult {
  int code;
  std::string err;
};
RunResult runXsect(const std::string& args, const fs::path& errFile) {
  const std::string cmd = std::string(XSECT_BIN) + " " + args + " 2> " + errFile.string();
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, readAll(errFile)};
}

PhantomShape sphere(double r, const Vec3& c) {
  PhantomShape s;
  s.kind = ShapeKind::sphere;
  s.params["radius"] = r;
  s.centre = c;
  return s;
}

const char* kSphereSpec = R"(seed: 5
shape: {kind: sphere, params: {radius: 6}, centre: [1, 2, 3]}
pattern: {kind: multiaxial, counts: [3, 2, 4]}
image: {pixel_mm: 0.25}
config: {reconstruction.voxel_size_mm: 0.3, output: {mesh: [ply, stl]}}
)";

}  // namespace

TEST(PhantomCommandRender, ThresholdedSectionHasTheAnalyticArea) {
  const double R = 10, d = 4, px = 0.1;
  const PhantomShape s = sphere(R, Vec3(1, 2, 3));
  // Plane z = 3 + d, image 241 x 241 px centred over the sphere.
  const Mat4 pose = centredPose(Vec3(1, 2, 3 + d), Vec3::UnitX(), Vec3::UnitY(), px, 241, 241);
  const RenderedSlice r = renderSlice(s, pose, 241, 241, cv::Mat(), {}, 1, 0);
  ASSERT_EQ(r.image.type(), CV_8UC1);
  EXPECT_FALSE(r.clipped);
  const double area = cv::countNonZero(r.image >= 128) * px * px;
  const double expected = M_PI * (R * R - d * d);
  EXPECT_NEAR(area, expected, 0.01 * expected);
  // The edge is anti-aliased: intermediate grey levels exist, and the centre is saturated.
  EXPECT_EQ(r.image.at<std::uint8_t>(120, 130), 255);
  EXPECT_GT(cv::countNonZero((r.image > 20) & (r.image < 235)), 100);
  // A section that leaves the image is reported as clipped.
  const Mat4 small = centredPose(Vec3(1, 2, 3), Vec3::UnitX(), Vec3::UnitY(), px, 101, 101);
  EXPECT_TRUE(renderSlice(s, small, 101, 101, cv::Mat(), {}, 1, 0).clipped);
}

TEST(PhantomCommandRender, DeterministicFromTheSeed) {
  const PhantomShape s = sphere(5, Vec3::Zero());
  const Mat4 pose = centredPose(Vec3(0, 0, 1), Vec3::UnitX(), Vec3::UnitY(), 0.1, 121, 121);
  PhantomDegradations d;
  d.noise_sigma = 12;
  d.speckle = 0.3;
  d.blur_sigma_px = 1.2;
  const cv::Mat a = renderSlice(s, pose, 121, 121, cv::Mat(), d, 7, 3).image;
  const cv::Mat b = renderSlice(s, pose, 121, 121, cv::Mat(), d, 7, 3).image;
  const cv::Mat c = renderSlice(s, pose, 121, 121, cv::Mat(), d, 8, 3).image;
  const cv::Mat e = renderSlice(s, pose, 121, 121, cv::Mat(), d, 7, 4).image;
  const cv::Mat clean = renderSlice(s, pose, 121, 121, cv::Mat(), {}, 7, 3).image;
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0);
  EXPECT_GT(cv::norm(a, c, cv::NORM_INF), 0);  // another seed, other noise
  EXPECT_GT(cv::norm(a, e, cv::NORM_INF), 0);  // another slice, other noise
  EXPECT_GT(cv::norm(a, clean, cv::NORM_L1) / a.total(), 3.0);  // the noise is there
  // A FOV mask blanks what lies outside it.
  cv::Mat fov(121, 121, CV_8U, cv::Scalar(0));
  fov(cv::Rect(0, 0, 60, 121)).setTo(255);
  const RenderedSlice masked = renderSlice(s, pose, 121, 121, fov, {}, 7, 3);
  EXPECT_EQ(cv::countNonZero(masked.image(cv::Rect(60, 0, 61, 121))), 0);
  EXPECT_TRUE(masked.clipped);
}

TEST(PhantomCommandRender, PoseJitterAndDrops) {
  const Mat4 pose = centredPose(Vec3(0, 0, 1), Vec3::UnitX(), Vec3::UnitY(), 0.2, 100, 80);
  EXPECT_EQ(jitterPose(pose, 100, 80, 0, 0, 1, 0), pose);
  const Mat4 j = jitterPose(pose, 100, 80, 0.5, 1.0, 1, 0);
  EXPECT_GT((j - pose).cwiseAbs().maxCoeff(), 1e-3);
  // Still a rigid pose with the same pixel size and orthogonal axes.
  EXPECT_NEAR((j.block<3, 1>(0, 0).norm()), 0.2, 1e-12);
  EXPECT_NEAR((j.block<3, 1>(0, 0).dot(j.block<3, 1>(0, 1))), 0, 1e-12);
  EXPECT_EQ(j, jitterPose(pose, 100, 80, 0.5, 1.0, 1, 0));
  int dropped = 0;
  for (int i = 0; i < 1000; ++i) dropped += dropFrame(0.3, 5, i);
  EXPECT_NEAR(dropped, 300, 60);
}

TEST(PhantomCommandRender, BlendedVesselTreeCullingKeepsEveryPixel) {
  // The renderer skips junctions far from the plane: every pixel must equal the one computed
  // from the whole tree.
  PhantomShape s;
  s.kind = ShapeKind::vessel_tree;
  s.params = {{"length", 10}, {"radius", 1}, {"levels", 3}, {"blend_mm", 0.5}};
  s.rotation = rotationFromEulerXyzDeg(Vec3(10, 20, 0));
  s = completePhantomShape(s);
  Vec3 u, v;
  const Vec3 n = Vec3(0.3, -0.2, 1).normalized();
  planeFrame(n, &u, &v);
  for (const double z : {9.7, 10.4, 17.5, 23.0}) {
    const double px = 0.1;
    const Mat4 pose = centredPose(s.rotation * Vec3(0, 0, z), u, v, px, 240, 240);
    const cv::Mat im = renderSlice(s, pose, 240, 240, cv::Mat(), {}, 1, 0).image;
    int differ = 0, inside = 0;
    for (int j = 0; j < 240; ++j)
      for (int i = 0; i < 240; ++i) {
        const Vec3 p = (pose * Eigen::Vector4d(i, j, 0, 1)).head<3>();
        const float f = float(std::clamp(127.5 * (1.0 - signedDistance(s, p) / px), 0.0, 255.0));
        differ += im.at<std::uint8_t>(j, i) != cv::saturate_cast<std::uint8_t>(f);
        inside += f > 128;
      }
    EXPECT_EQ(differ, 0) << z;
    EXPECT_GT(inside, 100) << z;
  }
}

TEST(PhantomCommand, WritesACompleteRunnableFolder) {
  TempDir tmp;
  const fs::path spec = tmp.write("spec.yaml", kSphereSpec);
  const fs::path out = tmp.path / "out";
  const RunResult r = runXsect("phantom " + spec.string() + " --out " + out.string() + " -q",
                         tmp.path / "err.txt");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto slices = readSlicesFile((out / "slices.yaml").string());
  ASSERT_EQ(slices.size(), 9u);
  const auto truePoses = readSlicesFile((out / "true_poses.yaml").string());
  ASSERT_EQ(truePoses.size(), 9u);
  for (std::size_t i = 0; i < slices.size(); ++i) {
    const cv::Mat im = cv::imread(slices[i].image_resolved, cv::IMREAD_UNCHANGED);
    ASSERT_EQ(im.type(), CV_8UC1);
    // No jitter in the spec: recorded = true poses.
    EXPECT_LT((slices[i].image_to_world - truePoses[i].image_to_world).cwiseAbs().maxCoeff(), 1e-12);
    // Every section lies inside its image: the border is black.
    cv::Mat border = im.clone();
    border(cv::Rect(1, 1, im.cols - 2, im.rows - 2)).setTo(0);
    EXPECT_EQ(cv::countNonZero(border), 0);
    // The section's area matches pi (R^2 - d^2).
    const Plane pl = planeOfPose(slices[i].image_to_world);
    const double d = pl.signedDistance(Vec3(1, 2, 3));
    const double area = cv::countNonZero(im >= 128) * 0.25 * 0.25;
    EXPECT_NEAR(area, M_PI * (36 - d * d), 0.03 * M_PI * 36) << i;
  }
  const PhantomShape t = readTruthFile((out / "truth.yaml").string());
  EXPECT_EQ(t.kind, ShapeKind::sphere);
  EXPECT_EQ(t.params.at("radius"), 6);
  EXPECT_EQ(t.centre, Vec3(1, 2, 3));
  const YAML::Node truth = YAML::LoadFile((out / "truth.yaml").string());
  EXPECT_EQ(truth["betti"][2].as<int>(), 0);
  EXPECT_EQ(truth["reach_mm"].as<double>(), 6);
  EXPECT_EQ(truth["reach_interior_mm"].as<double>(), 6);
  EXPECT_EQ(truth["reach_exterior_mm"].as<std::string>(), ".inf");  // convex
  EXPECT_FALSE(truth["labels"]);
  EXPECT_TRUE(truth["exact_distance"].as<bool>());
  const YAML::Node cfg = YAML::LoadFile((out / "config.yaml").string());
  EXPECT_EQ(cfg["input"]["slices"].as<std::string>(), "slices.yaml");
  EXPECT_EQ(cfg["segmentation"]["threshold"].as<double>(), 128);
  EXPECT_EQ(cfg["reconstruction"]["voxel_size_mm"].as<double>(), 0.3);  // from the spec
  EXPECT_EQ(cfg["reconstruction"]["method"].as<std::string>(), "nearest_plane");
  EXPECT_EQ(cfg["reconstruction"]["end_margin_mm"].as<std::string>(), "auto");
  EXPECT_FALSE(cfg["conformity"]["enforce"].as<bool>());
  EXPECT_EQ(cfg["output"]["mesh"].size(), 2u);
  // Nothing else was left beside the output (no staging folder).
  int entries = 0;
  for (const auto& e : fs::directory_iterator(tmp.path)) entries += e.path().filename() != "err.txt";
  EXPECT_EQ(entries, 2);  // spec.yaml and out
}

TEST(PhantomCommand, SameSeedGivesByteIdenticalFolders) {
  TempDir tmp;
  const fs::path spec = tmp.write("spec.yaml", R"(seed: 3
shape: {kind: vessel_tree, params: {length: 6, radius: 0.8, levels: 2}}
pattern: {kind: freehand, count: 30, sector: true, tilt_deg: 4}
image: {pixel_mm: 0.2, width: 120, height: 90}
degradations: {noise_sigma: 8, speckle: 0.2, blur_sigma_px: 0.8, pose_jitter_mm: 0.2,
               pose_jitter_deg: 0.5, drop_probability: 0.2}
)");
  const fs::path a = tmp.path / "a", b = tmp.path / "b";
  ASSERT_EQ(runXsect("--threads 1 phantom " + spec.string() + " --out " + a.string() + " -q",
                     tmp.path / "e1").code, 0);
  ASSERT_EQ(runXsect("--threads 2 phantom " + spec.string() + " --out " + b.string() + " -q",
                     tmp.path / "e2").code, 0);
  int files = 0;
  for (const auto& e : fs::recursive_directory_iterator(a)) {
    if (!e.is_regular_file()) continue;
    ++files;
    const fs::path rel = fs::relative(e.path(), a);
    ASSERT_TRUE(fs::exists(b / rel)) << rel;
    EXPECT_EQ(readAll(e.path()), readAll(b / rel)) << rel;
  }
  EXPECT_GT(files, 10);
  // Drops and jitter are applied: fewer slices than frames, recorded poses differ from true.
  const auto rec = readSlicesFile((a / "slices.yaml").string());
  const auto tru = readSlicesFile((a / "true_poses.yaml").string());
  ASSERT_EQ(rec.size(), tru.size());
  EXPECT_LT(rec.size(), 30u);
  EXPECT_GT(rec.size(), 10u);
  EXPECT_TRUE(rec[0].fov.has_value());
  EXPECT_GT((rec[0].image_to_world - tru[0].image_to_world).cwiseAbs().maxCoeff(), 1e-4);
  const YAML::Node cfg = YAML::LoadFile((a / "config.yaml").string());
  EXPECT_EQ(cfg["segmentation"]["method"].as<std::string>(), "otsu");
  const YAML::Node truth = YAML::LoadFile((a / "truth.yaml").string());
  EXPECT_EQ(truth["shape"]["tubes"].size(), 7u);
  const PhantomShape tree = readTruthFile((a / "truth.yaml").string());
  EXPECT_EQ(tree.tubes.size(), 7u);
  EXPECT_GT(tree.params.at("nominal_reach"), 0.0);
  EXPECT_FALSE(truth["exact_distance"].as<bool>());
  // The smooth (default) tree: reach bounds recorded, read back as written.
  EXPECT_EQ(truth["shape"]["params"]["blend_mm"].as<double>(), 0.5);
  EXPECT_GT(truth["reach_exterior_mm"].as<double>(), 0.0);
  EXPECT_EQ(*tree.reach_interior_mm, truth["reach_interior_mm"].as<double>());
  EXPECT_EQ(*tree.reach_exterior_mm, truth["reach_exterior_mm"].as<double>());
  EXPECT_EQ(truth["reach_mm"].as<double>(),
            std::min(*tree.reach_interior_mm, *tree.reach_exterior_mm));
  EXPECT_EQ(tree.junctions.size(), 3u);
}

TEST(PhantomCommand, MalformedSpecsNameTheKeyAndLeaveNoFolder) {
  TempDir tmp;
  struct Case {
    std::string spec, key;
  };
  const std::vector<Case> cases{
      {"shape: {kind: cube, params: {radius: 3}}\npattern: {kind: random, count: 3}\n",
       "shape.kind"},
      {"shape: {kind: sphere, params: {radius: -3}}\npattern: {kind: random, count: 3}\n",
       "shape.params.radius"},
      {"shape: {kind: torus, params: {major_radius: 5}}\npattern: {kind: random, count: 3}\n",
       "shape.params.minor_radius"},
      {"shape: {kind: sphere, params: {radius: 3}}\n", "pattern"},
      {"shape: {kind: sphere, params: {radius: 3}}\npattern: {kind: random}\n", "pattern.count"},
      {"shape: {kind: sphere, params: {radius: three}}\npattern: {kind: random, count: 3}\n",
       "shape.params.radius"},
      {"shape: {kind: sphere, params: {radius: 3}}\npattern: {kind: random, count: 2.5}\n",
       "pattern.count"},
      {"shape: {kind: sphere, params: {radius: 3}, centre: [1, 2]}\n"
       "pattern: {kind: random, count: 3}\n", "shape.centre"},
      {"shape: {kind: sphere, params: {radius: 3}}\npattern: {kind: random, count: 3}\n"
       "degradations: {noise: 3}\n", "degradations.noise"},
      {"shape: {kind: sphere, params: {radius: 3}}\npattern: {kind: spiral, count: 3}\n",
       "pattern.kind"},
      {"shape: {kind: sphere, params: {radius: 3}}\npattern: {kind: random, count: 3}\n"
       "image: {pixel_mm: -1}\n", "image.pixel_mm"},
      {"shape: {kind: vessel_tree, params: {length: 10, radius: 1, blend_mm: -1}}\n"
       "pattern: {kind: random, count: 3}\n", "shape.params.blend_mm"},
      {"shape: {kind: sphere, params: {radius: 3}, label_split: {point: [0, 0, 0]}}\n"
       "pattern: {kind: random, count: 3}\n", "shape.label_split.normal"},
      {"shape: {kind: sphere, params: {radius: 3}, label_split: {normal: [0, 0, 0]}}\n"
       "pattern: {kind: random, count: 3}\n", "shape.label_split.normal"},
      {"shape: {kind: sphere, params: {radius: 3}, label_split: {normal: [1, 0, 0], side: 2}}\n"
       "pattern: {kind: random, count: 3}\n", "shape.label_split.side"},
      {"shape: {kind: sphere, params: {radius: 3}, label_split: [1, 0, 0]}\n"
       "pattern: {kind: random, count: 3}\n", "shape.label_split"},
      {"shape: {kind: sphere, params: {radius: 3}, label_split: {normal: [1, 0, 0]}}\n"
       "pattern: {kind: random, count: 3}\ndegradations: {noise_sigma: 5}\n",
       "degradations.noise_sigma"},
      {"shape: {kind: sphere, params: {radius: 3}, label_split: {normal: [1, 0, 0]}}\n"
       "pattern: {kind: random, count: 3}\ndegradations: {blur_sigma_px: 1}\n",
       "degradations.blur_sigma_px"},
      {"shape: {kind: sphere, params: {radius: 3}}\n"
       "pattern: {kind: random, count: 3, extra_planes: {point: [0, 0, 0]}}\n",
       "pattern.extra_planes"},
      {"shape: {kind: sphere, params: {radius: 3}}\n"
       "pattern: {kind: random, count: 3, extra_planes: []}\n", "pattern.extra_planes"},
      {"shape: {kind: sphere, params: {radius: 3}}\n"
       "pattern: {kind: random, count: 3, extra_planes: [{point: [0, 0, 0]}]}\n",
       "pattern.extra_planes[0].normal"},
      {"shape: {kind: sphere, params: {radius: 3}}\n"
       "pattern: {kind: fan, count: 3, extra_planes: [{point: [0, 0, 0], normal: [0, 0, 1]}, "
       "{point: [0, 0], normal: [0, 0, 1]}]}\n", "pattern.extra_planes[1].point"},
      {"shape: {kind: sphere, params: {radius: 3}}\n"
       "pattern: {kind: parallel, count: 3, extra_planes: [{point: [0, 0, 0], "
       "normal: [0, 0, 0]}]}\n",
       "pattern.extra_planes[0].normal"},
      {"shape: {kind: sphere, params: {radius: 3}}\n"
       "pattern: {kind: random, count: 3, extra_planes: [{point: [0, 0, 0], normal: [0, 0, 1], "
       "tilt: 2}]}\n", "pattern.extra_planes[0].tilt"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const fs::path spec = tmp.write("bad" + std::to_string(i) + ".yaml", cases[i].spec);
    try {
      readPhantomSpec(spec.string());
      ADD_FAILURE() << "accepted: " << cases[i].spec;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), cases[i].key) << e.what();
      EXPECT_EQ(e.file(), spec.string());
    }
    const fs::path out = tmp.path / ("out" + std::to_string(i));
    const RunResult r = runXsect("phantom " + spec.string() + " --out " + out.string(),
                           tmp.path / "err.txt");
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(cases[i].key), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(spec.filename().string()), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out)) << cases[i].spec;
  }
  for (const auto& e : fs::directory_iterator(tmp.path))
    EXPECT_EQ(e.path().filename().string().find(".out"), std::string::npos) << e.path();
}

TEST(PhantomCommand, TruthFileRoundTripsAndRejectsBadInput) {
  TempDir tmp;
  PhantomShape s;
  s.kind = ShapeKind::genus2;
  s.params = {{"disk_radius", 20}, {"hole_radius", 5}, {"hole_offset", 8}, {"offset_radius", 2.5}};
  s.centre = Vec3(0.1, -2, 3.5);
  s.rotation = rotationFromEulerXyzDeg(Vec3(10, 20, 30));
  writeTruthFile((tmp.path / "t.yaml").string(), s);
  const PhantomShape back = readTruthFile((tmp.path / "t.yaml").string());
  EXPECT_EQ(back.params, s.params);
  EXPECT_EQ(back.centre, s.centre);
  EXPECT_EQ(back.rotation, s.rotation);  // shortest round-trip text is exact
  const std::string good = readAll(tmp.path / "t.yaml");
  auto expectError = [&](std::string text, const std::string& key) {
    const fs::path p = tmp.write("bad.yaml", text);
    try {
      readTruthFile(p.string());
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), key) << e.what();
    }
  };
  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string t = good;
    const auto at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return t.replace(at, from.size(), to);
  };
  expectError(replaced("kind: genus2", "kind: blob"), "shape.kind");
  expectError(replaced("disk_radius: 20", "disk_radius: .nan"), "shape.params.disk_radius");
  expectError(replaced("hole_radius: 5", "hole_radius: -5"), "shape.params.hole_radius");
  expectError(replaced("betti: [1, 2, 0]", "betti: [1, 2]"), "betti");
  expectError(replaced("exact_distance: true", "exact_distance: maybe"), "exact_distance");
  expectError(replaced("reach_mm: 2.5\n", ""), "reach_mm");
  expectError(replaced("reach_interior_mm: 2.5", "reach_interior_mm: -1"), "reach_interior_mm");
  expectError(replaced("reach_exterior_mm: 2.5", "reach_exterior_mm: far"), "reach_exterior_mm");
  expectError(replaced("reach_mm: 2.5\n", "reach_mm: 2.5\nlabels: {1: {betti: [1, 0, 0]}}\n"),
              "labels");  // labels without a label_split
  // reach_interior_mm and reach_exterior_mm are read back; files without them still read.
  EXPECT_EQ(*back.reach_interior_mm, 2.5);
  EXPECT_EQ(*back.reach_exterior_mm, 2.5);
  const fs::path old = tmp.write(
      "old.yaml", replaced("reach_interior_mm: 2.5\nreach_exterior_mm: 2.5\n", ""));
  const PhantomShape fromOld = readTruthFile(old.string());
  EXPECT_FALSE(fromOld.reach_interior_mm.has_value());
  EXPECT_EQ(reachInterior(fromOld), 2.5);
}

TEST(PhantomCommand, TruthFileOfATwoLabelPhantomRoundTrips) {
  TempDir tmp;
  PhantomShape s;
  s.kind = ShapeKind::torus;
  s.params = {{"major_radius", 8}, {"minor_radius", 2}};
  s.rotation = rotationFromEulerXyzDeg(Vec3(0, 30, 0));
  s.label_split = PhantomShape::LabelSplit{Vec3(0, 0, 0.5), Vec3(0, 1, 0)};
  writeTruthFile((tmp.path / "t.yaml").string(), s);
  const YAML::Node y = YAML::LoadFile((tmp.path / "t.yaml").string());
  EXPECT_EQ(y["labels"][1]["betti"][0].as<int>(), 1);
  EXPECT_EQ(y["labels"][2]["betti"][1].as<int>(), 0);
  EXPECT_EQ(y["betti"][1].as<int>(), 1);  // the union: a torus
  EXPECT_EQ(y["reach_exterior_mm"].as<double>(), 6);
  const PhantomShape back = readTruthFile((tmp.path / "t.yaml").string());
  ASSERT_TRUE(back.label_split.has_value());
  EXPECT_EQ(back.label_split->point, Vec3(0, 0, 0.5));
  EXPECT_EQ(back.label_split->normal, Vec3(0, 1, 0));
  ASSERT_TRUE(back.label_betti.has_value());
  EXPECT_EQ(back.label_betti->at(1), (Betti{1, 0, 0}));
  EXPECT_EQ(back.label_betti->at(2), (Betti{1, 0, 0}));
  const std::string good = readAll(tmp.path / "t.yaml");
  auto expectError = [&](const std::string& from, const std::string& to, const std::string& key) {
    std::string t = good;
    const auto at = t.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    const fs::path p = tmp.write("bad.yaml", t.replace(at, from.size(), to));
    try {
      readTruthFile(p.string());
      ADD_FAILURE() << "accepted: " << to;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), key) << e.what();
    }
  };
  expectError("normal: [0, 1, 0]", "normal: [0, 0, 0]", "shape.label_split.normal");
  expectError("normal: [0, 1, 0]", "normal: [0, 1]", "shape.label_split.normal");
  expectError("point: [0, 0, 0.5]", "point: [0, 0, 0.5], side: 1", "shape.label_split.side");
  expectError("1: {betti: [1, 0, 0]}", "3: {betti: [1, 0, 0]}", "labels.3");
  expectError("1: {betti: [1, 0, 0]}", "1: {betti: [1, -1, 0]}", "labels.1.betti[1]");
  expectError("1: {betti: [1, 0, 0]}", "1: [1, 0, 0]", "labels.1");
}

TEST(PhantomCommand, OldVesselTreeTruthFilesAreUnionsOfCapsules) {
  // Files written before blending (no blend_mm, no reach_interior_mm / reach_exterior_mm)
  // describe the union of their capsules.
  TempDir tmp;
  PhantomShape s;
  s.kind = ShapeKind::vessel_tree;
  s.params = {{"length", 10}, {"radius", 1}, {"levels", 2}};
  s = completePhantomShape(s);
  ASSERT_GT(s.params.at("blend_mm"), 0.0);
  writeTruthFile((tmp.path / "t.yaml").string(), s);
  std::istringstream lines(readAll(tmp.path / "t.yaml"));
  std::string text, line;
  int dropped = 0;
  while (std::getline(lines, line)) {
    const bool drop = line.find("blend_mm:") != std::string::npos ||
                      line.find("reach_interior_mm:") != std::string::npos ||
                      line.find("reach_exterior_mm:") != std::string::npos;
    dropped += drop;
    if (!drop) text += line + "\n";
  }
  ASSERT_EQ(dropped, 3);
  const PhantomShape old = readTruthFile(tmp.write("old.yaml", text).string());
  EXPECT_EQ(old.params.at("blend_mm"), 0.0);
  EXPECT_EQ(reachExterior(old), 0.0);  // creases
  for (double z = -1; z < 20; z += 0.37) {
    const Vec3 x(0.3 * z - 2, 0.7, z);
    double capsules = INFINITY;
    for (const auto& t : old.tubes) {
      const Vec3 d = t.b - t.a;
      const double u = std::clamp((x - t.a).dot(d) / d.squaredNorm(), 0.0, 1.0);
      capsules = std::min(capsules, (t.a + u * d - x).norm() - t.radius);
    }
    EXPECT_EQ(signedDistance(old, x), capsules);
  }
  // The written file itself reads back as the blended tree.
  const PhantomShape now = readTruthFile((tmp.path / "t.yaml").string());
  EXPECT_EQ(now.params.at("blend_mm"), 0.5);
  EXPECT_EQ(now.tubes.size(), s.tubes.size());
  EXPECT_EQ(signedDistance(now, s.tubes[0].b), signedDistance(s, s.tubes[0].b));
}

TEST(PhantomCommand, TwoLabelPhantomWritesLabelImages) {
  TempDir tmp;
  const fs::path spec = tmp.write("spec.yaml", R"(seed: 2
shape:
  kind: torus
  params: {major_radius: 6, minor_radius: 2}
  rotation_deg: [20, 10, 0]
  label_split: {normal: [1, 0, 0]}
pattern: {kind: multiaxial, count: 3}
image: {pixel_mm: 0.25}
degradations: {pose_jitter_mm: 0.1}
)");
  const fs::path out = tmp.path / "out";
  const RunResult r = runXsect("phantom " + spec.string() + " --out " + out.string() + " -q",
                               tmp.path / "err.txt");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto slices = readSlicesFile((out / "slices.yaml").string());
  ASSERT_EQ(slices.size(), 9u);
  std::set<int> seen;
  int touching = 0;
  for (const auto& sl : slices) {
    const cv::Mat im = cv::imread(sl.image_resolved, cv::IMREAD_UNCHANGED);
    ASSERT_EQ(im.type(), CV_8UC1);
    for (int j = 0; j < im.rows; ++j)
      for (int i = 0; i < im.cols; ++i) {
        const int v = im.at<std::uint8_t>(j, i);
        ASSERT_LE(v, 2) << sl.image;
        seen.insert(v);
        // Label 1 and label 2 pixels meet along the split line.
        if (i + 1 < im.cols && v * im.at<std::uint8_t>(j, i + 1) == 2) ++touching;
        if (j + 1 < im.rows && v * im.at<std::uint8_t>(j + 1, i) == 2) ++touching;
      }
  }
  EXPECT_EQ(seen, (std::set<int>{0, 1, 2}));
  EXPECT_GT(touching, 20);
  const YAML::Node cfg = YAML::LoadFile((out / "config.yaml").string());
  EXPECT_EQ(cfg["segmentation"]["method"].as<std::string>(), "labels");
  EXPECT_FALSE(cfg["segmentation"]["threshold"]);
  const YAML::Node truth = YAML::LoadFile((out / "truth.yaml").string());
  EXPECT_EQ(truth["betti"][1].as<int>(), 1);
  for (const int l : {1, 2}) {
    EXPECT_EQ(truth["labels"][l]["betti"][0].as<int>(), 1) << l;  // two C-shaped halves
    EXPECT_EQ(truth["labels"][l]["betti"][1].as<int>(), 0) << l;
  }
  const PhantomShape t = readTruthFile((out / "truth.yaml").string());
  ASSERT_TRUE(t.label_split.has_value());
  EXPECT_EQ(t.label_split->normal, Vec3(1, 0, 0));
  // The render itself: label 1 on the negative side of the split.
  const Mat4 pose = centredPose(Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), 0.25, 81, 81);
  PhantomShape flat = t;
  flat.rotation.setIdentity();
  const RenderedSlice lab = renderLabelSlice(flat, pose, 81, 81, cv::Mat());
  EXPECT_EQ(lab.image.at<std::uint8_t>(40, 40 - 24), 1);  // x = -6 mm, on the core circle
  EXPECT_EQ(lab.image.at<std::uint8_t>(40, 40 + 24), 2);
  EXPECT_EQ(lab.image.at<std::uint8_t>(40, 40), 0);  // the hole
  EXPECT_FALSE(lab.clipped);
}

TEST(PhantomCommand, ExtraPlanesAreAddedAfterThePattern) {
  TempDir tmp;
  const fs::path spec = tmp.write("spec.yaml", R"(shape: {kind: sphere, params: {radius: 4}}
pattern:
  kind: multiaxial
  counts: [0, 0, 3]
  extra_planes:
    - {point: [0, 0, 5], normal: [0, 0, 2]}
    - {point: [1, 2, 3], normal: [1, 1, 0]}
image: {pixel_mm: 0.2}
)");
  const PhantomSpec ps = readPhantomSpec(spec.string());
  ASSERT_EQ(ps.extra_planes.size(), 2u);
  EXPECT_EQ(ps.extra_planes[0].normal, Vec3(0, 0, 1));  // normalised
  const fs::path out = tmp.path / "out";
  const RunResult r = runXsect("phantom " + spec.string() + " --out " + out.string() + " -q",
                               tmp.path / "err.txt");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto slices = readSlicesFile((out / "slices.yaml").string());
  ASSERT_EQ(slices.size(), 5u);
  const Plane a = planeOfPose(slices[3].image_to_world), b = planeOfPose(slices[4].image_to_world);
  EXPECT_NEAR(a.normal.dot(Vec3(0, 0, 1)), 1.0, 1e-12);
  EXPECT_NEAR(a.signedDistance(Vec3(0, 0, 5)), 0.0, 1e-9);
  EXPECT_NEAR(b.normal.dot(Vec3(1, 1, 0).normalized()), 1.0, 1e-12);
  EXPECT_NEAR(b.signedDistance(Vec3(1, 2, 3)), 0.0, 1e-9);
  // The plane z = 5 misses the sphere: an empty image.
  EXPECT_EQ(cv::countNonZero(cv::imread(slices[3].image_resolved, cv::IMREAD_UNCHANGED)), 0);
  EXPECT_GT(cv::countNonZero(cv::imread(slices[4].image_resolved, cv::IMREAD_UNCHANGED)), 100);
}

TEST(PhantomCommand, SparseVesselTreeSpecHasEmptyPlanesBesideTheTree) {
  const PhantomSpec ps = readPhantomSpec(
      (fs::path(XSECT_SOURCE_DIR) / "configs/phantoms/vessel-tree-sparse.yaml").string());
  const PhantomShape& s = ps.shape;
  EXPECT_GT(reachInterior(s), 0.1);
  EXPECT_GT(reachExterior(s), 0.05);
  ASSERT_EQ(ps.extra_planes.size(), 2u);
  Vec3 lo, hi;
  bounds(s, &lo, &hi);
  const Vec3 c = 0.5 * (lo + hi);
  const double half = 0.5 * (hi - lo).norm();
  for (const auto& pl : ps.extra_planes) {
    Vec3 u, v;
    planeFrame(pl.normal, &u, &v);
    const Vec3 o = c - (c - pl.point).dot(pl.normal) * pl.normal;
    double nearest = INFINITY, lowest = INFINITY;
    for (double a = -half; a <= half; a += 0.05)
      for (double b = -half; b <= half; b += 0.05) {
        const Vec3 x = o + a * u + b * v;
        const double f = signedDistance(s, x);
        lowest = std::min(lowest, f);
        if (f < 0.5) nearest = std::min(nearest, (x - closestBoundaryPoint(s, x)).norm());
      }
    EXPECT_GT(lowest, 0.0) << pl.point.transpose();  // the plane misses the tree
    EXPECT_GE(nearest, 0.1) << pl.point.transpose();  // just beside it
    EXPECT_LE(nearest, 0.5) << pl.point.transpose();
  }
  // The pattern's planes are 2.4 mm apart.
  EXPECT_EQ(ps.pattern.positions_mm.size(), 11u);
}

TEST(PhantomCommand, ExampleSpecsAreValid) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(fs::path(XSECT_SOURCE_DIR) / "configs/phantoms")) {
    if (e.path().extension() != ".yaml") continue;
    ++n;
    const PhantomSpec s = readPhantomSpec(e.path().string());
    EXPECT_FALSE(checkPhantomShape(s.shape).has_value()) << e.path();
  }
  EXPECT_GE(n, 13);
}

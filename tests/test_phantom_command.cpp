// Phantom rendering and the `xsect phantom` command: the rendered section matches the analytic
// one, renders and whole output folders are deterministic, degradations act as specified, and
// malformed specs give an InputError naming the key with no output folder left behind.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>
#include <yaml-cpp/yaml.h>
#include <opencv2/imgcodecs.hpp>

#include "geometry/plane_of_pose.h"
#include "geometry/slicing_pattern.h"
#include "io/input_error.h"
#include "io/phantom_spec.h"
#include "io/slices_file.h"
#include "io/truth_file.h"
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
  s.kind = "sphere";
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

TEST(PhantomRender, ThresholdedSectionHasTheAnalyticArea) {
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

TEST(PhantomRender, DeterministicFromTheSeed) {
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

TEST(PhantomRender, PoseJitterAndDrops) {
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
  EXPECT_EQ(t.kind, "sphere");
  EXPECT_EQ(t.params.at("radius"), 6);
  EXPECT_EQ(t.centre, Vec3(1, 2, 3));
  const YAML::Node truth = YAML::LoadFile((out / "truth.yaml").string());
  EXPECT_EQ(truth["betti"][2].as<int>(), 0);
  EXPECT_EQ(truth["reach_mm"].as<double>(), 6);
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
  s.kind = "genus2";
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
}

TEST(PhantomCommand, ExampleSpecsAreValid) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(fs::path(XSECT_SOURCE_DIR) / "configs/phantoms")) {
    if (e.path().extension() != ".yaml") continue;
    ++n;
    const PhantomSpec s = readPhantomSpec(e.path().string());
    EXPECT_FALSE(checkPhantomShape(s.shape).has_value()) << e.path();
  }
  EXPECT_GE(n, 11);
}

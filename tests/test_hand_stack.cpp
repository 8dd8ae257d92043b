// A slice stack written by hand in the slices.yaml format of docs/inputs.md (testdata/hand_stack) runs end to end.
// The images are disks drawn with OpenCV (16x supersampled, area-averaged): not the phantom tool.
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "io/mesh_io.h"

namespace fs = std::filesystem;
using namespace xsect;

namespace {

/// 64x64 image at 0.25 mm whose pixel (32, 32) is the disk centre; radius in mm.
void drawDisk(const fs::path& path, double radius_mm) {
  const int S = 16;
  cv::Mat big(64 * S, 64 * S, CV_8U, cv::Scalar(0));
  if (radius_mm > 0) {
    // pixel i centre = (I + 0.5)/S - 0.5 in fine pixels I; with 4 fractional bits (shift = 4)
    const double c = (32 + 0.5) * S - 0.5, r = radius_mm / 0.25 * S;
    cv::circle(big, cv::Point(int(std::lround(c * 16)), int(std::lround(c * 16))),
               int(std::lround(r * 16)), cv::Scalar(255), cv::FILLED, cv::LINE_8, 4);
  }
  cv::Mat small;
  cv::resize(big, small, cv::Size(64, 64), 0, 0, cv::INTER_AREA);
  fs::create_directories(path.parent_path());
  cv::imwrite(path.string(), small);
}

}  // namespace

TEST(HandStack, RunsEndToEnd) {
  const fs::path src = fs::path(XSECT_SOURCE_DIR) / "testdata/hand_stack";
  const fs::path dir = test::freshDir("hand");
  fs::copy(src / "slices.yaml", dir / "slices.yaml");
  fs::copy(src / "config.yaml", dir / "config.yaml");
  const double R = 6;
  char name[32];
  for (double z : {-4.5, -3.0, -1.5, 0.0, 1.5, 3.0, 4.5}) {
    std::snprintf(name, sizeof name, "images/z%+.1f.png", z);
    drawDisk(dir / name, std::sqrt(R * R - z * z));
  }
  for (double x : {-3.0, 0.0, 3.0}) {
    std::snprintf(name, sizeof name, "images/x%+.1f.png", x);
    drawDisk(dir / name, std::sqrt(R * R - x * x));
  }
  const auto r = test::runXsect("run " + (dir / "config.yaml").string() + " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  const fs::path out = dir / "out";
  for (const char* f : {"mesh.ply", "mesh.stl", "mesh.obj", "report.json", "manifest.json", "graph.json"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  const auto report = nlohmann::json::parse(std::ifstream(out / "report.json"));
  EXPECT_EQ(report["betti"], nlohmann::json::array({1, 0, 0}));
  EXPECT_EQ(report["counts"]["slices"], 10);
  EXPECT_EQ(report["counts"]["sections"], 10);
  const TriangleMesh mesh = readMesh((out / "mesh.ply").string());
  ASSERT_GT(mesh.triangles.size(), 100u);
  double worst = 0;
  for (const auto& v : mesh.vertices) worst = std::max(worst, std::abs(double(v.norm()) - R));
  // largest gap between neighbouring parallel planes: 3 mm (sagittal); axial 1.5 mm
  EXPECT_LT(worst, 3.0);
  fs::remove_all(dir);
}

TEST(HandStack, ConformalMeshCanBeSwitchedOff) {
  const fs::path src = fs::path(XSECT_SOURCE_DIR) / "testdata/hand_stack";
  const fs::path dir = test::freshDir("hand-noconf");
  fs::copy(src / "slices.yaml", dir / "slices.yaml");
  fs::copy(src / "config.yaml", dir / "config.yaml");
  char name[32];
  for (double z : {-4.5, -3.0, -1.5, 0.0, 1.5, 3.0, 4.5}) {
    std::snprintf(name, sizeof name, "images/z%+.1f.png", z);
    drawDisk(dir / name, std::sqrt(36 - z * z));
  }
  for (double x : {-3.0, 0.0, 3.0}) {
    std::snprintf(name, sizeof name, "images/x%+.1f.png", x);
    drawDisk(dir / name, std::sqrt(36 - x * x));
  }
  nlohmann::json reports[2];
  for (int on = 0; on < 2; ++on) {
    const auto r = test::runXsect("run " + (dir / "config.yaml").string() + " --quiet --out " +
                                  (dir / ("out" + std::to_string(on))).string() +
                                  " --set reconstruction.conformal_mesh=" + (on ? "true" : "false"));
    ASSERT_EQ(r.code, 0) << r.err;
    reports[on] = nlohmann::json::parse(std::ifstream(dir / ("out" + std::to_string(on)) / "report.json"));
    EXPECT_EQ(reports[on]["betti"], nlohmann::json::array({1, 0, 0}));
  }
  EXPECT_EQ(reports[0]["conformity"]["planes_cut"], 0);
  EXPECT_EQ(reports[1]["conformity"]["planes_cut"], 10);
  EXPECT_LT(reports[0]["counts"]["mesh_triangles"], reports[1]["counts"]["mesh_triangles"]);
  fs::remove_all(dir);
}

// Issue 48, "bounded work" and "no silent wrong answer": poses in metres with a millimetre voxel
// end in seconds; a run estimated past run.max_seconds, or past this machine's memory, is refused
// by `check` as by `run`; duplicated YAML keys, segmentation settings no image can take and
// coordinates beyond any acquisition are input errors naming the key; a series mixing 8- and
// 16-bit frames gives the sections of the same pictures stored at one depth.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <yaml-cpp/yaml.h>

#include <chrono>

#include "cli.h"
#include "io/file_hash.h"
#include "io/mesh_io.h"
#include "io/input_error.h"
#include "io/yaml_duplicate_keys.h"
#include "phantom_runs.h"
#include "pipeline/time_budget.h"

namespace fs = std::filesystem;
using namespace xsect;

namespace {

/// A sphere (radius 5 mm) cut by 3 x 4 planes, 0.25 mm pixels, in dir/ph.
fs::path sphere(const std::string& tag, const std::string& config = "{reconstruction: {voxel_size_mm: 0.5}}") {
  return test::phantom(tag,
                       "seed: 1\nshape: {kind: sphere, params: {radius: 5}}\npattern: {kind: multiaxial, count: 4}\n"
                       "image: {pixel_mm: 0.25}\nconfig: " + config + "\n");
}

/// The phantom's slices.yaml with every pose's first three rows multiplied by `factor` (the same
/// acquisition in other units: 0.001 turns millimetres into metres).
void scalePoses(const fs::path& slices, double factor) {
  YAML::Node root = YAML::LoadFile(slices.string());
  for (YAML::Node s : root["slices"])
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) s["image_to_world"][r][c] = s["image_to_world"][r][c].as<double>() * factor;
  std::ofstream(slices) << YAML::Dump(root) << "\n";
}

void expectInputError(const test::CliResult& r, const std::vector<std::string>& parts) {
  EXPECT_EQ(r.code, 2) << r.err;
  for (const auto& p : parts) EXPECT_NE(r.err.find(p), std::string::npos) << p << "\n" << r.err;
}

}  // namespace

TEST(SettingRefusals, PosesInMetresWithAMillimetreVoxelEndWithinSecondsAndAutoFitsThem) {
  const fs::path dir = sphere("metres");
  scalePoses(dir / "ph/slices.yaml", 1e-3);
  const std::string cfg = (dir / "ph/config.yaml").string();
  for (const std::string voxel : {"0.4", "0.05", "0.02"}) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto r = test::runXsect("run " + cfg + " --out " + (dir / "o").string() +
                                      " --quiet --set reconstruction.voxel_size_mm=" + voxel, 60);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_LT(s, 10.0) << voxel;
    // The sections are 0.01 wide: no voxel centre of these grids lies in them. At 40 times their
    // width, the message asks about units.
    expectInputError(r, {"reconstruction.voxel_size_mm", "or auto"});
    if (voxel == "0.4") EXPECT_NE(r.err.find("are the poses in other units"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "o"));
  }
  // The automatic voxel fits data in any units: the sphere, one solid without tunnels.
  const nlohmann::json rep = test::run(dir, "auto", "--set reconstruction.voxel_size_mm=auto");
  EXPECT_EQ(rep["betti"], nlohmann::json({1, 0, 0}));
  EXPECT_LT(rep["reconstruction"]["voxel_size"]["voxel_size_mm"].get<double>(), 0.001);
  fs::remove_all(dir);
}

TEST(SettingRefusals, CheckAndRunRefuseTheSameTimeAndMemory) {
  const fs::path dir = sphere("budget");
  const std::string cfg = (dir / "ph/config.yaml").string();
  // Time: the estimate exceeds run.max_seconds.
  for (const std::string cmd : {"check", "run"}) {
    const auto r = test::runXsect(cmd + " " + cfg + " --quiet --set run.max_seconds=0.01");
    expectInputError(r, {"run.max_seconds", "estimated to take", "reconstruction.voxel_size_mm"});
  }
  // Memory: a whole-volume smoothing on 4e10 voxels.
  std::string messages[2];
  int k = 0;
  for (const std::string cmd : {"check", "run"}) {
    const auto r = test::runXsect(cmd + " " + cfg + " --quiet --set reconstruction.voxel_size_mm=0.005 --set smoothing.method=shepard");
    expectInputError(r, {"reconstruction.voxel_size_mm", "more than this machine has"});
    messages[k++] = r.err;
  }
  EXPECT_EQ(messages[0], messages[1]);
  // check's estimate is in its JSON.
  const fs::path json = dir / "check.json";
  ASSERT_EQ(std::system((std::string(XSECT_BIN) + " check " + cfg + " --quiet --json > " + json.string()).c_str()), 0);
  const nlohmann::json c = test::readJson(json);
  EXPECT_GT(c["estimated_seconds"].get<double>(), 0.0);
  EXPECT_EQ(c["estimated_time_s"]["max_seconds"], 86400.0);
  EXPECT_FALSE(fs::exists(dir / "ph/out"));
  fs::remove_all(dir);
}

// The segmentation's time estimate reads lengths given in mm at the series' pixel, as the frames
// are segmented (pixel_settings.h), and counts the speckle filter and the shadows' beams: an
// estimate that read the ultrasound preset's mm settings as 0 pixels came out at a third of the run.
TEST(SettingRefusals, SegmentationEstimateReadsMillimetreSettingsAtThePixel) {
  const double pixels = 1e8;
  const Vec2 pixel(0.1, 0.1);
  SegmentationParams mm, px;
  mm.open_radius_mm = 1.0, mm.sigma_mm = 0.3;
  px.open_radius_px = 10, px.sigma_px = 3.0;
  EXPECT_DOUBLE_EQ(segmentSeconds(pixels, mm, pixel), segmentSeconds(pixels, px, pixel));
  EXPECT_GT(segmentSeconds(pixels, mm, pixel), segmentSeconds(pixels, SegmentationParams(), pixel));
  // No frame, no pixel: only settings in pixels count.
  EXPECT_DOUBLE_EQ(segmentSeconds(pixels, mm, Vec2::Zero()), segmentSeconds(pixels, SegmentationParams(), Vec2::Zero()));
  SegmentationParams median = mm, shadows = mm;
  median.speckle_filter_mm = 1.0;
  shadows.shadows = ShadowRule::unobserved;
  EXPECT_GT(segmentSeconds(pixels, median, pixel), segmentSeconds(pixels, mm, pixel));
  EXPECT_GT(segmentSeconds(pixels, shadows, pixel), segmentSeconds(pixels, mm, pixel));
}

TEST(SettingRefusals, DuplicatedKeysAreInputErrorsNamingBothLines) {
  const fs::path dir = sphere("duplicates");
  const fs::path ph = dir / "ph";
  // Two reconstruction blocks: the second's method used to be dropped silently.
  test::writeFile(ph / "twice.yaml",
                  "input:\n  slices: slices.yaml\nreconstruction:\n  voxel_size_mm: 0.5\noutput:\n  dir: out\n"
                  "reconstruction:\n  method: delaunay\n");
  expectInputError(test::runXsect("run " + (ph / "twice.yaml").string() + " --quiet"),
                   {"twice.yaml:7: reconstruction", "given twice (lines 3 and 7)"});
  expectInputError(test::runXsect("check " + (ph / "twice.yaml").string() + " --quiet"), {"given twice (lines 3 and 7)"});
  // A key twice inside one mapping, at depth.
  test::writeFile(ph / "inner.yaml", "input:\n  slices: slices.yaml\nsegmentation:\n  threshold: 100\n  threshold: 200\n");
  expectInputError(test::runXsect("run " + (ph / "inner.yaml").string() + " --quiet"),
                   {"inner.yaml:5: segmentation.threshold", "lines 4 and 5"});
  // A key twice in an entry of slices.yaml.
  std::string slices = test::slurp(ph / "slices.yaml");
  const std::size_t at = slices.find("    image_to_world:");
  slices.insert(at, "    image: images/001.png\n");
  test::writeFile(ph / "slices.yaml", slices);
  expectInputError(test::runXsect("run " + (ph / "config.yaml").string() + " --quiet"),
                   {"slices.yaml:", "slices[0].image", "given twice"});
  EXPECT_FALSE(fs::exists(ph / "out"));
  fs::remove_all(dir);
}

TEST(SettingRefusals, DuplicateKeyDetectionOnValidAndInvalidYaml) {
  // Valid: one key under two mappings, lists of mappings with the same keys, anchors and aliases
  // (alias keys are not compared), merge keys, flow mappings, two documents, complex keys.
  const std::vector<std::string> valid = {
      "a: {method: x}\nb: {method: y}\n",
      "slices:\n  - {image: a, fov: b}\n  - image: c\n    fov: d\n",
      "base: &b {x: 1}\nother:\n  <<: *b\n  <<: *b\n  y: 2\n",
      "k: &k name\n*k : 1\nname2: 2\n",
      "? [1, 2]\n: a\n? [1, 2]\n: b\n",
      "a: 1\n---\na: 2\n",
  };
  for (const std::string& t : valid) EXPECT_NO_THROW(checkNoDuplicateKeys(t, "t.yaml")) << t;
  struct Bad {
    std::string text, key;
    int line;
  };
  const std::vector<Bad> bad = {
      {"a: {x: 1, x: 2}\n", "a.x", 1},
      {"l:\n  - {p: 1}\n  - p: 1\n    q: 2\n    p: 3\n", "l[1].p", 5},
      {"a:\n  b:\n    c: 1\n  b: 2\n", "a.b", 4},
  };
  for (const Bad& b : bad) {
    try {
      checkNoDuplicateKeys(b.text, "t.yaml");
      ADD_FAILURE() << b.text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), b.key) << b.text;
      EXPECT_EQ(e.line(), b.line) << b.text;
    }
  }
}

TEST(SettingRefusals, SegmentationSettingsNoImageCanTakeNameTheirKey) {
  const fs::path dir = sphere("segmentation");
  const std::string cfg = (dir / "ph/config.yaml").string();
  // The limits follow each image's size and field of view.
  struct Case {
    std::string set, key, why;
  };
  const std::vector<Case> cases = {
      {"segmentation.min_area_mm2=1e6", "segmentation.min_area_mm2", "at or above the image's observed area"},
      {"segmentation.min_area_mm2=1e300", "segmentation.min_area_mm2", "at or above the image's observed area"},
      {"segmentation.sigma_px=1e9", "segmentation.sigma_px", "beyond the image"},
      {"segmentation.close_radius_px=1e9", "segmentation.close_radius_px", "larger than any image"},
      {"segmentation.close_radius_px=100000", "segmentation.close_radius_px", "does not fit in the image"},
      {"segmentation.open_radius_px=1e30", "segmentation.open_radius_px", "larger than any image"},
      {"segmentation.open_radius_px=5000", "segmentation.open_radius_px", "does not fit in the image"},
  };
  for (const Case& c : cases)
    for (const std::string cmd : {"check", "run"}) {
      const auto r = test::runXsect(cmd + " " + cfg + " --quiet --set " + c.set, 60);
      expectInputError(r, {c.key, c.why});
      EXPECT_EQ(r.err.find("OpenCV"), std::string::npos) << r.err;
    }
  // A minimum area below the image's keeps the sphere.
  const nlohmann::json rep = test::run(dir, "small-area", "--set segmentation.min_area_mm2=0.5");
  EXPECT_EQ(rep["betti"], nlohmann::json({1, 0, 0}));
  fs::remove_all(dir);
}

TEST(SettingRefusals, CoordinatesBeyondAnyAcquisitionNameTheirLine) {
  const fs::path dir = sphere("coordinates");
  const fs::path ph = dir / "ph";
  // A translation of 1e300 in slices.yaml.
  std::string slices = test::slurp(ph / "slices.yaml");
  const std::size_t row = slices.find("      - [", slices.find("image_to_world:"));
  const std::size_t last = slices.rfind(',', slices.find(']', row));
  slices.replace(last + 1, slices.find(']', row) - last - 1, " 1e300");
  test::writeFile(ph / "slices.yaml", slices);
  expectInputError(test::runXsect("run " + (ph / "config.yaml").string() + " --quiet"),
                   {"slices[0].image_to_world[0][3]", "beyond any acquisition"});
  // A vertex of 1e308 in a .csl.
  test::writeFile(dir / "c/input.csl",
                  "CSLC\n2 1\n\n1 3 1 0 0 1 -1\n0 0 1\n1e308 0 1\n0 1 1\n3 1 0 1 2\n\n"
                  "2 3 1 0 0 1 -2\n0 0 2\n1 0 2\n0 1 2\n3 1 0 1 2\n");
  test::writeFile(dir / "c/config.yaml", "input:\n  csl: input.csl\n");
  expectInputError(test::runXsect("run " + (dir / "c/config.yaml").string() + " --quiet"),
                   {"input.csl:6", "vertex 1", "beyond any acquisition"});
  fs::remove_all(dir);
}

TEST(SettingRefusals, FramesOfOtherBitDepthsGiveTheSectionsOfTheSamePicturesAtOneDepth) {
  // Each case: the phantom's frames all at one depth (the reference) against the same pictures
  // with some frames stored at the other depth (full range to full range: v16 = 257 v8).
  const fs::path dir = sphere("depths");
  const fs::path ph = dir / "ph";
  std::vector<fs::path> images;
  for (const auto& e : fs::directory_iterator(ph / "images"))
    if (e.path().filename().string() != "fov.png") images.push_back(e.path());
  std::sort(images.begin(), images.end());
  ASSERT_GE(images.size(), 12u);
  const auto store = [&](const fs::path& p, int bits) {
    cv::Mat m = cv::imread(p.string(), cv::IMREAD_UNCHANGED);
    if (bits == 16 && m.depth() == CV_8U) m.convertTo(m, CV_16U, 257.0);
    if (bits == 8 && m.depth() == CV_16U) m.convertTo(m, CV_8U, 1.0 / 257.0);
    ASSERT_TRUE(cv::imwrite(p.string(), m));
  };
  const auto meshOf = [&](const std::string& out, const std::string& sets, std::string* warnings) {
    const nlohmann::json rep = test::run(dir, out, "--set reconstruction.voxel_size_mm=0.5 " + sets);
    *warnings = rep["warnings"].dump();
    return sha256File((dir / out / "mesh.ply").string());  // compared by hash: a mesh is binary
  };
  for (const std::string method : {"segmentation.method=otsu", "segmentation.threshold=128"}) {
    std::string w;
    // 8-bit series with its first frame at 16 bits; the majority (8) is the series' depth.
    for (const auto& p : images) store(p, 8);
    const std::string all8 = meshOf("all8", "--set " + method, &w);
    EXPECT_EQ(w.find("mixes 8- and 16-bit"), std::string::npos) << w;
    store(images[0], 16);
    const std::string first16 = meshOf("first16", "--set " + method, &w);
    EXPECT_EQ(first16, all8) << method;
    EXPECT_NE(w.find("mixes 8- and 16-bit"), std::string::npos) << w;
    EXPECT_NE(w.find("/ 257"), std::string::npos) << w;
    // 16-bit series (threshold in 16-bit units) with its first frame at 8 bits.
    for (const auto& p : images) store(p, 16);
    const std::string sets16 = method == "segmentation.threshold=128" ? "segmentation.threshold=32896" : method;
    const std::string all16 = meshOf("all16", "--set " + sets16, &w);
    store(images[0], 8);
    const std::string first8 = meshOf("first8", "--set " + sets16, &w);
    EXPECT_EQ(first8, all16) << method;
    EXPECT_NE(w.find("x 257"), std::string::npos) << w;
    // The same pictures at either depth, with the threshold in that depth's units (Otsu's
    // finds its own): the same sections, to the sub-pixel offset the contour tracer gives grey
    // levels exactly at the threshold (1e-6 of a grey level, not scaled with the depth).
    const TriangleMesh m8 = readMesh((dir / "all8/mesh.ply").string()), m16 = readMesh((dir / "all16/mesh.ply").string());
    ASSERT_EQ(m8.vertices.size(), m16.vertices.size()) << method;
    EXPECT_EQ(m8.triangles, m16.triangles) << method;
    double worst = 0;
    for (std::size_t v = 0; v < m8.vertices.size(); ++v) worst = std::max(worst, double((m8.vertices[v] - m16.vertices[v]).norm()));
    EXPECT_LT(worst, 1e-4) << method;
    for (const auto& p : images) store(p, 8);
  }
  fs::remove_all(dir);
}

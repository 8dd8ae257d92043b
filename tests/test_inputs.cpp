// Invalid input is rejected where it enters: exit code 2, a message naming the file and the key,
// and no output folder. Every reader is exercised with malformed files.
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <nlohmann/json.hpp>

#include "cli.h"
#include "io/csl_file.h"
#include "io/image_io.h"
#include "io/input_error.h"
#include "io/run_config.h"
#include "io/slices_file.h"

namespace fs = std::filesystem;
using namespace xsect;

namespace {

const char* kPose = "[[0.5, 0, 0, -10], [0, 0.5, 0, -10], [0, 0, 0, 0], [0, 0, 0, 1]]";

/// A valid little input: two slices with a disk, a config writing to DIR/out.
fs::path validInput() {
  const fs::path d = test::freshDir("inputs");
  cv::Mat img(40, 40, CV_8U, cv::Scalar(0));
  for (int j = 0; j < 40; ++j)
    for (int i = 0; i < 40; ++i)
      if ((i - 20) * (i - 20) + (j - 20) * (j - 20) < 64) img.at<unsigned char>(j, i) = 255;
  fs::create_directories(d / "images");
  cv::imwrite((d / "images/a.png").string(), img);
  cv::imwrite((d / "images/b.png").string(), img);
  test::writeFile(d / "slices.yaml", std::string("slices:\n  - image: images/a.png\n    image_to_world: ") +
                                         kPose + "\n  - image: images/b.png\n    image_to_world: " +
                                         "[[0.5, 0, 0, -10], [0, 0.5, 0, -10], [0, 0, 0, 2], [0, 0, 0, 1]]\n");
  test::writeFile(d / "config.yaml",
                  "input:\n  slices: slices.yaml\nreconstruction:\n  voxel_size_mm: 0.5\n"
                  "output:\n  dir: out\n  mesh: [ply]\n");
  return d;
}

void expectRejected(const fs::path& dir, const std::string& mustMention, const std::string& extra = "") {
  const auto r = test::runXsect("run " + (dir / "config.yaml").string() + " --quiet " + extra);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find(mustMention), std::string::npos) << "message: " << r.err;
  EXPECT_FALSE(fs::exists(dir / "out")) << "output folder left behind";
}

std::string slicesWithPose(const std::string& pose) {
  return std::string("slices:\n  - image: images/a.png\n    image_to_world: ") + pose + "\n";
}

}  // namespace

TEST(Inputs, ValidInputRuns) {
  const fs::path d = validInput();
  const auto r = test::runXsect("run " + (d / "config.yaml").string() + " --quiet");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(d / "out/mesh.ply"));
  // nothing else left beside the output (no staging folder)
  int entries = 0;
  for (const auto& e : fs::directory_iterator(d)) entries += e.path().filename().string()[0] == '.';
  EXPECT_EQ(entries, 0);
  fs::remove_all(d);
}

TEST(Inputs, ConfigErrorsNameTheKey) {
  struct Case { std::string config, mention; };
  const std::vector<Case> cases = {
      {"input: [unclosed\n", "not valid YAML"},
      {"reconstruction:\n  voxel_size_mm: 0.5\n", "input"},
      {"input:\n  slices: nothere.yaml\n", "input.slices"},
      {"input:\n  slices: slices.yaml\nreconstruction:\n  method: marching\n", "reconstruction.method"},
      {"input:\n  slices: slices.yaml\nreconstruction:\n  voxel_size_mm: -1\n", "reconstruction.voxel_size_mm"},
      {"input:\n  slices: slices.yaml\nreconstruction:\n  voxel_size_mm: abc\n", "reconstruction.voxel_size_mm"},
      {"input:\n  slices: slices.yaml\nreconstruction:\n  voxel_size_mm: .nan\n", "not finite"},
      {"input:\n  slices: slices.yaml\nsegmentation:\n  method: kmeans\n", "segmentation.method"},
      {"input:\n  slices: slices.yaml\nsegmentation:\n  threshold: [1, 2]\n", "segmentation.threshold"},
      {"input:\n  slices: slices.yaml\nconformity:\n  enforce: maybe\n", "conformity.enforce"},
      {"input:\n  slices: slices.yaml\nreconstruction:\n  conformal_mesh: 2x\n", "reconstruction.conformal_mesh"},
      {"input:\n  slices: slices.yaml\noutput:\n  mesh: [vtk]\n  dir: out\n", "output.mesh"},
      {"input:\n  slices: slices.yaml\n  csl: x.csl\n", "input"},
      {"input:\n  slices: slices.yaml\nreconstruction: 3\n", "reconstruction"},
      // Typos stop the run before any work, at the key's line, with the key they were meant to be.
      {"input:\n  slices: slices.yaml\nreconstruction:\n  voxle_size_mm: 0.5\n",
       "config.yaml:4: reconstruction.voxle_size_mm: unknown key (did you mean 'reconstruction.voxel_size_mm'?)"},
      {"input:\n  slices: slices.yaml\nvoxel_size_mm: 0.5\n",
       "unknown key (did you mean 'reconstruction.voxel_size_mm'?)"},
      {"input:\n  slices: slices.yaml\nsegmentaton:\n  threshold: 3\n", "did you mean 'segmentation'?"},
      {"input:\n  slices: slices.yaml\nreconstruction:\n  method: nearest_plan\n", "did you mean 'nearest_plane'?"},
      {"input:\n  slices: slices.yaml\nsmoothing:\n  methd: shepard\n  exponant: 2\n",
       "also unknown: 'smoothing.exponant' (line 5) (did you mean 'smoothing.exponent'?)"},
      {"input:\n  slices: slices.yaml\ncolour: blue\n", "colour: unknown key"},
  };
  for (const auto& c : cases) {
    const fs::path d = validInput();
    // One output block (a second would be a duplicated key, refused before the key under test).
    const bool hasOutput = c.config.find("output:") != std::string::npos;
    test::writeFile(d / "config.yaml", c.config + (hasOutput ? "" : "output:\n  dir: out\n"));
    SCOPED_TRACE(c.config);
    expectRejected(d, c.mention);
    expectRejected(d, "config.yaml");
    fs::remove_all(d);
  }
}

TEST(Inputs, SetOverridesAreValidatedToo) {
  const fs::path d = validInput();
  // An error in a --set value names the option as typed, not a line of config.yaml.
  expectRejected(d, "error: --set reconstruction.voxel_size_mm=0: must be", "--set reconstruction.voxel_size_mm=0");
  expectRejected(d, "--set", "--set novalue");
  expectRejected(d, "error: --set extra.key=1: extra: unknown key", "--set extra.key=1");
  expectRejected(d, "error: --set reconstruction.voxle_size_mm=1: unknown key (did you mean "
                    "'reconstruction.voxel_size_mm'?)", "--set reconstruction.voxle_size_mm=1");
  const RunConfig c = readRunConfig((d / "config.yaml").string(),
                                    {"reconstruction.voxel_size_mm=0.75", "segmentation.threshold=90"});
  EXPECT_DOUBLE_EQ(c.voxel_size_mm, 0.75);
  EXPECT_DOUBLE_EQ(c.segmentation.threshold, 90);
  EXPECT_TRUE(c.warnings.empty());
  EXPECT_EQ(c.input_path, (d / "slices.yaml").lexically_normal().string());
  // Method 3's choice of what to do with tunnels within a cell (cell_tunnels.h): read, no warning.
  EXPECT_EQ(readRunConfig((d / "config.yaml").string(), {}).cell_tunnels, CellTunnels::cut);
  for (const auto& [name, value] : {std::pair{"keep", CellTunnels::keep}, std::pair{"cut", CellTunnels::cut}}) {
    const RunConfig t = readRunConfig((d / "config.yaml").string(), {std::string("reconstruction.cell_tunnels=") + name});
    EXPECT_EQ(t.cell_tunnels, value) << name;
    EXPECT_TRUE(t.warnings.empty()) << t.warnings.front();
  }
  expectRejected(d, "reconstruction.cell_tunnels", "--set reconstruction.cell_tunnels=fill");
  fs::remove_all(d);
}

TEST(Inputs, SlicesErrorsNameTheSliceAndKey) {
  struct Case { std::string slices, mention; };
  const std::vector<Case> cases = {
      {"slices: []\n", "slices"},
      {"images: []\n", "slices"},
      {"slices:\n  - image_to_world: [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]\n", "slices[0].image"},
      {"slices:\n  - image: images/missing.png\n    image_to_world: [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]\n",
       "file not found"},
      {"slices:\n  - image: images/a.png\n", "slices[0].image_to_world"},
      {slicesWithPose("[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]"), "4x4"},
      {slicesWithPose("[[1, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]"), "slices[0].image_to_world[0]"},
      {slicesWithPose("[[1, 0, 0, .nan], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]"), "not finite"},
      {slicesWithPose("[[1, 0, 0, x], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]"), "slices[0].image_to_world[0][3]"},
      {slicesWithPose("[[0, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]"), "zero pixel spacing"},
      {slicesWithPose("[[1, 2, 0, 0], [0, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]"), "singular"},
      {slicesWithPose("[[1, 1, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]"), "not orthogonal"},
      {slicesWithPose("[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]]"), "last row"},
      {"slices:\n  - image: images/a.png\n    image_to_world: [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]\n    fov: images/nofov.png\n",
       "slices[0].fov"},
  };
  for (const auto& c : cases) {
    const fs::path d = validInput();
    test::writeFile(d / "slices.yaml", c.slices);
    SCOPED_TRACE(c.slices);
    EXPECT_THROW(readSlicesFile((d / "slices.yaml").string()), InputError);
    expectRejected(d, c.mention);
    expectRejected(d, "slices.yaml");
    fs::remove_all(d);
  }
}

TEST(Inputs, LineNumbersAreReported) {
  const fs::path d = validInput();
  test::writeFile(d / "slices.yaml", slicesWithPose("[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]") +
                                         "  - image: images/b.png\n    image_to_world: [[1, 0, 0, 0], [0, 1, 0, 0]]\n");
  try {
    readSlicesFile((d / "slices.yaml").string());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "slices[1].image_to_world");
    EXPECT_EQ(e.line(), 5);
  }
  fs::remove_all(d);
}

TEST(Inputs, BadImagesAreRejected) {
  const fs::path d = validInput();
  test::writeFile(d / "images/a.png", "this is not a png");
  expectRejected(d, "slices[0].image");
  cv::Mat colour(10, 10, CV_8UC3, cv::Scalar(1, 2, 3));
  cv::imwrite((d / "images/a.png").string(), colour);
  expectRejected(d, "channels");
  EXPECT_THROW(readGreyImage((d / "images/a.png").string(), "s.yaml", "k"), InputError);
  cv::Mat grey16(10, 10, CV_16U, cv::Scalar(1000));
  cv::imwrite((d / "images/c.png").string(), grey16);
  EXPECT_EQ(readGreyImage((d / "images/c.png").string(), "s.yaml", "k").depth(), CV_16U);
  // a field-of-view mask of another size
  cv::imwrite((d / "images/a.png").string(), cv::Mat(40, 40, CV_8U, cv::Scalar(0)));
  cv::imwrite((d / "images/fov.png").string(), cv::Mat(20, 20, CV_8U, cv::Scalar(255)));
  test::writeFile(d / "slices.yaml", slicesWithPose(kPose) + "    fov: images/fov.png\n");
  expectRejected(d, "slices[0].fov");
  fs::remove_all(d);
}

TEST(Inputs, NoSectionAnywhereIsAnInputError) {
  const fs::path d = validInput();
  cv::imwrite((d / "images/a.png").string(), cv::Mat(40, 40, CV_8U, cv::Scalar(0)));
  cv::imwrite((d / "images/b.png").string(), cv::Mat(40, 40, CV_8U, cv::Scalar(0)));
  expectRejected(d, "no section");
  fs::remove_all(d);
}

TEST(Inputs, MalformedCslFiles) {
  const fs::path d = test::freshDir("csl");
  const std::string good =
      "CSLC\n2 1\n\n1 4 1 0 0 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 1 0 1 2 3\n\n2 0 0 0 0 1 -1\n";
  test::writeFile(d / "good.csl", good);
  const auto planes = readCslFile((d / "good.csl").string());
  ASSERT_EQ(planes.size(), 2u);
  EXPECT_EQ(planes[0].sections.size(), 1u);
  EXPECT_TRUE(planes[1].sections.empty());
  EXPECT_NEAR(std::abs(planes[1].plane.origin.z()), 1.0, 1e-12);
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"CSLX\n1 1\n", "header"},
      {"CSLC\n2 1\n1 4 1 0 0 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 1 0 1 2 3\n", "end of file"},
      {"CSLC\n1 1\n1 3 1 0 0 1 0\n0 0 0\n1 0 zz\n1 1 0\n3 1 0 1 2\n", "expected a number"},
      {"CSLC\n1 1\n1 3 1 0 0 1 0\n0 0 0\n1 0 0\n1 1 0\n3 1 0 1 7\n", "out of range"},
      {"CSLC\n1 1\n1 3 1 0 0 0 0\n0 0 0\n1 0 0\n1 1 0\n3 1 0 1 2\n", "normal"},
      {"CSLC\n1 1\n1 3 1 0 0 1 0\n0 0 0\n1 0 0\n1 1 5\n3 1 0 1 2\n", "one plane"},
  };
  for (const auto& [text, mention] : bad) {
    test::writeFile(d / "bad.csl", text);
    SCOPED_TRACE(text);
    try {
      readCslFile((d / "bad.csl").string());
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("bad.csl"), std::string::npos) << e.what();
    }
  }
  test::writeFile(d / "config.yaml", "input:\n  csl: bad.csl\noutput:\n  dir: out\n");
  expectRejected(d, "bad.csl");
  fs::remove_all(d);
}

TEST(Inputs, SlicesFileRoundTripsExactly) {
  const fs::path d = validInput();
  auto slices = readSlicesFile((d / "slices.yaml").string());
  slices[0].image_to_world(0, 3) = -12.8;  // not representable: must still round-trip exactly
  slices[1].image_to_world(1, 1) = 0.1 + 0.2;
  writeSlicesFile((d / "copy.yaml").string(), slices);
  const auto back = readSlicesFile((d / "copy.yaml").string());
  ASSERT_EQ(back.size(), slices.size());
  for (std::size_t i = 0; i < back.size(); ++i) {
    EXPECT_EQ(back[i].image, slices[i].image);
    EXPECT_TRUE(back[i].image_to_world == slices[i].image_to_world) << i;
  }
  std::ifstream f(d / "copy.yaml");
  const std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("-12.8]"), std::string::npos) << "shortest text expected:\n" << text;
  fs::remove_all(d);
}

TEST(Inputs, MissingScalarIsAnInputErrorNotACrash) {
  const fs::path d = validInput();
  // a key present with no value (null) and a missing nested map value
  test::writeFile(d / "config.yaml", "input:\n  slices: slices.yaml\nreconstruction:\n  voxel_size_mm:\n");
  expectRejected(d, "reconstruction.voxel_size_mm");
  test::writeFile(d / "slices.yaml", "slices:\n  - image:\n    image_to_world: [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]\n");
  test::writeFile(d / "config.yaml", "input:\n  slices: slices.yaml\n");
  expectRejected(d, "slices[0].image");
  fs::remove_all(d);
}

TEST(Inputs, CheckValidatesWithoutWriting) {
  const fs::path d = validInput();
  const fs::path out = d / "check.json";
  const int status = std::system((std::string(XSECT_BIN) + " check " + (d / "config.yaml").string() +
                                  " --quiet --json > " + out.string()).c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  const auto j = nlohmann::json::parse(std::ifstream(out));
  // Without --json, a few lines a reader takes in at a glance, from the same diagnosis.
  const auto summary = test::runXsect("check " + (d / "config.yaml").string() + " --quiet");
  EXPECT_EQ(summary.code, 0) << summary.err;
  for (const std::string says : {"config.yaml: valid\n", "input: 2 slices, 2 sections\n", "grid: 0.5000 mm voxels (configured)",
                                 "estimated: ", "sampling: ", "--json\n"})
    EXPECT_NE(summary.out.find(says), std::string::npos) << says << " in\n" << summary.out;
  EXPECT_LT(std::count(summary.out.begin(), summary.out.end(), '\n'), 12) << summary.out;
  EXPECT_TRUE(j["valid"].get<bool>());
  EXPECT_EQ(j["counts"]["slices"], 2);
  EXPECT_EQ(j["counts"]["sections"], 2);
  EXPECT_GT(j["estimated_voxels"].get<double>(), 0);
  EXPECT_FALSE(fs::exists(d / "out"));  // check never reconstructs or writes outputs
  // the grid check announces is the grid run builds
  ASSERT_EQ(test::runXsect("run " + (d / "config.yaml").string() + " --quiet").code, 0);
  const auto report = nlohmann::json::parse(std::ifstream(d / "out/report.json"));
  EXPECT_EQ(j["grid_dims"], report["reconstruction"]["grid_dims"]);
  EXPECT_EQ(j["estimated_voxels"], report["counts"]["voxels"]);
  test::writeFile(d / "slices.yaml", slicesWithPose("[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]"));
  const auto r = test::runXsect("check " + (d / "config.yaml").string() + " --quiet");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("slices[0].image_to_world"), std::string::npos) << r.err;
  fs::remove_all(d);
}

TEST(Inputs, UnknownSliceKeysAreWarnedAbout) {
  const fs::path d = validInput();
  test::writeFile(d / "slices.yaml", slicesWithPose(kPose) + "    timestamp_s: 12.5\n");
  std::vector<std::string> warnings;
  EXPECT_EQ(readSlicesFile((d / "slices.yaml").string(), &warnings).size(), 1u);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("slices[0].timestamp_s"), std::string::npos) << warnings[0];
  const auto r = test::runXsect("run " + (d / "config.yaml").string() + " --quiet");
  EXPECT_EQ(r.code, 0) << r.err;
  const auto report = nlohmann::json::parse(std::ifstream(d / "out/report.json"));
  bool found = false;
  for (const auto& w : report["warnings"]) found = found || w.get<std::string>().find("timestamp_s") != std::string::npos;
  EXPECT_TRUE(found);
  fs::remove_all(d);
}

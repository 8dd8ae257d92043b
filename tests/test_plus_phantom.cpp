// Phantoms written as PLUS recordings (`plus: true` in the spec, io/meta_image_writer.h): the
// recording reads back as the same frames with the same poses as slices.yaml, so that `xsect run`
// on config_plus.yaml reconstructs what it reconstructs from config.yaml (the same segmented
// pixels, the same mesh); a recording with a frame's pose missing is refused naming the field, one
// whose pose is INVALID skips that frame.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "io/meta_image.h"
#include "io/meta_image_writer.h"
#include "io/plus_sequence.h"
#include "io/slices_file.h"
#include "phantom_runs.h"

namespace xsect {
namespace {

namespace fs = std::filesystem;
using test::freshDir;
using test::readJson;
using test::runXsect;
using test::slurp;
using test::writeFile;

/// A torus cut by 30 parallel planes tilted by up to 4 degrees; 0.3 mm pixels (not a power of two:
/// removing the pixel scaling from the poses is not trivially exact).
const std::string kTorusSpec =
    "seed: 3\n"
    "shape: {kind: torus, params: {major_radius: 12, minor_radius: 4}, rotation_deg: [10, 0, 0]}\n"
    "pattern: {kind: parallel, count: 30, direction: [0.1, 0, 1], tilt_deg: 4}\n"
    "image: {pixel_mm: 0.3}\n"
    "config: {reconstruction: {voxel_size_mm: 0.4}}\n"
    "plus: true\n";

/// `xsect run CONFIG --out dir/out --quiet`: its report.json.
nlohmann::json runConfig(const fs::path& config, const fs::path& out) {
  const auto r = runXsect("run " + config.string() + " --out " + out.string() + " --quiet");
  EXPECT_EQ(r.code, 0) << r.err;
  return readJson(out / "report.json");
}

/// The number of vertices a binary or ASCII PLY header declares.
long plyVertices(const fs::path& ply) {
  std::ifstream in(ply, std::ios::binary);
  std::string line;
  while (std::getline(in, line) && line != "end_header")
    if (line.rfind("element vertex ", 0) == 0) return std::stol(line.substr(15));
  return -1;
}

/// The recording's poses (in file order) against slices.yaml's: equal, up to one unit in the last
/// place where no probe matrix times the pixel size gives the recorded entry back exactly.
void expectSamePoses(const fs::path& ph) {
  const PlusSequence seq = readPlusSequence((ph / "sequence.igs.mha").string(), (ph / "deviceset.xml").string(),
                                            "Reference");
  std::vector<std::string> warnings;
  const std::vector<SliceRecord> slices = readSlicesFile((ph / "slices.yaml").string(), &warnings);
  ASSERT_EQ(seq.frames.size(), slices.size());
  ASSERT_EQ(seq.header.frames, int(slices.size()));
  int inexact = 0;
  for (std::size_t k = 0; k < slices.size(); ++k) {
    EXPECT_EQ(seq.frames[k], int(k));
    const Mat4& a = seq.image_to_reference[k];
    const Mat4& b = slices[k].image_to_world;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) {
        if (a(r, c) == b(r, c)) continue;
        ++inexact;
        EXPECT_LE(std::abs(a(r, c) - b(r, c)), 2e-16 * std::max(1.0, std::abs(b(r, c)))) << k << " " << r << c;
      }
  }
  // Rare (a few % of the rotation entries: where fl(y * pixel_mm) misses x for every double y).
  EXPECT_LE(inexact, 9 * int(slices.size()) / 4);
  // The frames are the PNG files' pixels.
  MetaImageFrames frames(seq.header);
  for (std::size_t k = 0; k < slices.size(); ++k) {
    const cv::Mat png = cv::imread(slices[k].image_resolved, cv::IMREAD_UNCHANGED);
    const cv::Mat mha = orientedFrame(seq, frames.next());
    ASSERT_EQ(png.size(), mha.size());
    ASSERT_EQ(cv::norm(png, mha, cv::NORM_INF), 0) << "frame " << k;
  }
}

TEST(PlusPhantom, PngAndPlusRunsReconstructTheSameSolid) {
  const fs::path dir = test::phantom("plus-torus", kTorusSpec);
  const fs::path ph = dir / "ph";
  for (const char* f : {"sequence.igs.mha", "deviceset.xml", "config_plus.yaml", "config.yaml", "slices.yaml"})
    ASSERT_TRUE(fs::exists(ph / f)) << f;
  const MetaImageHeader h = readMetaImageHeader((ph / "sequence.igs.mha").string());
  EXPECT_TRUE(h.compressed);
  EXPECT_EQ(h.frames, 30);
  EXPECT_EQ(h.orientation, "MFA");
  EXPECT_EQ(h.field("Kinds"), "domain domain list");
  EXPECT_EQ(*frameField(h, 3, "ProbeToTrackerTransformStatus"), "OK");
  EXPECT_DOUBLE_EQ(*frameNumber(h, 3, "Timestamp"), 0.15);
  // ProbeToTracker is rigid: the pixel scaling is all in the device set's ImageToProbe.
  for (int f = 0; f < h.frames; ++f) {
    const Mat4 m = *frameMatrix(h, f, "ProbeToTrackerTransform");
    const Eigen::Matrix3d R = m.block<3, 3>(0, 0);
    EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-12) << f;
    EXPECT_GT(R.determinant(), 0) << f;
  }
  expectSamePoses(ph);

  const nlohmann::json png = runConfig(ph / "config.yaml", dir / "png");
  const nlohmann::json plus = runConfig(ph / "config_plus.yaml", dir / "plus");
  EXPECT_EQ(png["betti"], plus["betti"]);
  EXPECT_EQ(png["betti"], nlohmann::json({1, 1, 0}));
  EXPECT_EQ(png["counts"]["sections"], plus["counts"]["sections"]);
  EXPECT_EQ(png["counts"]["slices"], plus["counts"]["slices"]);
  EXPECT_EQ(plus["plus_sequence"]["frames_used"], 30);
  const long vp = plyVertices(dir / "png/mesh.ply"), vq = plyVertices(dir / "plus/mesh.ply");
  ASSERT_GT(vp, 0);
  EXPECT_LE(std::abs(vp - vq), vp / 100);
  // The same pixels and poses: the same solid, bit for bit.
  EXPECT_EQ(slurp(dir / "png/mesh.ply"), slurp(dir / "plus/mesh.ply"));
  EXPECT_EQ(slurp(dir / "png/labels.nrrd"), slurp(dir / "plus/labels.nrrd"));
  fs::remove_all(dir);
}

TEST(PlusPhantom, SectorBecomesTheFanAndDroppedFramesAreOmitted) {
  const fs::path dir = test::phantom(
      "plus-sector",
      "seed: 5\n"
      "shape: {kind: sphere, params: {radius: 5}}\n"
      "pattern: {kind: freehand, count: 24, direction: [0, 0, 1], sector: true}\n"
      "image: {pixel_mm: 0.15, width: 120, height: 90}\n"
      "degradations: {drop_probability: 0.25, pose_jitter_mm: 0.05, pose_jitter_deg: 0.1}\n"
      "config: {reconstruction: {voxel_size_mm: 0.3}}\n"
      "plus: true\n");
  const fs::path ph = dir / "ph";
  const PlusSequence seq =
      readPlusSequence((ph / "sequence.igs.mha").string(), (ph / "deviceset.xml").string(), "Reference");
  ASSERT_TRUE(seq.device_set.fan.has_value());
  EXPECT_FALSE(seq.device_set.clip_size.has_value());
  const cv::Mat fov = cv::imread((ph / "images/fov.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(seq.field_of_view.empty());
  ASSERT_EQ(fov.size(), seq.field_of_view.size());
  EXPECT_EQ(cv::norm(fov, seq.field_of_view, cv::NORM_INF), 0);
  expectSamePoses(ph);  // the dropped frames are left out of both
  EXPECT_LT(seq.header.frames, 24);
  // Timestamps keep the pattern's clock: a dropped frame leaves a gap.
  double last = -1;
  for (int f = 0; f < seq.header.frames; ++f) {
    const double t = *frameNumber(seq.header, f, "Timestamp");
    EXPECT_GT(t, last);
    last = t;
  }
  const nlohmann::json png = runConfig(ph / "config.yaml", dir / "png");
  const nlohmann::json plus = runConfig(ph / "config_plus.yaml", dir / "plus");
  EXPECT_EQ(png["betti"], plus["betti"]);
  EXPECT_EQ(png["counts"]["sections"], plus["counts"]["sections"]);
  EXPECT_EQ(plus["plus_sequence"]["field_of_view"], true);
  EXPECT_EQ(slurp(dir / "png/mesh.ply"), slurp(dir / "plus/mesh.ply"));
  fs::remove_all(dir);
}

/// The recording's header with `edit` applied to its text (the pixel data untouched).
void editHeader(const fs::path& from, const fs::path& to, const std::function<void(std::string&)>& edit) {
  const std::string all = slurp(from);
  const std::string marker = "ElementDataFile = LOCAL\n";
  const std::size_t end = all.find(marker);
  ASSERT_NE(end, std::string::npos);
  std::string head = all.substr(0, end + marker.size());
  edit(head);
  std::ofstream(to, std::ios::binary) << head << all.substr(end + marker.size());
}

TEST(PlusPhantom, MalformedRecordingIsRefusedAndAnInvalidPoseSkipsItsFrame) {
  const fs::path dir = test::phantom("plus-bad", kTorusSpec);
  const fs::path ph = dir / "ph";
  const fs::path good = ph / "sequence.igs.mha", saved = dir / "good.igs.mha";
  fs::copy_file(good, saved);

  // Frame 3 without its ProbeToTrackerTransform line: exit 2, the field named, no output folder.
  editHeader(saved, good, [](std::string& head) {
    const std::string key = "Seq_Frame0003_ProbeToTrackerTransform = ";
    const std::size_t at = head.find(key);
    ASSERT_NE(at, std::string::npos);
    head.erase(at, head.find('\n', at) + 1 - at);
  });
  {
    const fs::path out = dir / "missing";
    const auto r = runXsect("run " + (ph / "config_plus.yaml").string() + " --out " + out.string());
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("Seq_Frame0003_ProbeToTrackerTransform"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
  }

  // Frame 3's pose INVALID: the run goes on without it.
  editHeader(saved, good, [](std::string& head) {
    const std::string key = "Seq_Frame0003_ProbeToTrackerTransformStatus = OK";
    const std::size_t at = head.find(key);
    ASSERT_NE(at, std::string::npos);
    head.replace(at, key.size(), "Seq_Frame0003_ProbeToTrackerTransformStatus = INVALID");
  });
  const nlohmann::json rep = runConfig(ph / "config_plus.yaml", dir / "invalid");
  EXPECT_EQ(rep["plus_sequence"]["frames"], 30);
  EXPECT_EQ(rep["plus_sequence"]["frames_used"], 29);
  EXPECT_EQ(rep["plus_sequence"]["skipped_transform_not_ok"], 1);
  EXPECT_EQ(rep["counts"]["slices"], 29);
  fs::remove_all(dir);
}

TEST(PlusPhantom, WriterRoundTripsRawAndSixteenBitSequences) {
  const fs::path dir = freshDir("plus-writer");
  const auto frameOf = [](int i) {
    cv::Mat m(5, 7, CV_16UC1);
    for (int r = 0; r < m.rows; ++r)
      for (int c = 0; c < m.cols; ++c) m.at<std::uint16_t>(r, c) = std::uint16_t(1000 * i + 10 * r + c + 60000 * (c == 6));
    return m;
  };
  for (const bool compressed : {false, true}) {
    const std::string path = (dir / (compressed ? "z.mha" : "raw.mha")).string();
    std::vector<MetaFrameFields> fields(3);
    for (int i = 0; i < 3; ++i) fields[std::size_t(i)] = {{"ImageStatus", "OK"}, {"Timestamp", std::to_string(i)}};
    writeMetaImageSequence(path, 3, frameOf, fields, compressed);
    const MetaImageHeader h = readMetaImageHeader(path);
    EXPECT_EQ(h.compressed, compressed);
    EXPECT_EQ(h.pixel, MetaPixelType::uint16);
    EXPECT_EQ(h.frames, 3);
    EXPECT_EQ(*frameNumber(h, 2, "Timestamp"), 2.0);
    MetaImageFrames frames(h);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(cv::norm(frames.next(), frameOf(i), cv::NORM_INF), 0) << i;
  }
  EXPECT_THROW(writeMetaImageSequence((dir / "bad.mha").string(), 2,
                                      [](int i) { return cv::Mat(4 + i, 4, CV_8UC1, cv::Scalar(0)); }, {}, true),
               std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir / "bad.mha"));
  for (const auto& e : fs::directory_iterator(dir))  // no temporary left behind
    EXPECT_EQ(e.path().filename().string().find(".partial"), std::string::npos) << e.path();
  fs::remove_all(dir);
}

}  // namespace
}  // namespace xsect

// Issue 49, item 3: ultrasound-ready segmentation. The pieces are checked against what they are
// defined to compute (segmentation/acoustic_shadows.h, series_threshold.h, pixel_settings.h), and
// the preset end to end on B-mode phantoms (speckle, a hypoechoic object, reflectors and their
// shadows, the PLUS fan) through a PLUS recording and the same frames as PNG images.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstring>
#include <map>
#include <random>

#include "io/image_header.h"
#include "io/input_error.h"
#include "io/slices_file.h"
#include "pipeline/load_sections.h"
#include "io/meta_image.h"
#include "io/meta_image_writer.h"
#include "io/run_config.h"
#include "segmentation/acoustic_shadows.h"
#include "segmentation/pixel_settings.h"
#include "segmentation/segment_slice.h"
#include "segmentation/series_threshold.h"
#include "tests/phantom_runs.h"

namespace fs = std::filesystem;
using namespace xsect;

namespace {

/// A histogram of two normal classes: `n1` pixels around m1 (spread s1), `n2` around m2.
GreyHistogram twoClasses(double m1, double s1, std::int64_t n1, double m2, double s2, std::int64_t n2,
                         std::mt19937_64& rng) {
  GreyHistogram h{};
  std::normal_distribution<double> a(m1, s1), b(m2, s2);
  for (std::int64_t k = 0; k < n1; ++k) ++h[std::size_t(std::clamp(std::lround(a(rng)), 0L, 255L))];
  for (std::int64_t k = 0; k < n2; ++k) ++h[std::size_t(std::clamp(std::lround(b(rng)), 0L, 255L))];
  return h;
}

}  // namespace

// Over random class sizes and spreads (classes at least 5 spreads apart), the minimum-error
// threshold lies half-way between the two classes' means (within their spreads' rounding), where
// Otsu's lands inside the larger, wider class when the smaller is a few percent of the pixels.
TEST(UltrasoundSegmentation, MinimumErrorThresholdSitsBetweenUnequalClasses) {
  std::mt19937_64 rng(49);
  std::uniform_real_distribution<double> u(0, 1);
  int otsuInsideTissue = 0, cases = 0;
  for (int k = 0; k < 60; ++k) {
    const double sDark = 3 + 5 * u(rng), sTissue = 8 + 14 * u(rng);
    const double mDark = 15 + 25 * u(rng), mTissue = mDark + 5 * std::max(sDark, sTissue) + 20 * u(rng);
    if (mTissue + 3 * sTissue > 250) continue;
    const std::int64_t nDark = std::int64_t(2000 + 20000 * u(rng)), nTissue = 200000;
    const GreyHistogram h = twoClasses(mDark, sDark, nDark, mTissue, sTissue, nTissue, rng);
    const double t = minimumErrorThresholdOfHistogram(h);
    ++cases;
    SCOPED_TRACE("dark " + std::to_string(mDark) + "±" + std::to_string(sDark) + " x" + std::to_string(nDark) +
                 ", tissue " + std::to_string(mTissue) + "±" + std::to_string(sTissue));
    EXPECT_NEAR(t, 0.5 * (mDark + mTissue), 3.0);
    // The classes behind the threshold, found again from it; the core a quarter of the way in.
    const GreyClasses c = minimumErrorClassesAt(h, t);
    ASSERT_TRUE(c.found);
    EXPECT_NEAR(c.dark_mean, mDark, 0.5 * sDark + 0.5);
    EXPECT_NEAR(c.bright_mean, mTissue, 0.5 * sTissue + 0.5);
    EXPECT_EQ(std::floor(0.5 * (c.dark_mean + c.bright_mean)), t);
    EXPECT_NEAR(coreThresholdOfClasses(c, InsideSide::below), c.dark_mean + 0.25 * (c.bright_mean - c.dark_mean), 1e-9);
    EXPECT_NEAR(coreThresholdOfClasses(c, InsideSide::above), c.bright_mean - 0.25 * (c.bright_mean - c.dark_mean), 1e-9);
    otsuInsideTissue += otsuThresholdOfHistogram(h) > mTissue - 1.5 * sTissue;
  }
  EXPECT_GT(cases, 40);
  // Why the preset does not use Otsu's: on these histograms it often splits the larger class.
  EXPECT_GT(otsuInsideTissue, cases / 10) << "Otsu's threshold inside the tissue class on " << otsuInsideTissue << " of " << cases;
}

// The core (SegmentationParams::core_threshold): over random lumens (a dark disk, grey 25, in
// tissue of grey 100) with a patch of speckle a little darker than the threshold beside them (grey
// between the core's level and the threshold, 8-14 px across, joined over a neck wider than the
// opening), the threshold alone takes the patch into the section (its edge 10 px or more beyond
// the circle); with the core the patch is cut at the core's reach: the edge lies within that
// reach (2 px for sigma 1.5 px) beyond where the blurred lumen-patch step crosses the core's
// level, plus a pixel, of the circle, and nowhere inside it by more than a pixel.
TEST(UltrasoundSegmentation, CoreKeepsSpeckleBesideTheLumenOut) {
  std::mt19937_64 rng(4903);
  std::uniform_real_distribution<double> u(0, 1);
  int cases = 0, patchTakenWithoutCore = 0;
  for (int k = 0; k < 40; ++k) {
    const int w = 160, h = 160;
    const double cx = 70 + 10 * u(rng), cy = 70 + 10 * u(rng), r = 18 + 22 * u(rng);
    const double angle = 2 * M_PI * u(rng), pr = 8 + 6 * u(rng);  // the patch's centre and radius
    const double px = cx + (r + 0.6 * pr) * std::cos(angle), py = cy + (r + 0.6 * pr) * std::sin(angle);
    const double threshold = 62.5, core = 25 + 0.25 * 75;  // half-way; a quarter of the way
    const double patchGrey = core + 4 + (threshold - core - 8) * u(rng);
    cv::Mat img(h, w, CV_32F);
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const double inDisk = std::clamp(r - std::hypot(i - cx, j - cy) + 0.5, 0.0, 1.0);
        const double inPatch = std::hypot(i - px, j - py) < pr ? 1.0 : 0.0;
        img.at<float>(j, i) = float(inDisk * 25 + (1 - inDisk) * (inPatch ? patchGrey : 100.0));
      }
    cv::Mat grey;
    img.convertTo(grey, CV_8U);
    SegmentationParams p;
    p.method = SegmentationMethod::threshold;
    p.threshold = threshold;
    p.inside = InsideSide::below;
    p.sigma_px = 1.5;
    p.open_radius_px = 3;
    const SegmentedSlice without = segmentSlice(grey, cv::Mat(), Vec2(1, 1), p);
    p.core_threshold = core;
    const SegmentedSlice with = segmentSlice(grey, cv::Mat(), Vec2(1, 1), p);
    ++cases;
    SCOPED_TRACE("case " + std::to_string(k) + ": r " + std::to_string(r) + ", patch grey " + std::to_string(patchGrey));
    ASSERT_EQ(without.sections.size(), 1u);
    ASSERT_EQ(with.sections.size(), 1u);
    double farWithout = 0, outWith = 0, inWith = 0;
    for (const Vec2& q : without.sections[0].outer) farWithout = std::max(farWithout, std::hypot(q.x() - cx, q.y() - cy) - r);
    for (const Vec2& q : with.sections[0].outer) {
      outWith = std::max(outWith, std::hypot(q.x() - cx, q.y() - cy) - r);
      inWith = std::max(inWith, r - std::hypot(q.x() - cx, q.y() - cy));
    }
    patchTakenWithoutCore += farWithout > 10;
    // Where the step from the lumen to the patch, blurred by sigma, crosses the core's level.
    double lo = 0, hi = 10;
    for (int it = 0; it < 60; ++it) {
      const double d = 0.5 * (lo + hi), stepAt = 25 + (patchGrey - 25) * 0.5 * std::erfc(-d / (1.5 * std::sqrt(2.0)));
      (stepAt < core ? lo : hi) = d;
    }
    EXPECT_LT(outWith, std::hypot(2, 1) + lo + 1);  // OpenCV's 5-pixel ellipse reaches (2, 1)
    EXPECT_LT(inWith, 1.0);
  }
  EXPECT_EQ(patchTakenWithoutCore, cases);  // the threshold alone takes every patch
}

// A shadow is the dark run at the far end of a beam: down the columns for a linear probe, along
// rays from the apex for a fan. A dark disk with tissue beyond it is never in shadow.
TEST(UltrasoundSegmentation, ShadowsAreTheDarkEndsOfBeams) {
  cv::Mat grey(200, 240, CV_32F, cv::Scalar(100));
  cv::circle(grey, {170, 80}, 20, cv::Scalar(20), cv::FILLED);            // a cyst, tissue below it
  cv::rectangle(grey, cv::Rect(40, 60, 30, 140), cv::Scalar(5), cv::FILLED);  // a shadow to the end
  const cv::Mat shadow = acousticShadows(grey, cv::Mat(), 50, std::nullopt, 4);
  cv::Mat expected(grey.size(), CV_8U, cv::Scalar(0));
  cv::rectangle(expected, cv::Rect(40, 60, 30, 140), cv::Scalar(255), cv::FILLED);
  EXPECT_EQ(cv::norm(shadow, expected, cv::NORM_L1), 0);
  // A run shorter than the minimum length is not a shadow.
  EXPECT_EQ(cv::countNonZero(acousticShadows(grey, cv::Mat(), 50, std::nullopt, 141)), 0);

  // A fan: apex above the image, a wedge from radius 120 to the end of the view is dark.
  const Vec2 apex(120, -40);
  cv::Mat fan(grey.size(), CV_8U, cv::Scalar(0)), wedge = fan.clone(), fanGrey(grey.size(), CV_32F, cv::Scalar(100));
  for (int j = 0; j < fan.rows; ++j)
    for (int i = 0; i < fan.cols; ++i) {
      const double dx = i - apex.x(), dy = j - apex.y(), r = std::hypot(dx, dy), a = std::atan2(dx, dy);
      if (r < 60 || r > 230 || std::abs(a) > 0.6) continue;
      fan.at<unsigned char>(j, i) = 255;
      if (std::abs(a - 0.2) < 0.08 && r > 120) {
        wedge.at<unsigned char>(j, i) = 255;
        fanGrey.at<float>(j, i) = 5;
      }
    }
  cv::circle(fanGrey, {100, 110}, 15, cv::Scalar(20), cv::FILLED);
  const cv::Mat fanShadow = acousticShadows(fanGrey, fan, 50, apex, 4);
  // The polar resampling blurs the wedge's sides by a pixel: its core (a pixel in) is all found.
  cv::Mat core;
  cv::erode(wedge, core, cv::Mat::ones(3, 3, CV_8U));
  const int found = cv::countNonZero(fanShadow & core), wrong = cv::countNonZero(fanShadow & ~wedge);
  EXPECT_GT(found, 0.99 * cv::countNonZero(core));
  EXPECT_LT(wrong, 0.03 * cv::countNonZero(wedge));  // a pixel's rim of the wedge's rays
  cv::Mat cyst(grey.size(), CV_8U, cv::Scalar(0));
  cv::circle(cyst, {100, 110}, 15, cv::Scalar(255), cv::FILLED);
  EXPECT_EQ(cv::countNonZero(fanShadow & cyst), 0);
  EXPECT_EQ(cv::countNonZero(fanShadow & ~fan), 0);
}

// inside: auto: the side that covers less of the view's border is the object.
TEST(UltrasoundSegmentation, InsideAutoIsTheSideAwayFromTheBorder) {
  for (const bool darkObject : {true, false}) {
    cv::Mat grey(120, 160, CV_32F, cv::Scalar(darkObject ? 100 : 20));
    cv::circle(grey, {80, 60}, 30, cv::Scalar(darkObject ? 20 : 100), cv::FILLED);
    const ObservedHistograms h = observedHistograms(grey, cv::Mat(), 1.0);
    EXPECT_EQ(insideOfBorder(h.border, 60), darkObject ? InsideSide::below : InsideSide::above);
  }
}

// Lengths in mm become pixels at the frame's pixel size: the same settings on a probe at twice
// the resolution use twice the pixels.
TEST(UltrasoundSegmentation, MillimetreSettingsScaleWithThePixel) {
  SegmentationParams p;
  p.sigma_mm = 0.3, p.open_radius_mm = 0.5, p.close_radius_mm = 0.5, p.speckle_filter_mm = 1.0;
  const SegmentationParams a = inPixels(p, Vec2(0.2, 0.2)), b = inPixels(p, Vec2(0.1, 0.1));
  EXPECT_DOUBLE_EQ(a.sigma_px, 1.5);
  EXPECT_DOUBLE_EQ(b.sigma_px, 3.0);
  EXPECT_EQ(a.open_radius_px, 3);
  EXPECT_EQ(b.open_radius_px, 5);
  EXPECT_EQ(a.speckle_filter_px % 2, 1);
  EXPECT_EQ(a.speckle_filter_px, 5);
  EXPECT_EQ(b.speckle_filter_px, 11);
}

// The preset's keys: explicit keys win, a length is given once, and label images take no preset.
TEST(UltrasoundSegmentation, PresetFillsOnlyTheKeysLeftOut) {
  const fs::path dir = test::freshDir("us-preset");
  test::writeFile(dir / "slices.yaml", "slices: []\n");
  const auto config = [&](const std::string& segmentation) {
    test::writeFile(dir / "config.yaml", "input: {slices: slices.yaml}\nsegmentation: " + segmentation + "\n");
    return readRunConfig((dir / "config.yaml").string());
  };
  const RunConfig c = config("{preset: ultrasound, open_radius_px: 2}");
  EXPECT_EQ(c.segmentation.method, SegmentationMethod::min_error);
  EXPECT_EQ(c.segmentation.inside, InsideSide::automatic);
  EXPECT_EQ(c.segmentation.shadows, ShadowRule::unobserved);
  EXPECT_EQ(c.segmentation.open_radius_px, 2);
  EXPECT_EQ(c.segmentation.open_radius_mm, 0);
  EXPECT_EQ(c.segmentation.close_radius_mm, 0);  // no closing: it joins speckle blobs to the object
  EXPECT_EQ(c.segmentation.elevation_median_mm, 1.0);  // frames within the beam's slab vote
  EXPECT_EQ(config("{preset: ultrasound, elevation_median_mm: 0}").segmentation.elevation_median_mm, 0.0);
  EXPECT_EQ(config("{}").segmentation.elevation_median_mm, 0.0);  // not without the preset
  EXPECT_THROW(config("{elevation_median_mm: -1}"), InputError);
  EXPECT_THROW(config("{method: labels, elevation_median_mm: 1}"), InputError);
  EXPECT_EQ(config("{preset: ultrasound, close_radius_mm: 0.4}").segmentation.close_radius_mm, 0.4);
  EXPECT_EQ(config("{preset: ultrasound, method: otsu, inside: below}").segmentation.inside, InsideSide::below);
  EXPECT_THROW(config("{sigma_px: 1, sigma_mm: 0.2}"), InputError);
  EXPECT_THROW(config("{preset: ultrasound, method: labels}"), InputError);
  EXPECT_THROW(config("{method: labels, shadows: unobserved}"), InputError);
  EXPECT_THROW(config("{preset: speckle}"), InputError);
  fs::remove_all(dir);
}

// End to end: a B-mode torus (a vessel loop: tube 8 mm) swept freehand through the PLUS fan, with
// speckle, a hypoechoic lumen and two reflectors' shadows per frame. The preset finds the lumen
// (inside: below), leaves the shadows out of the view, and gives the sections the clean phantom
// gives; the PLUS recording and the PNG frames (the apex given in the configuration) give the same
// solid. Measured topology over the family is in the note (not yet the truth on every
// seed: see docs/ultrasound.md).
TEST(UltrasoundSegmentation, PresetFindsTheLumenAndLeavesShadowsOut) {
  const std::string spec =
      "seed: 3\n"
      "shape: {kind: torus, params: {major_radius: 12, minor_radius: 4}, rotation_deg: [70, 0, 0]}\n"
      "pattern: {kind: freehand, count: 60, direction: [0, 0, 1], tilt_deg: 3, sector: true}\n"
      "image: {pixel_mm: 0.2, width: 320, height: 240}\n"
      "degradations: {ultrasound: {}}\n"
      "config: {reconstruction: {voxel_size_mm: 0.4}}\n"
      "plus: true\n";
  const fs::path dir = test::phantom("us-torus", spec);
  const auto r = test::runXsect("run " + (dir / "ph/config_plus.yaml").string() + " --out " + (dir / "plus").string() +
                                " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json plus = test::readJson(dir / "plus/report.json");
  const nlohmann::json png = test::run(dir, "png", "");
  EXPECT_EQ(plus["segmentation"]["inside_used"], "below");
  EXPECT_EQ(plus["segmentation"]["shadows"], "unobserved");
  EXPECT_GT(plus["segmentation"]["elevation_median"]["frames_changed"].get<int>(), 0);  // speckle differs frame to frame
  EXPECT_EQ(plus["betti"], png["betti"]);
  EXPECT_EQ(plus["counts"]["sections"], png["counts"]["sections"]);
  EXPECT_EQ(test::slurp(dir / "plus/mesh.ply"), test::slurp(dir / "png/mesh.ply"));
  EXPECT_EQ(plus["betti"], nlohmann::json({1, 1, 0}));
  // The clean phantom's sections: the same count over the sweep.
  const fs::path clean = test::phantom("us-torus-clean", std::string(spec).replace(spec.find("degradations: {ultrasound: {}}"),
                                                                                    30, "degradations: {}"));
  const nlohmann::json truth = test::run(clean, "out", "");
  EXPECT_EQ(plus["counts"]["sections"], truth["counts"]["sections"]);
  fs::remove_all(dir);
  fs::remove_all(clean);
}

// input.plus_masks: masks drawn by another tool beside the recording. The recording with its masks
// gives the solid the masks' own contours give (the same masks as PNG images in slices.yaml, at
// the same poses); masks that are not the recording's frames (another count, other timestamps)
// are refused, naming the mask file and field.
TEST(UltrasoundSegmentation, MaskSequenceBesideTheRecordingGivesTheMasksSolid) {
  const fs::path dir = test::phantom("us-masks",
                                     "seed: 2\n"
                                     "shape: {kind: torus, params: {major_radius: 10, minor_radius: 3.5}, rotation_deg: [70, 0, 0]}\n"
                                     "pattern: {kind: freehand, count: 40, direction: [0, 0, 1], tilt_deg: 3, sector: true}\n"
                                     "image: {pixel_mm: 0.2, width: 240, height: 180}\n"
                                     "config: {reconstruction: {voxel_size_mm: 0.4}}\n"
                                     "plus: true\n");
  const fs::path ph = dir / "ph";
  const MetaImageHeader h = readMetaImageHeader((ph / "sequence.igs.mha").string());
  // The masks: each frame's pixels above half, 0/1 (a tool's labels), as PNGs and as a sequence
  // with the recording's timestamps.
  std::vector<cv::Mat> masks;
  {
    MetaImageFrames frames(h);
    for (int f = 0; f < h.frames; ++f) {
      cv::Mat m;
      cv::threshold(frames.next(), m, 127, 1, cv::THRESH_BINARY);
      masks.push_back(m);
    }
  }
  std::vector<MetaFrameFields> stamps(std::size_t(h.frames));
  for (int f = 0; f < h.frames; ++f) stamps[std::size_t(f)]["Timestamp"] = *frameField(h, f, "Timestamp");
  writeMetaImageSequence((ph / "masks.mha").string(), h.frames, [&](int f) { return masks[std::size_t(f)]; }, stamps, true);
  std::string slices = test::slurp(ph / "slices.yaml");
  for (int f = 0; f < h.frames; ++f) {
    char name[64];
    std::snprintf(name, sizeof name, "images/%03d.png", f);
    cv::Mat png = masks[std::size_t(f)] * 255;
    ASSERT_TRUE(cv::imwrite((ph / ("mask_" + std::to_string(f) + ".png")).string(), png));
    const std::size_t at = slices.find(name);
    ASSERT_NE(at, std::string::npos) << name;
    slices.replace(at, std::strlen(name), "mask_" + std::to_string(f) + ".png");
  }
  test::writeFile(ph / "slices_masks.yaml", slices);
  std::string config = test::slurp(ph / "config.yaml");
  config.replace(config.find("slices.yaml"), 11, "slices_masks.yaml");
  // The masks' level is half way between 0 and 255, as input.plus_masks segments them.
  const std::size_t level = config.find("threshold: 128");
  ASSERT_NE(level, std::string::npos) << config;
  config.replace(level, 14, "threshold: 127.5");
  test::writeFile(ph / "config_masks.yaml", config);
  std::string plus = test::slurp(ph / "config_plus.yaml");
  plus.replace(plus.find("plus_config:"), 12, "plus_masks: masks.mha\n  plus_config:");
  test::writeFile(ph / "config_plus_masks.yaml", plus);

  const auto a = test::runXsect("run " + (ph / "config_masks.yaml").string() + " --out " + (dir / "png").string() + " --quiet");
  const auto b = test::runXsect("run " + (ph / "config_plus_masks.yaml").string() + " --out " + (dir / "plus").string() + " --quiet");
  ASSERT_EQ(a.code, 0) << a.err;
  ASSERT_EQ(b.code, 0) << b.err;
  EXPECT_EQ(test::readJson(dir / "png/report.json")["betti"], nlohmann::json({1, 1, 0}));
  EXPECT_EQ(test::readJson(dir / "png/report.json")["betti"], test::readJson(dir / "plus/report.json")["betti"]);
  EXPECT_EQ(test::slurp(dir / "png/mesh.ply"), test::slurp(dir / "plus/mesh.ply"));

  // Masks that are not the recording's: one frame short, or a timestamp off by 0.1 s.
  writeMetaImageSequence((ph / "masks.mha").string(), h.frames - 1, [&](int f) { return masks[std::size_t(f)]; },
                         std::vector<MetaFrameFields>(stamps.begin(), stamps.end() - 1), true);
  auto c = test::runXsect("run " + (ph / "config_plus_masks.yaml").string() + " --out " + (dir / "short").string());
  EXPECT_EQ(c.code, 2) << c.err;
  EXPECT_NE(c.err.find("masks.mha"), std::string::npos) << c.err;
  EXPECT_NE(c.err.find("DimSize"), std::string::npos) << c.err;
  EXPECT_FALSE(fs::exists(dir / "short"));
  stamps[3]["Timestamp"] = std::to_string(std::stod(stamps[3]["Timestamp"]) + 0.1);
  writeMetaImageSequence((ph / "masks.mha").string(), h.frames, [&](int f) { return masks[std::size_t(f)]; }, stamps, true);
  c = test::runXsect("run " + (ph / "config_plus_masks.yaml").string() + " --out " + (dir / "late").string());
  EXPECT_EQ(c.code, 2) << c.err;
  EXPECT_NE(c.err.find("Seq_Frame0003_Timestamp"), std::string::npos) << c.err;
  fs::remove_all(dir);
}

// The case: B-mode frames segmented as clean images (Otsu, no preset) give speckle
// sections by the hundred. The refusal names the segmentation first, with the preset, and any
// voxel size it advises is one `xsect check` accepts.
TEST(UltrasoundSegmentation, SpeckleSectionsAreBlamedOnTheSegmentation) {
  const fs::path dir = test::phantom("us-speckle",
                                     "seed: 4\n"
                                     "shape: {kind: torus, params: {major_radius: 12, minor_radius: 4}, rotation_deg: [70, 0, 0]}\n"
                                     "pattern: {kind: freehand, count: 30, direction: [0, 0, 1], tilt_deg: 3, sector: true}\n"
                                     "image: {pixel_mm: 0.2, width: 320, height: 240}\n"
                                     "degradations: {ultrasound: {}}\n");
  std::string config = test::slurp(dir / "ph/config.yaml");
  const std::size_t from = config.find("segmentation:"), to = config.find("conformity:");
  ASSERT_NE(from, std::string::npos);
  ASSERT_NE(to, std::string::npos);
  config.replace(from, to - from, "segmentation:\n  method: otsu\n");
  test::writeFile(dir / "ph/config_otsu.yaml", config);
  const auto r = test::runXsect("run " + (dir / "ph/config_otsu.yaml").string() + " --out " + (dir / "otsu").string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("the segmentation is the likely cause"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("segmentation.preset: ultrasound"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "otsu"));
  const std::string key = "set reconstruction.voxel_size_mm: ";
  const std::size_t at = r.err.find(key);
  // A voxel size is advised only where a run at it fits in memory (else the message says so).
  EXPECT_TRUE(at != std::string::npos || r.err.find("more than this machine has") != std::string::npos) << r.err;
  if (at != std::string::npos) {
    const std::string voxel = r.err.substr(at + key.size(), r.err.find_first_of(" \n", at + key.size()) - at - key.size());
    const auto c = test::runXsect("check " + (dir / "ph/config_otsu.yaml").string() + " --set reconstruction.voxel_size_mm=" +
                                  voxel);
    EXPECT_EQ(c.code, 0) << c.err;
  }
  fs::remove_all(dir);
}

// A frame whose every beam is dark to its end (the probe lifted off the skin) was observed nowhere:
// its plane has no extent, not an empty field of view (which says "observed everywhere").
TEST(UltrasoundSegmentation, AFrameAllInShadowIsObservedNowhere) {
  const fs::path dir = test::phantom("us-lifted",
                                     "seed: 1\n"
                                     "shape: {kind: sphere, params: {radius: 5}}\n"
                                     "pattern: {kind: freehand, count: 8, direction: [0, 0, 1], sector: true}\n"
                                     "image: {pixel_mm: 0.2, width: 160, height: 120}\n"
                                     "degradations: {ultrasound: {}}\n");
  const fs::path ph = dir / "ph";
  const std::vector<SliceRecord> slices = readSlicesFile((ph / "slices.yaml").string());
  ASSERT_EQ(slices.size(), 8u);
  const cv::Mat frame = cv::imread(slices[4].image_resolved, cv::IMREAD_UNCHANGED);
  ASSERT_TRUE(cv::imwrite(slices[4].image_resolved, cv::Mat::zeros(frame.size(), frame.type())));
  const RunConfig c = readRunConfig((ph / "config.yaml").string());
  std::vector<ImageHeader> headers;
  for (const SliceRecord& s : slices) headers.push_back(readImageHeader(s.image_resolved));
  const std::vector<CuttingPlane> planes =
      sectionsFromSlices(slices, (ph / "slices.yaml").string(), c.segmentation, (ph / "config.yaml").string(), headers)
          .planes;
  ASSERT_EQ(planes.size(), 8u);
  EXPECT_TRUE(planes[4].sections.empty());
  EXPECT_EQ(planes[4].extent.min, planes[4].extent.max);  // observed nowhere
  for (const int k : {3, 5}) {  // its neighbours: observed, in a sector
    EXPECT_NE(planes[std::size_t(k)].extent.min, planes[std::size_t(k)].extent.max) << k;
    EXPECT_FALSE(planes[std::size_t(k)].field_of_view.empty()) << k;
  }
  fs::remove_all(dir);
}

// Shadows (grey ~6, their beams dark to the end), a small dark object (~30, tissue beyond it) and
// tissue (~110), over random class sizes: the threshold out of its own shadows separates object
// from tissue, and leaves the shadows out of the histogram it comes from.
TEST(UltrasoundSegmentation, ThresholdOutOfShadowsSplitsObjectFromTissue) {
  std::mt19937_64 rng(7);
  int right = 0, cases = 0;
  for (int trial = 0; trial < 20; ++trial) {
    std::uniform_real_distribution<double> u(0, 1);
    const std::int64_t nShadow = std::int64_t(20000 + 40000 * u(rng)), nObject = std::int64_t(3000 + 5000 * u(rng));
    const std::int64_t nTissue = 100000;
    ShadowedHistograms h;
    std::normal_distribution<double> shadow(6, 2), object(30, 5), tissue(110, 15);
    const auto add = [&](std::normal_distribution<double>& d, std::int64_t n, bool inShadow) {
      for (std::int64_t k = 0; k < n; ++k) {
        const int g = int(std::clamp(std::lround(d(rng)), 0L, 255L));
        const int tail = inShadow ? std::min(255, g + 3) : ShadowedHistograms::kTailBins - 1;
        ++h.observed[std::size_t(g) * ShadowedHistograms::kTailBins + std::size_t(tail)];
      }
    };
    add(shadow, nShadow, true), add(object, nObject, false), add(tissue, nTissue, false);
    const auto rule = [](const GreyHistogram& g) { return minimumErrorThresholdOfHistogram(g); };
    const double t = thresholdOutOfShadows(h, rule);
    ++cases;
    right += t > 30 + 2 * 5 && t < 110 - 2 * 15;
    std::int64_t shadowLeft = 0;  // pixels as dark as the shadows (the object's are 3 spreads above)
    const ObservedHistograms out = outsideShadow(h, t);
    for (int g = 0; g < 15; ++g) shadowLeft += out.observed[std::size_t(g)];
    EXPECT_LT(shadowLeft, nShadow / 100) << trial;
  }
  EXPECT_EQ(right, cases);
}

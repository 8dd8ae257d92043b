// Segmentation (GUIDE.md stage 2): sub-pixel contours, holes and islands, thresholds, field of
// view, morphology, small components, simplification, bit depths, labels, anisotropic pixels.
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <random>

#include "geometry/polygon.h"
#include "segmentation/segment_slice.h"
#include "segmentation/series_threshold.h"

using namespace xsect;

namespace {

constexpr int S = 16;  // supersampling factor for anti-aliased test images

/// Anti-aliased image of the set {inside(x, y)} (x = column, y = row, pixel centres at integers).
template <class F>
cv::Mat render(int w, int h, F inside, double fg = 255, double bg = 0) {
  cv::Mat big(h * S, w * S, CV_32F);
  for (int J = 0; J < h * S; ++J)
    for (int I = 0; I < w * S; ++I) {
      const double x = (I + 0.5) / S - 0.5, y = (J + 0.5) / S - 0.5;
      big.at<float>(J, I) = float(inside(x, y) ? fg : bg);
    }
  cv::Mat small, out;
  cv::resize(big, small, cv::Size(w, h), 0, 0, cv::INTER_AREA);
  small.convertTo(out, CV_8U);
  return out;
}

cv::Mat disk(int w, int h, double cx, double cy, double r) {
  return render(w, h, [&](double x, double y) { return std::hypot(x - cx, y - cy) < r; });
}

double totalArea(const SegmentedSlice& s) {
  double a = 0;
  for (const auto& sec : s.sections) a += sectionArea(sec);
  return a;
}

}  // namespace

TEST(Segmentation, ContoursAreSubPixel) {
  const double cx = 31.37, cy = 28.81, r = 12.3;
  const SegmentedSlice s = segmentSlice(disk(64, 60, cx, cy, r), cv::Mat(), Vec2(1, 1), {});
  ASSERT_EQ(s.sections.size(), 1u);
  EXPECT_NEAR(sectionArea(s.sections[0]), M_PI * r * r, 0.005 * M_PI * r * r);
  double worst = 0;
  for (const auto& p : s.sections[0].outer) worst = std::max(worst, std::abs(std::hypot(p.x() - cx, p.y() - cy) - r));
  EXPECT_LT(worst, 0.1);  // a pixel staircase would be off by up to ~0.7 px
  EXPECT_GT(signedArea(s.sections[0].outer), 0);  // counter-clockwise in (u, v)
}

TEST(Segmentation, HolesAndIslandsInHoles) {
  // a ring (outer r 20, inner r 12) with an island (r 5) in its hole, and a separate disk
  const cv::Mat img = render(80, 64, [](double x, double y) {
    const double d = std::hypot(x - 30, y - 30);
    return (d < 20 && d > 12) || d < 5 || std::hypot(x - 68, y - 52) < 6;
  });
  const SegmentedSlice s = segmentSlice(img, cv::Mat(), Vec2(0.5, 0.5), {});
  ASSERT_EQ(s.sections.size(), 3u);
  int withHole = 0;
  for (const auto& sec : s.sections) {
    EXPECT_GT(signedArea(sec.outer), 0);
    for (const auto& h : sec.holes) EXPECT_LT(signedArea(h), 0);
    withHole += int(sec.holes.size());
  }
  EXPECT_EQ(withHole, 1);
  const double want = 0.25 * M_PI * (20 * 20 - 12 * 12 + 5 * 5 + 6 * 6);  // mm² (0.5 mm pixels)
  EXPECT_NEAR(totalArea(s), want, 0.01 * want);
  // containment: the island's centre is in the island's section, not in the ring's
  int containing = 0;
  for (const auto& sec : s.sections) containing += sectionContains(sec, Vec2(15, 15));
  EXPECT_EQ(containing, 1);
}

TEST(Segmentation, OtsuFindsTheThresholdOfNoisyImages) {
  cv::Mat img = render(64, 64, [](double x, double y) { return std::hypot(x - 32, y - 32) < 15; }, 190, 60);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 12);
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i)
      img.at<unsigned char>(j, i) = cv::saturate_cast<unsigned char>(img.at<unsigned char>(j, i) + noise(rng));
  SegmentationParams p;
  p.method = "otsu";
  p.sigma_px = 1.5;
  const SegmentedSlice s = segmentSlice(img, cv::Mat(), Vec2(1, 1), p);
  EXPECT_GT(s.threshold_used, 90);
  EXPECT_LT(s.threshold_used, 160);
  ASSERT_EQ(s.sections.size(), 1u);
  EXPECT_NEAR(sectionArea(s.sections[0]), M_PI * 225, 0.05 * M_PI * 225);
  // a fixed threshold far off the modes gives a different, wrong answer: the test can fail
  p.method = "threshold";
  p.threshold = 185;
  EXPECT_LT(totalArea(segmentSlice(img, cv::Mat(), Vec2(1, 1), p)), 0.8 * M_PI * 225);
}

TEST(Segmentation, FieldOfViewClipsAndWarns) {
  const cv::Mat img = disk(64, 64, 32, 32, 10);
  cv::Mat fov(64, 64, CV_8U, cv::Scalar(0));
  cv::rectangle(fov, cv::Rect(0, 0, 64, 32), cv::Scalar(255), cv::FILLED);  // top half observed
  const SegmentedSlice clipped = segmentSlice(img, fov, Vec2(1, 1), {});
  EXPECT_TRUE(clipped.touches_fov_edge);
  EXPECT_NEAR(totalArea(clipped), 0.5 * M_PI * 100, 0.06 * M_PI * 100);
  cv::Mat all(64, 64, CV_8U, cv::Scalar(255));
  EXPECT_FALSE(segmentSlice(img, all, Vec2(1, 1), {}).touches_fov_edge);
  EXPECT_FALSE(segmentSlice(img, cv::Mat(), Vec2(1, 1), {}).touches_fov_edge);
  EXPECT_TRUE(segmentSlice(disk(64, 64, 2, 32, 10), cv::Mat(), Vec2(1, 1), {}).touches_fov_edge);
}

TEST(Segmentation, SmallComponentsAndHolesAreRemoved) {
  const cv::Mat img = render(64, 64, [](double x, double y) {
    return (std::hypot(x - 32, y - 32) < 15 && std::hypot(x - 32, y - 32) > 1.2) ||
           std::hypot(x - 5, y - 5) < 1.5 || std::hypot(x - 58, y - 6) < 1.5;
  });
  SegmentationParams p;
  const SegmentedSlice raw = segmentSlice(img, cv::Mat(), Vec2(0.2, 0.2), p);
  EXPECT_EQ(raw.sections.size(), 3u);
  p.min_area_mm2 = 0.5;  // specks: ~7 px = 0.28 mm²; the big disk: ~700 px
  const SegmentedSlice clean = segmentSlice(img, cv::Mat(), Vec2(0.2, 0.2), p);
  ASSERT_EQ(clean.sections.size(), 1u);
  EXPECT_TRUE(clean.sections[0].holes.empty());  // the small hole is filled too
}

TEST(Segmentation, OpeningCutsThinBridges) {
  const cv::Mat img = render(80, 40, [](double x, double y) {
    return std::hypot(x - 20, y - 20) < 10 || std::hypot(x - 60, y - 20) < 10 ||
           (std::abs(y - 20) < 0.8 && x > 20 && x < 60);
  });
  SegmentationParams p;
  EXPECT_EQ(segmentSlice(img, cv::Mat(), Vec2(1, 1), p).sections.size(), 1u);
  p.open_radius_px = 2;
  EXPECT_EQ(segmentSlice(img, cv::Mat(), Vec2(1, 1), p).sections.size(), 2u);
  // closing joins two disks one pixel apart
  const cv::Mat near = render(60, 40, [](double x, double y) {
    return std::hypot(x - 19, y - 20) < 10 || std::hypot(x - 40.5, y - 20) < 10;
  });
  SegmentationParams q;
  EXPECT_EQ(segmentSlice(near, cv::Mat(), Vec2(1, 1), q).sections.size(), 2u);
  q.close_radius_px = 3;
  EXPECT_EQ(segmentSlice(near, cv::Mat(), Vec2(1, 1), q).sections.size(), 1u);
}

TEST(Segmentation, SimplificationStaysWithinTolerance) {
  const SegmentedSlice full = segmentSlice(disk(128, 128, 64, 64, 50), cv::Mat(), Vec2(0.1, 0.1), {});
  SegmentationParams p;
  p.simplify_mm = 0.05;
  const SegmentedSlice simple = segmentSlice(disk(128, 128, 64, 64, 50), cv::Mat(), Vec2(0.1, 0.1), p);
  ASSERT_EQ(simple.sections.size(), 1u);
  EXPECT_LT(simple.sections[0].outer.size(), full.sections[0].outer.size() / 3);
  for (const auto& q : full.sections[0].outer)
    EXPECT_LT(ringDistance(simple.sections[0].outer, q), 0.05 + 1e-6);
}

TEST(Segmentation, SixteenBitAndLabelImages) {
  const cv::Mat img8 = disk(64, 64, 30.5, 33.2, 11);
  cv::Mat img16;
  img8.convertTo(img16, CV_16U, 257.0);
  SegmentationParams p16;
  p16.threshold = 128 * 257.0;
  const double a8 = totalArea(segmentSlice(img8, cv::Mat(), Vec2(1, 1), {}));
  EXPECT_NEAR(totalArea(segmentSlice(img16, cv::Mat(), Vec2(1, 1), p16)), a8, 1e-3 * a8);
  cv::Mat labels(64, 64, CV_16U, cv::Scalar(0));
  cv::circle(labels, {20, 20}, 8, cv::Scalar(3), cv::FILLED);
  cv::circle(labels, {45, 45}, 8, cv::Scalar(7), cv::FILLED);
  SegmentationParams pl;
  pl.method = "labels";
  EXPECT_EQ(segmentSlice(labels, cv::Mat(), Vec2(1, 1), pl).sections.size(), 2u);
}

TEST(Segmentation, AnisotropicPixelsScaleToMillimetres) {
  const cv::Mat img = disk(64, 64, 32, 32, 12);
  const double unit = totalArea(segmentSlice(img, cv::Mat(), Vec2(1, 1), {}));
  const SegmentedSlice s = segmentSlice(img, cv::Mat(), Vec2(0.3, 0.7), {});
  EXPECT_NEAR(totalArea(s), unit * 0.21, 1e-9 * unit);
  double maxU = 0, maxV = 0;
  for (const auto& q : s.sections[0].outer) maxU = std::max(maxU, q.x()), maxV = std::max(maxV, q.y());
  EXPECT_NEAR(maxU, 44 * 0.3, 0.1);
  EXPECT_NEAR(maxV, 44 * 0.7, 0.2);
}

TEST(Segmentation, SeriesOtsuKeepsEmptySlicesEmpty) {
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0, 20);
  const auto noisy = [&](cv::Mat m) {
    for (int j = 0; j < m.rows; ++j)
      for (int i = 0; i < m.cols; ++i)
        m.at<unsigned char>(j, i) = cv::saturate_cast<unsigned char>(m.at<unsigned char>(j, i) + 20 + noise(rng));
    return m;
  };
  const cv::Mat object = noisy(disk(64, 64, 32, 32, 14)), empty = noisy(cv::Mat(64, 64, CV_8U, cv::Scalar(0)));
  const double t = otsuThresholdOfSeries({object, empty}, {cv::Mat(), cv::Mat()}, 1.5);
  EXPECT_GT(t, 70);
  EXPECT_LT(t, 200);
  SegmentationParams p;
  p.sigma_px = 1.5;
  p.threshold = t;
  EXPECT_EQ(segmentSlice(object, cv::Mat(), Vec2(1, 1), p).sections.size(), 1u);
  EXPECT_TRUE(segmentSlice(empty, cv::Mat(), Vec2(1, 1), p).sections.empty());
  // the per-image Otsu of the empty slice splits the noise and invents sections
  p.method = "otsu";
  EXPECT_GT(segmentSlice(empty, cv::Mat(), Vec2(1, 1), p).sections.size(), 5u);
}

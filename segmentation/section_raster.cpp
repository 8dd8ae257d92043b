// Sections of several planes sampled in one plane's frame (see section_raster.h).
#include "segmentation/section_raster.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "geometry/core/polygon.h"
#include "geometry/scene/section_distance_field.h"

namespace xsect {
namespace {

constexpr double kMarginSteps = 18.0;      // raster margin around the box
constexpr double kMaxNodeValues = 6.4e7;   // distances held at once (256 MB)

}  // namespace

cv::Point SectionRaster::fixedPoint(const Vec2& q) const {
  const Vec2 p = (q - origin) / step * double(1 << kSectionRasterShift);
  return {int(std::lround(std::clamp(p.x(), -1e9, 1e9))), int(std::lround(std::clamp(p.y(), -1e9, 1e9)))};
}

SectionRaster sectionRasterAround(const Eigen::AlignedBox2d& box, double step, int layers, double maxNodes) {
  SectionRaster r;
  r.step = step;
  for (int attempt = 0; attempt < 64; ++attempt) {
    const Vec2 lo = box.min() - Vec2::Constant(kMarginSteps * r.step);
    const Vec2 hi = box.max() + Vec2::Constant(kMarginSteps * r.step);
    r.origin = Vec2(std::floor(lo.x() / r.step) * r.step, std::floor(lo.y() / r.step) * r.step);
    r.nu = int(std::ceil((hi.x() - r.origin.x()) / r.step)) + 1;
    r.nv = int(std::ceil((hi.y() - r.origin.y()) / r.step)) + 1;
    const double limit = std::min(maxNodes, kMaxNodeValues / std::max(layers, 1));
    if (r.count() <= limit) return r;
    r.step *= std::max(1.1, std::sqrt(r.count() / limit));
  }
  throw std::runtime_error("no raster fits the sections");
}

Vec2 inReferenceFrame(const CuttingPlane& reference, const CuttingPlane& member, const Vec2& p) {
  return reference.plane.toPlane(member.plane.toWorld(p));
}

Ring ringInReferenceFrame(const CuttingPlane& reference, const CuttingPlane& member, Ring ring) {
  for (Vec2& p : ring) p = inReferenceFrame(reference, member, p);
  if (reference.plane.normal.dot(member.plane.normal) < 0) std::reverse(ring.begin(), ring.end());
  return ring;
}

std::vector<Section> sectionsInReferenceFrame(const CuttingPlane& reference, const CuttingPlane& member,
                                              std::vector<Section> sections) {
  for (Section& s : sections) {
    s.outer = ringInReferenceFrame(reference, member, std::move(s.outer));
    for (Ring& h : s.holes) h = ringInReferenceFrame(reference, member, std::move(h));
  }
  return sections;
}

std::array<Vec2, 4> extentCorners(const PlaneRect& e) {
  return {e.min, Vec2(e.max.x(), e.min.y()), e.max, Vec2(e.min.x(), e.max.y())};
}

bool extentIsEmpty(const PlaneRect& e) { return !(e.max.x() > e.min.x() && e.max.y() > e.min.y()); }

cv::Mat observedMask(const CuttingPlane& reference, const CuttingPlane& member, const SectionRaster& r) {
  if (member.observed_everywhere) return cv::Mat(r.nv, r.nu, CV_8U, cv::Scalar(1));
  cv::Mat mask(r.nv, r.nu, CV_8U, cv::Scalar(0));
  if (extentIsEmpty(member.extent)) return mask;
  std::vector<cv::Point> quad;
  for (const Vec2& c : extentCorners(member.extent)) quad.push_back(r.fixedPoint(inReferenceFrame(reference, member, c)));
  cv::fillConvexPoly(mask, quad, cv::Scalar(1), cv::LINE_8, kSectionRasterShift);
  if (member.field_of_view.empty()) return mask;
  std::vector<std::vector<cv::Point>> rings;
  for (const Ring& ring : member.field_of_view) {
    rings.emplace_back();
    for (const Vec2& p : ring) rings.back().push_back(r.fixedPoint(inReferenceFrame(reference, member, p)));
  }
  cv::Mat fov(r.nv, r.nu, CV_8U, cv::Scalar(0));
  cv::fillPoly(fov, rings, cv::Scalar(1), cv::LINE_8, kSectionRasterShift);
  return mask & fov;
}

cv::Mat signedDistanceOnRaster(const std::vector<Section>& sections, const SectionRaster& r) {
  const double band = kSectionRasterBandSteps * r.step;
  const SectionDistanceField f = sectionDistanceField(sections, r.step, band);
  cv::Mat d(r.nv, r.nu, CV_32F), inside(r.nv, r.nu, CV_8U);
  for (int j = 0; j < r.nv; ++j)
    for (int i = 0; i < r.nu; ++i) {
      const Vec2 q = r.node(i, j);
      const float v = f.sample(q.x(), q.y());
      d.at<float>(j, i) = v;
      inside.at<unsigned char>(j, i) = v < 0 ? 1 : 0;
    }
  const int in = cv::countNonZero(inside);
  if (in == 0 || double(in) == r.count()) return d;  // no node on one side: nothing to measure to
  cv::Mat toInside, toOutside;
  cv::distanceTransform(inside == 0, toInside, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  cv::distanceTransform(inside, toOutside, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  for (int j = 0; j < r.nv; ++j)
    for (int i = 0; i < r.nu; ++i) {
      float& v = d.at<float>(j, i);
      if (std::abs(v) < band) continue;
      v = inside.at<unsigned char>(j, i) ? -std::max(float(band), float(r.step) * toOutside.at<float>(j, i))
                                         : std::max(float(band), float(r.step) * toInside.at<float>(j, i));
    }
  return d;
}

cv::Mat signedDistanceNearContours(const std::vector<Section>& sections, const SectionRaster& r, double band_steps) {
  const SectionDistanceField f = sectionDistanceField(sections, r.step, band_steps * r.step);
  cv::Mat d(r.nv, r.nu, CV_32F);
  for (int j = 0; j < r.nv; ++j)
    for (int i = 0; i < r.nu; ++i) {
      const Vec2 q = r.node(i, j);
      d.at<float>(j, i) = f.sample(q.x(), q.y());
    }
  return d;
}

std::vector<Section> sectionsOfRasterRings(std::vector<Ring> rings, const SectionRaster& r, int label) {
  std::vector<Ring> outers, holes;
  for (Ring& ring : rings) {
    for (Vec2& p : ring) p = r.node(0, 0) + r.step * p;
    (signedArea(ring) > 0 ? outers : holes).push_back(std::move(ring));
  }
  std::vector<Section> sections = sectionsFromRings(std::move(outers), std::move(holes));
  for (Section& s : sections) s.label = label;
  return sections;
}

}  // namespace xsect

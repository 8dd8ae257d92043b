// The elevation median of a sweep (see elevation_median.h).
#include "segmentation/elevation_median.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include <opencv2/core.hpp>

#include "geometry/core/polygon.h"
#include "segmentation/iso_contours.h"
#include "segmentation/section_raster.h"

namespace xsect {
namespace {

constexpr double kMaxAngleDeg = 10.0;  // neighbours more tilted than this are another view, not the same slab
constexpr double kMaxNodes = 4.0e6;    // the raster's step grows past this many nodes
// Distances exact within this many raster steps of a contour. The median of 1-Lipschitz functions
// is 1-Lipschitz, so at the nodes beside a change of its sign (all isoContours reads) it is within
// sqrt(2) steps of zero, and it is one of the three values there: exact. Beyond, signs suffice.
constexpr double kBandSteps = 3.0;

/// 1 where `neighbour`'s plane passes within max_mm of the raster node of `frame`'s plane.
cv::Mat nearMask(const CuttingPlane& frame, const CuttingPlane& neighbour, const SectionRaster& r, double max_mm) {
  cv::Mat near(r.nv, r.nu, CV_8U);
  for (int j = 0; j < r.nv; ++j)
    for (int i = 0; i < r.nu; ++i)
      near.at<unsigned char>(j, i) =
          std::abs(neighbour.plane.signedDistance(frame.plane.toWorld(r.node(i, j)))) <= max_mm ? 1 : 0;
  return near;
}

bool closeInAngle(const Plane& a, const Plane& b) {
  return std::abs(a.normal.dot(b.normal)) >= std::cos(kMaxAngleDeg * M_PI / 180.0);
}

struct FrameMedian {
  std::vector<Section> sections;
  bool changed = false;
  double removed_mm2 = 0, added_mm2 = 0;
};

FrameMedian medianOfFrame(const CuttingPlane& before, const CuttingPlane& frame, const CuttingPlane& after,
                          double max_mm) {
  FrameMedian out;
  const std::vector<Section> previous = sectionsInReferenceFrame(frame, before, before.sections);
  const std::vector<Section> next = sectionsInReferenceFrame(frame, after, after.sections);
  Eigen::AlignedBox2d box;
  for (const auto* sections : {&previous, &frame.sections, &next})
    for (const Section& s : *sections) box.extend(ringBounds(s.outer));
  if (box.isEmpty()) return out;
  const double step = frame.pixel_mm > 0 ? frame.pixel_mm : box.diagonal().norm() / 1024.0;
  const SectionRaster r = sectionRasterAround(box, step, 3, kMaxNodes);
  const cv::Mat votes = observedMask(frame, frame, r) & observedMask(frame, before, r) & observedMask(frame, after, r) &
                        nearMask(frame, before, r, max_mm) & nearMask(frame, after, r, max_mm);
  if (cv::countNonZero(votes) == 0) return out;
  const cv::Mat own = signedDistanceNearContours(frame.sections, r, kBandSteps);
  const cv::Mat a = signedDistanceNearContours(previous, r, kBandSteps);
  const cv::Mat b = signedDistanceNearContours(next, r, kBandSteps);
  cv::Mat field(r.nv, r.nu, CV_32F);  // positive inside, for isoContours
  int removed = 0, added = 0;
  for (int j = 0; j < r.nv; ++j)
    for (int i = 0; i < r.nu; ++i) {
      const float d = own.at<float>(j, i);
      float m = d;
      if (votes.at<unsigned char>(j, i)) {
        const float x = a.at<float>(j, i), y = b.at<float>(j, i);
        m = std::max(std::min(x, y), std::min(std::max(x, y), d));  // the median of three
      }
      field.at<float>(j, i) = -m;
      removed += d < 0 && m >= 0;
      added += d >= 0 && m < 0;
    }
  if (removed == 0 && added == 0) return out;
  out.changed = true;
  out.removed_mm2 = removed * r.step * r.step;
  out.added_mm2 = added * r.step * r.step;
  const int label = frame.sections.empty() ? 1 : frame.sections.front().label;
  out.sections = sectionsOfRasterRings(isoContours(field), r, label);
  return out;
}

}  // namespace

ElevationMedian elevationMedian(std::vector<CuttingPlane> planes, double max_mm) {
  ElevationMedian out;
  const int n = int(planes.size());
  std::vector<FrameMedian> medians(static_cast<std::size_t>(std::max(n, 0)));
  tbb::parallel_for(1, std::max(n - 1, 1), [&](int k) {
    const CuttingPlane &before = planes[std::size_t(k - 1)], &frame = planes[std::size_t(k)],
                       &after = planes[std::size_t(k + 1)];
    if (frame.observed_everywhere || frame.is_virtual || before.is_virtual || after.is_virtual) return;
    if (!closeInAngle(frame.plane, before.plane) || !closeInAngle(frame.plane, after.plane)) return;
    medians[std::size_t(k)] = medianOfFrame(before, frame, after, max_mm);
  });
  for (int k = 0; k < n; ++k) {
    FrameMedian& m = medians[std::size_t(k)];
    if (!m.changed) continue;
    planes[std::size_t(k)].sections = std::move(m.sections);
    ++out.frames_changed;
    out.area_removed_mm2 += m.removed_mm2;
    out.area_added_mm2 += m.added_mm2;
  }
  out.planes = std::move(planes);
  return out;
}

}  // namespace xsect

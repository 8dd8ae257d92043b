// Observed pieces of cutting planes (see observed_piece.h).
#include "geometry/scene/observed_piece.h"

#include <opencv2/imgproc.hpp>

#include <cstring>
#include <map>
#include <string>

namespace xsect {

namespace {

/// The raster of a field of view (rings in plane mm) over the image rectangle `full`, eroded by
/// one node; null when nothing is observed.
std::shared_ptr<const FieldOfViewRaster> fieldOfViewRaster(const std::vector<Ring>& rings, const PlaneRect& full,
                                                           double pixel) {
  auto r = std::make_shared<FieldOfViewRaster>();
  const Vec2 size = full.max - full.min;
  r->step = pixel;
  // At most 16 M nodes (a 4096² image): coarser beyond, which `slack` reports.
  while ((size.x() / r->step + 1) * (size.y() / r->step + 1) > 16.0e6) r->step *= 2;
  r->origin = full.min;
  r->nu = int(std::floor(size.x() / r->step)) + 1;
  r->nv = int(std::floor(size.y() / r->step)) + 1;
  cv::Mat observed(r->nv, r->nu, CV_8U, cv::Scalar(0));
  constexpr int kShift = 4;  // sub-node precision of the polygon vertices
  std::vector<std::vector<cv::Point>> polys;
  for (const Ring& ring : rings) {
    std::vector<cv::Point> poly;
    for (const Vec2& q : ring) {
      const Vec2 n = (q - r->origin) / r->step * double(1 << kShift);
      poly.emplace_back(int(std::lround(n.x())), int(std::lround(n.y())));
    }
    polys.push_back(std::move(poly));
  }
  cv::fillPoly(observed, polys, cv::Scalar(255), cv::LINE_8, kShift);
  cv::erode(observed, observed, cv::Mat::ones(3, 3, CV_8U));
  if (cv::countNonZero(observed) == 0) return nullptr;
  cv::Mat unobserved = observed == 0, distance, labels;
  cv::distanceTransform(unobserved, distance, labels, cv::DIST_L2, cv::DIST_MASK_5, cv::DIST_LABEL_PIXEL);
  std::vector<std::int32_t> ofLabel(std::size_t(r->nu) * std::size_t(r->nv) + 1, 0);
  for (int j = 0; j < r->nv; ++j)
    for (int i = 0; i < r->nu; ++i)
      if (observed.at<std::uint8_t>(j, i)) ofLabel[std::size_t(labels.at<std::int32_t>(j, i))] = j * r->nu + i;
  cv::Mat depth;
  cv::distanceTransform(observed, depth, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  r->depth.resize(std::size_t(r->nu) * std::size_t(r->nv));
  for (int j = 0; j < r->nv; ++j)
    for (int i = 0; i < r->nu; ++i)
      r->depth[std::size_t(j) * std::size_t(r->nu) + std::size_t(i)] = float(r->step * depth.at<float>(j, i));
  r->nearest.resize(std::size_t(r->nu) * std::size_t(r->nv));
  for (int j = 0; j < r->nv; ++j)
    for (int i = 0; i < r->nu; ++i)
      r->nearest[std::size_t(j) * std::size_t(r->nu) + std::size_t(i)] =
          observed.at<std::uint8_t>(j, i) ? j * r->nu + i : ofLabel[std::size_t(labels.at<std::int32_t>(j, i))];
  return r;
}

/// The bytes that make two fields of view the same raster.
std::string fieldOfViewKey(const CuttingPlane& p) {
  std::string key;
  const auto add = [&](const void* d, std::size_t n) { key.append(static_cast<const char*>(d), n); };
  add(p.extent.min.data(), sizeof(double) * 2);
  add(p.extent.max.data(), sizeof(double) * 2);
  add(&p.pixel_mm, sizeof(double));
  for (const Ring& ring : p.field_of_view) {
    const std::size_t n = ring.size();
    add(&n, sizeof n);
    for (const Vec2& q : ring) add(q.data(), sizeof(double) * 2);
  }
  return key;
}

}  // namespace

std::vector<ObservedPiece> observedPieces(const std::vector<CuttingPlane>& planes, bool observed) {
  std::vector<ObservedPiece> out(planes.size());
  if (!observed) return out;
  std::map<std::string, std::shared_ptr<const FieldOfViewRaster>> shared;
  for (std::size_t i = 0; i < planes.size(); ++i) {
    const CuttingPlane& p = planes[i];
    ObservedPiece& piece = out[i];
    if (p.is_virtual || p.observed_everywhere) continue;
    piece.whole = false;
    const Vec2 size = p.extent.max - p.extent.min;
    // One pixel: the image's own, or, without one, a thousandth of the rectangle.
    const double pixel = p.pixel_mm > 0 ? p.pixel_mm : 1e-3 * std::max(size.x(), size.y());
    piece.rect.min = p.extent.min + Vec2::Constant(pixel);
    piece.rect.max = p.extent.max - Vec2::Constant(pixel);
    if (!(pixel > 0) || !(piece.rect.max.x() >= piece.rect.min.x() && piece.rect.max.y() >= piece.rect.min.y())) {
      piece.empty = true;
      continue;
    }
    if (p.field_of_view.empty()) continue;
    const std::string key = fieldOfViewKey(p);
    auto it = shared.find(key);
    if (it == shared.end()) it = shared.emplace(key, fieldOfViewRaster(p.field_of_view, p.extent, pixel)).first;
    piece.fov = it->second;
    if (!piece.fov) {
      piece.empty = true;
      continue;
    }
    piece.slack = piece.fov->step;
  }
  return out;
}

}  // namespace xsect

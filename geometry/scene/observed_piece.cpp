// Observed pieces of cutting planes (see observed_piece.h).
#include "geometry/scene/observed_piece.h"

#include <opencv2/imgproc.hpp>
#include <tbb/parallel_for.h>

#include <cstring>
#include <map>
#include <string>

namespace xsect {

namespace {

/// The raster of a field of view (rings in plane mm) over the image rectangle `full` grown by a
/// quarter of its size on each side (unobserved), eroded by one node; null when nothing is observed.
/// Why the margin: beyond the raster the distance is only bounded (through the domain's nearest
/// point); within it, a point beside the image finds its own nearest observed node.
/// Nodes of the raster over `full` at `step` (the image rectangle and its margin).
double rasterNodes(const PlaneRect& full, double step) {
  const Vec2 size = full.max - full.min;
  const double margin = 0.25 * std::max(size.x(), size.y());
  return (size.x() + 2 * margin) / step * ((size.y() + 2 * margin) / step);
}

/// `coarsening`: the raster's step is the pixel times this (a power of two, observedPieces).
std::shared_ptr<const FieldOfViewRaster> fieldOfViewRaster(const std::vector<Ring>& rings, const PlaneRect& full,
                                                           double pixel, double coarsening) {
  auto r = std::make_shared<FieldOfViewRaster>();
  const Vec2 size = full.max - full.min;
  const double margin = 0.25 * std::max(size.x(), size.y());
  r->step = pixel * coarsening;
  // At most 16 M nodes (a 3000² image and its margin): coarser beyond (the slack follows the step).
  while (rasterNodes(full, r->step) > 16.0e6) r->step *= 2;
  const int pad = int(std::ceil(margin / r->step)) + 1;
  r->origin = full.min - Vec2::Constant(pad * r->step);
  r->nu = int(std::floor(size.x() / r->step)) + 1 + 2 * pad;
  r->nv = int(std::floor(size.y() / r->step)) + 1 + 2 * pad;
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
  cv::erode(observed, observed, cv::Mat::ones(3, 3, CV_8U), cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  if (cv::countNonZero(observed) == 0) return nullptr;
  cv::Mat unobserved = observed == 0, distance, labels, depth;
  cv::distanceTransform(unobserved, distance, labels, cv::DIST_L2, cv::DIST_MASK_5, cv::DIST_LABEL_PIXEL);
  cv::distanceTransform(observed, depth, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  std::vector<std::int32_t> ofLabel(std::size_t(r->nu) * std::size_t(r->nv) + 1, 0);
  for (int j = 0; j < r->nv; ++j)
    for (int i = 0; i < r->nu; ++i)
      if (observed.at<std::uint8_t>(j, i)) ofLabel[std::size_t(labels.at<std::int32_t>(j, i))] = j * r->nu + i;
  const std::size_t nodes = std::size_t(r->nu) * std::size_t(r->nv);
  r->nearest.resize(nodes);
  r->depth.resize(nodes);
  for (int j = 0; j < r->nv; ++j)
    for (int i = 0; i < r->nu; ++i) {
      const std::size_t n = std::size_t(j) * std::size_t(r->nu) + std::size_t(i);
      r->nearest[n] = observed.at<std::uint8_t>(j, i) ? j * r->nu + i : ofLabel[std::size_t(labels.at<std::int32_t>(j, i))];
      r->depth[n] = float(r->step * depth.at<float>(j, i));
    }
  return r;
}

/// What makes two fields of view the same raster: the rings, rectangle and pixel, each number
/// rounded to a millionth of the rectangle's size (a sweep's frames share one field of view, but
/// their spacings, from each frame's chained pose, differ in the last digits).
std::string fieldOfViewKey(const CuttingPlane& p) {
  const double quantum = 1e-6 * (1.0 + (p.extent.max - p.extent.min).norm());
  std::string key;
  const auto add = [&](double v) {
    const long long q = std::llround(v / quantum);
    key.append(reinterpret_cast<const char*>(&q), sizeof q);
  };
  add(p.extent.min.x()), add(p.extent.min.y()), add(p.extent.max.x()), add(p.extent.max.y()), add(p.pixel_mm);
  for (const Ring& ring : p.field_of_view) {
    add(double(ring.size()) * quantum);
    for (const Vec2& q : ring) add(q.x()), add(q.y());
  }
  return key;
}

}  // namespace

void markSectionsClearOfEdges(std::vector<ObservedPiece>& pieces, const std::vector<SectionDistanceField>& fields) {
  tbb::parallel_for(std::size_t(0), pieces.size(), [&](std::size_t i) {
    ObservedPiece& piece = pieces[i];
    if (piece.whole || piece.empty) return;
    const SectionDistanceField& f = fields[i];
    const double h = f.step;
    const auto clear = [&](double a, double b) { return f.outsideOver(a - h, a + h, b - h, b + h); };
    bool ok = true;
    if (!piece.fov) {  // the rectangle's sides, every raster step
      const PlaneRect& r = piece.rect;
      const int na = int(std::ceil((r.max.x() - r.min.x()) / h)), nb = int(std::ceil((r.max.y() - r.min.y()) / h));
      for (int k = 0; k <= na && ok; ++k) {
        const double a = std::min(r.max.x(), r.min.x() + k * h);
        ok = clear(a, r.min.y()) && clear(a, r.max.y());
      }
      for (int k = 0; k <= nb && ok; ++k) {
        const double b = std::min(r.max.y(), r.min.y() + k * h);
        ok = clear(r.min.x(), b) && clear(r.max.x(), b);
      }
    } else {  // the observed nodes beside an unobserved one (the field of view's raster step)
      const FieldOfViewRaster& v = *piece.fov;
      const double pad = std::max(0.0, v.step - h);
      for (int j = 1; j + 1 < v.nv && ok; ++j)
        for (int k = 1; k + 1 < v.nu && ok; ++k) {
          const std::size_t n = std::size_t(j) * std::size_t(v.nu) + std::size_t(k);
          // Not an edge node: the nearest observed node of an unobserved one (the 5 x 5 chamfer mask
          // reaches a knight's move away) lies within √5 nodes of the unobserved region.
          if (v.depth[n] <= 0 || v.depth[n] > 2.5 * v.step) continue;
          const Vec2 p = v.point(n);
          ok = f.outsideOver(p.x() - h - pad, p.x() + h + pad, p.y() - h - pad, p.y() + h + pad);
        }
    }
    piece.edge_outside = ok;
  });
}

std::vector<ObservedPiece> observedPieces(const std::vector<CuttingPlane>& planes, bool observed) {
  std::vector<ObservedPiece> out(planes.size());
  if (!observed) return out;
  // Fields of view by key, in the order first met: the plane that rasterises each, then its raster.
  std::map<std::string, std::size_t> keyed;
  std::vector<std::size_t> first;
  std::vector<std::size_t> fovOf(planes.size(), 0);  // 0: none, else 1 + index into `first`
  // One pixel: the image's own, or, without one, a thousandth of the rectangle.
  const auto pixelOf = [&](const CuttingPlane& p) {
    const Vec2 size = p.extent.max - p.extent.min;
    return p.pixel_mm > 0 ? p.pixel_mm : 1e-3 * std::max(size.x(), size.y());
  };
  for (std::size_t i = 0; i < planes.size(); ++i) {
    const CuttingPlane& p = planes[i];
    ObservedPiece& piece = out[i];
    if (p.is_virtual || p.observed_everywhere) continue;
    piece.whole = false;
    const double pixel = pixelOf(p);
    piece.rect.min = p.extent.min + Vec2::Constant(pixel);
    piece.rect.max = p.extent.max - Vec2::Constant(pixel);
    if (!(pixel > 0) || !(piece.rect.max.x() >= piece.rect.min.x() && piece.rect.max.y() >= piece.rect.min.y())) {
      piece.empty = true;
      continue;
    }
    if (p.field_of_view.empty()) continue;
    const auto it = keyed.emplace(fieldOfViewKey(p), first.size()).first;
    if (it->second == first.size()) first.push_back(i);
    fovOf[i] = it->second + 1;
  }
  // Every distinct field of view is a raster kept for the whole run: one for a probe's sector, but
  // one per frame where each frame's differs (acoustic shadows left unobserved, issue 49: 200
  // frames of 640x480 px held 1.1 GB of rasters at the pixel). Together they are kept under 64 M
  // nodes (512 MB) by doubling every raster's step; the slack of their distances follows the step.
  double coarsening = 1;
  for (;;) {
    double nodes = 0;
    for (const std::size_t i : first)
      nodes += std::min(16.0e6, rasterNodes(planes[i].extent, pixelOf(planes[i]) * coarsening));
    if (nodes <= 64.0e6) break;
    coarsening *= 2;
  }
  std::vector<std::shared_ptr<const FieldOfViewRaster>> rasters(first.size());
  tbb::parallel_for(std::size_t(0), first.size(), [&](std::size_t k) {
    const CuttingPlane& p = planes[first[k]];
    rasters[k] = fieldOfViewRaster(p.field_of_view, p.extent, pixelOf(p), coarsening);
  });
  for (std::size_t i = 0; i < planes.size(); ++i) {
    if (fovOf[i] == 0) continue;
    out[i].fov = rasters[fovOf[i] - 1];
    if (!out[i].fov) out[i].empty = true;
  }
  return out;
}

}  // namespace xsect

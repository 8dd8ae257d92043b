// Frames with their contours for report.html (see frame_overlays.h).
#include "report/run/frame_overlays.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <map>

#include "geometry/core/plane_of_pose.h"
#include "geometry/core/polygon.h"
#include "io/base64.h"
#include "io/image_io.h"
#include "io/meta_image.h"
#include "report/page/report_page.h"
#include "report/run/page_text.h"

namespace xsect {

namespace {

/// The page's material palette (report_page.js) as OpenCV BGR.
cv::Scalar labelColour(int label) {
  static constexpr unsigned kRgb[] = {0x4e79a7, 0xf28e2b, 0x59a14f, 0xe15759, 0x76b7b2,
                                      0xedc948, 0xb07aa1, 0xff9da7, 0x9c755f, 0xbab0ac};
  const unsigned c = kRgb[std::size_t(std::max(1, label) - 1) % std::size(kRgb)];
  return cv::Scalar(c & 255, (c >> 8) & 255, c >> 16);
}

struct Chosen {
  std::size_t plane;    ///< index into RunInputs::planes
  std::string why;      ///< the caption's reason
};

/// The planes to show: the largest sections, the worst disagreement, the flagged; no repeats.
std::vector<Chosen> chooseFrames(const RunInputs& in, std::size_t maxFrames) {
  std::map<int, std::size_t> planeOfSlice;
  for (std::size_t i = 0; i < in.planes.size(); ++i)
    if (!in.planes[i].is_virtual) planeOfSlice.emplace(in.planes[i].slice, i);
  std::vector<Chosen> chosen;
  const auto add = [&](int slice, const std::string& why) {
    const auto it = planeOfSlice.find(slice);
    if (it == planeOfSlice.end() || chosen.size() >= maxFrames) return;
    for (Chosen& c : chosen)
      if (c.plane == it->second) {
        c.why += "; " + why;
        return;
      }
    chosen.push_back({it->second, why});
  };
  // The slice that shows most of the object: the largest area of sections (the first of equals).
  const CuttingPlane* largest = nullptr;
  double largestArea = 0;
  for (const CuttingPlane& p : in.planes) {
    if (p.is_virtual || p.sections.empty()) continue;
    double area = 0;
    for (const Section& s : p.sections) area += sectionArea(s);
    if (!largest || area > largestArea) largest = &p, largestArea = area;
  }
  if (largest)
    add(largest->slice, "holds the largest sections (" + shortNumber(largestArea) + " mm²)");
  const SliceConformity* worst = nullptr;
  for (const SliceConformity& s : in.conformity.slices)
    if (!s.dropped && s.before.pairs > 0 && (!worst || s.before.median_mismatch_mm > worst->before.median_mismatch_mm))
      worst = &s;
  if (worst)
    add(worst->slice, "disagrees most with the slices it crosses (median " + shortNumber(worst->before.median_mismatch_mm) +
                          " mm over " + std::to_string(worst->before.pairs) + " crossings)");
  for (const int f : in.conformity.flagged_slices) add(f, "flagged");
  for (const SliceConformity& s : in.conformity.slices)
    if (s.correction.outlier) add(s.slice, "a pose-correction outlier");
  return chosen;
}

/// An 8-bit image for display: 16-bit images stretched over their range.
cv::Mat displayable(const cv::Mat& image) {
  cv::Mat grey;
  if (image.depth() == CV_8U) {
    grey = image;
  } else {
    double lo = 0, hi = 0;
    cv::minMaxLoc(image, &lo, &hi);
    image.convertTo(grey, CV_8U, hi > lo ? 255.0 / (hi - lo) : 1.0, hi > lo ? -lo * 255.0 / (hi - lo) : 0.0);
  }
  cv::Mat colour;
  cv::cvtColor(grey, colour, cv::COLOR_GRAY2BGR);
  return colour;
}

/// The image with the plane's field of view and sections drawn, scaled by `scale`. Plane points go
/// to pixels through the pose the image was taken at (a pose correction moves the plane rigidly
/// and keeps its plane coordinates).
cv::Mat overlay(const cv::Mat& image, const Mat4& pose, const CuttingPlane& p, const std::vector<Section>& sections,
                double scale) {
  cv::Mat shown;
  cv::resize(displayable(image), shown, cv::Size(), scale, scale, scale < 1 ? cv::INTER_AREA : cv::INTER_NEAREST);
  const Plane plane = planeOfPose(pose);
  Eigen::Matrix<double, 3, 2> axes;
  axes.col(0) = pose.block<3, 1>(0, 0);
  axes.col(1) = pose.block<3, 1>(0, 1);
  const Eigen::Matrix2d gramInverse = (axes.transpose() * axes).inverse();
  constexpr int kShift = 4;  // sub-pixel drawing: coordinates in 1/16 pixel
  const auto pixels = [&](const Ring& ring) {
    std::vector<cv::Point> points;
    for (const Vec2& q : ring) {
      const Eigen::Vector2d ij = gramInverse * axes.transpose() * (plane.toWorld(q) - pose.block<3, 1>(0, 3));
      // Pixel centres sit at integer (i, j); the scaled image's at (i + 0.5) * scale - 0.5.
      points.emplace_back(int(std::lround(((ij.x() + 0.5) * scale - 0.5) * (1 << kShift))),
                          int(std::lround(((ij.y() + 0.5) * scale - 0.5) * (1 << kShift))));
    }
    return points;
  };
  for (const Ring& fov : p.field_of_view)
    cv::polylines(shown, std::vector<std::vector<cv::Point>>{pixels(fov)}, true, cv::Scalar(200, 160, 90), 1, cv::LINE_AA, kShift);
  for (const Section& s : sections) {
    std::vector<std::vector<cv::Point>> rings{pixels(s.outer)};
    for (const Ring& h : s.holes) rings.push_back(pixels(h));
    cv::polylines(shown, rings, true, labelColour(s.label), 2, cv::LINE_AA, kShift);
  }
  return shown;
}

std::string figure(const cv::Mat& shown, const std::string& caption) {
  const std::string png = pngBytes(shown);
  return "<figure><img alt=\"" + htmlEscape(caption) + "\" width=\"" + std::to_string(shown.cols) + "\" height=\"" +
         std::to_string(shown.rows) + "\" src=\"data:image/png;base64," + base64(png.data(), png.size()) +
         "\"><figcaption>" + htmlEscape(caption) + "</figcaption></figure>\n";
}

}  // namespace

std::string frameOverlaysHtml(const RunInputs& in, int maxSidePx, std::size_t maxFrames) {
  if (in.slice_records.empty() && !in.plus)
    return "";  // contours, not images: no frame to show
  const std::vector<Chosen> chosen = chooseFrames(in, maxFrames);
  if (chosen.empty()) return "";
  // The images, read once each (a PLUS recording is streamed up to the last frame needed).
  std::vector<cv::Mat> images(chosen.size());
  std::vector<Mat4> poses(chosen.size());
  std::string problems;
  if (in.plus) {
    std::vector<std::size_t> order(chosen.size());
    for (std::size_t c = 0; c < order.size(); ++c) order[c] = c;
    const auto frameOf = [&](std::size_t c) { return in.plus->frames[std::size_t(in.planes[chosen[c].plane].slice)]; };
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return frameOf(a) < frameOf(b); });
    try {
      MetaImageFrames reader(in.plus->header);
      for (const std::size_t c : order) {
        while (reader.index() < frameOf(c)) reader.next();
        if (reader.index() == frameOf(c)) images[c] = orientedFrame(*in.plus, reader.next());
        poses[c] = in.plus->image_to_reference[std::size_t(in.planes[chosen[c].plane].slice)];
      }
    } catch (const std::exception& e) {
      problems = e.what();
    }
  } else {
    for (std::size_t c = 0; c < chosen.size(); ++c) {
      const SliceRecord& record = in.slice_records[std::size_t(in.planes[chosen[c].plane].slice)];
      poses[c] = record.image_to_world;
      try {
        images[c] = readGreyImage(record.image_resolved, in.config.input_path, "image");
      } catch (const std::exception& e) {
        problems += std::string(problems.empty() ? "" : "; ") + e.what();
      }
    }
  }
  std::string html = "<p>Segmented contours drawn over their images (material colours as in the 3D view; the field of view "
                     "in blue when a mask narrows it).</p>\n<div class=\"frames\">\n";
  for (std::size_t c = 0; c < chosen.size(); ++c) {
    if (images[c].empty()) continue;
    const std::size_t i = chosen[c].plane;
    const CuttingPlane& p = in.planes[i];
    const std::vector<Section>& sections =
        i < in.labelled.size() && !in.labelled[i].empty() ? in.labelled[i] : p.sections;
    const double scale = std::min(1.0, double(maxSidePx) / double(std::max(images[c].cols, images[c].rows)));
    html += figure(overlay(images[c], poses[c], p, sections, scale),
                   "slice " + std::to_string(p.slice) + " (" + p.name + "): " + chosen[c].why);
  }
  html += "</div>\n";
  if (!problems.empty()) html += "<p class=\"hint\">Some images could not be read again: " + htmlEscape(problems) + "</p>\n";
  return html;
}

}  // namespace xsect

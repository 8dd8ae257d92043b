// Slices -> cutting planes with sections (see load_sections.h).
#include "pipeline/load_sections.h"

#include <tbb/parallel_for.h>

#include <map>

#include "geometry/core/plane_of_pose.h"
#include "io/file_hash.h"
#include "io/image_io.h"
#include "io/input_error.h"
#include "pipeline/machine_memory.h"
#include "segmentation/field_of_view.h"
#include "segmentation/series_threshold.h"

namespace xsect {

std::vector<SliceRecord> mergeRepeatedSlices(std::vector<SliceRecord> slices, std::vector<std::string>* warnings) {
  std::map<std::string, std::size_t> first;  // identity -> first slice with it
  std::vector<SliceRecord> kept;
  for (std::size_t i = 0; i < slices.size(); ++i) {
    std::string key = sha256File(slices[i].image_resolved) + "|" +
                      (slices[i].fov_resolved ? sha256File(*slices[i].fov_resolved) : std::string("-")) + "|";
    const Mat4& m = slices[i].image_to_world;
    key.append(reinterpret_cast<const char*>(m.data()), sizeof(double) * 16);
    const auto [it, inserted] = first.emplace(key, i);
    if (inserted) {
      kept.push_back(std::move(slices[i]));
    } else if (warnings) {
      warnings->push_back("slices[" + std::to_string(i) + "] (" + slices[i].image + ") repeats slices[" +
                          std::to_string(it->second) + "] (the same image at the same pose): merged");
    }
  }
  return kept;
}

std::vector<CuttingPlane> sectionsFromSlices(const std::vector<SliceRecord>& slices,
                                             const std::string& listing_file,
                                             const SegmentationParams& params,
                                             std::vector<std::string>* warnings,
                                             double* thresholdUsed,
                                             std::vector<std::vector<Section>>* labelled) {
  const int n = int(slices.size());
  std::vector<CuttingPlane> planes(n);
  std::vector<char> touches(n, 0);
  // Every frame is held while the series is segmented: its decoded size, from the headers, is
  // checked against this machine's memory before any image is decoded (issue 15, item 3). Header
  // errors are therefore reported before decoding errors, each for the first slice that has one.
  double bytes = 0;
  for (int i = 0; i < n; ++i) {
    const std::string key = "slices[" + std::to_string(i) + "]";
    bytes += double(greyImageBytes(slices[i].image_resolved, listing_file, key + ".image"));
    if (slices[i].fov_resolved) bytes += double(greyImageBytes(*slices[i].fov_resolved, listing_file, key + ".fov"));
  }
  const double memory = physicalMemoryBytes();
  if (memory > 0 && bytes > 0.5 * memory)
    throw InputError(listing_file, "slices",
                     "the " + std::to_string(n) + " frames take " + std::to_string(std::int64_t(bytes / 1e6)) +
                         " MB decoded, more than half of this machine's memory (" +
                         std::to_string(std::int64_t(memory / 1e6)) + " MB)");
  // Read all images first (errors are reported for the first bad slice, deterministically).
  std::vector<cv::Mat> images(n), fovs(n);
  for (int i = 0; i < n; ++i) {
    const std::string key = "slices[" + std::to_string(i) + "]";
    images[i] = readGreyImage(slices[i].image_resolved, listing_file, key + ".image");
    if (slices[i].fov_resolved) {
      cv::Mat f = readGreyImage(*slices[i].fov_resolved, listing_file, key + ".fov");
      if (f.size() != images[i].size())
        throw InputError(listing_file, key + ".fov", "field-of-view mask size differs from the image");
      if (f.depth() != CV_8U) f.convertTo(f, CV_8U, 1.0 / 256.0);
      fovs[i] = f != 0;
    }
  }
  // Otsu: one threshold for the series, from the pooled histogram (series_threshold.h).
  SegmentationParams perSlice = params;
  if (params.method == SegmentationMethod::otsu) {
    perSlice.method = SegmentationMethod::threshold;
    perSlice.threshold = otsuThresholdOfSeries(images, fovs, params.sigma_px);
    if (thresholdUsed) *thresholdUsed = perSlice.threshold;
  } else if (thresholdUsed) {
    *thresholdUsed = params.method == SegmentationMethod::labels ? 0.5 : params.threshold;
  }
  if (labelled) labelled->assign(std::size_t(n), {});
  tbb::parallel_for(0, n, [&](int i) {
    Vec2 spacing;
    CuttingPlane& cp = planes[i];
    cp.slice = i;
    cp.name = slices[i].image;
    cp.plane = planeOfPose(slices[i].image_to_world, &spacing);
    cp.pixel_mm = std::min(spacing.x(), spacing.y());
    cp.extent.min = Vec2::Zero();
    cp.extent.max = Vec2((images[i].cols - 1) * spacing.x(), (images[i].rows - 1) * spacing.y());
    cp.field_of_view = fieldOfViewRings(fovs[i], spacing);
    if (!fovs[i].empty() && cv::countNonZero(fovs[i]) == 0) cp.extent = PlaneRect{};  // observed nowhere
    const bool perLabel = perSlice.method == SegmentationMethod::labels && labelled;
    if (perLabel && !perSlice.merge_labels)
      (*labelled)[std::size_t(i)] = segmentSlice(images[i], fovs[i], spacing, perSlice).sections;
    cv::Mat input = images[i];
    if (perSlice.method == SegmentationMethod::labels) {  // the union of the labels: the geometry reconstructed
      input = cv::Mat(images[i].size(), CV_8U);
      input.setTo(0);
      input.setTo(1, images[i] != 0);
    }
    SegmentedSlice seg = segmentSlice(input, fovs[i], spacing, perSlice);
    cp.sections = std::move(seg.sections);
    touches[i] = seg.touches_fov_edge;
  });
  if (warnings) {
    int count = 0;
    std::string first;
    for (int i = 0; i < n; ++i)
      if (touches[i]) {
        if (count++ < 5) first += (first.empty() ? "" : ", ") + std::to_string(i);
      }
    if (count)
      warnings->push_back(std::to_string(count) +
                          " slice(s) have a section touching the edge of the image or field of view "
                          "(the object is not fully in view), e.g. slice " + first);
  }
  return planes;
}

}  // namespace xsect

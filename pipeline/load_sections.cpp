// Slices -> cutting planes with sections (see load_sections.h).
#include "pipeline/load_sections.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <functional>
#include <map>
#include <mutex>

#include "geometry/core/plane_of_pose.h"
#include "io/file_hash.h"
#include "io/image_header.h"
#include "io/image_io.h"
#include "io/input_error.h"
#include "segmentation/acoustic_shadows.h"
#include "segmentation/field_of_view.h"
#include "segmentation/grey_field.h"
#include "segmentation/pixel_settings.h"
#include "segmentation/series_threshold.h"
#include "segmentation/setting_limits.h"

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

namespace {

/// One frame decoded: its image and its field-of-view mask (empty: the whole image is observed).
struct Frame {
  cv::Mat image, fov;
  Vec2 spacing = Vec2::Ones();  ///< mm per pixel along i and j (the pose's)
};

cv::Mat readFieldOfView(const std::string& path, const std::string& listing_file, const std::string& key) {
  cv::Mat m = readGreyImage(path, listing_file, key);
  if (m.depth() != CV_8U) m.convertTo(m, CV_8U, 1.0 / 256.0);
  return m != 0;
}

/// A field-of-view mask file that several frames name (a probe's sector): decoded and traced once
/// instead of once per frame (issue 17: 2000 frames, one mask, traced in 40% of segmentation).
struct SharedFieldOfView {
  cv::Mat mask;               ///< non-zero where observed
  std::exception_ptr error;   ///< decoding failed (the message names the first slice using it)
  std::map<std::pair<double, double>, std::vector<Ring>> rings;  ///< per pixel spacing (x, y)
};

/// The shared masks by file, and per slice the rings of its mask at its spacing (null: its mask
/// is its own, traced with its frame).
struct SharedFieldsOfView {
  std::map<std::string, SharedFieldOfView> byFile;
  std::vector<const std::vector<Ring>*> ringsOfSlice;
};

Vec2 pixelSpacing(const SliceRecord& slice) {
  Vec2 spacing;
  planeOfPose(slice.image_to_world, &spacing);
  return spacing;
}

SharedFieldsOfView sharedFieldsOfView(const std::vector<SliceRecord>& slices, const std::string& listing_file) {
  std::map<std::string, int> users, first;
  for (std::size_t i = 0; i < slices.size(); ++i)
    if (slices[i].fov_resolved) {
      ++users[*slices[i].fov_resolved];
      first.emplace(*slices[i].fov_resolved, int(i));
    }
  SharedFieldsOfView out;
  for (const auto& [path, count] : users) {
    if (count < 2) continue;
    SharedFieldOfView& s = out.byFile[path];
    try {
      s.mask = readFieldOfView(path, listing_file, "slices[" + std::to_string(first[path]) + "].fov");
    } catch (...) {
      s.error = std::current_exception();
    }
  }
  out.ringsOfSlice.assign(slices.size(), nullptr);
  for (std::size_t i = 0; i < slices.size(); ++i) {
    if (!slices[i].fov_resolved) continue;
    const auto it = out.byFile.find(*slices[i].fov_resolved);
    if (it == out.byFile.end() || it->second.error) continue;
    const Vec2 spacing = pixelSpacing(slices[i]);
    auto& rings = it->second.rings;
    auto r = rings.find({spacing.x(), spacing.y()});
    if (r == rings.end()) r = rings.emplace(std::make_pair(spacing.x(), spacing.y()), fieldOfViewRings(it->second.mask, spacing)).first;
    out.ringsOfSlice[i] = &r->second;
  }
  return out;
}

/// The grey values of a series whose frames have different bit depths (issue 48), brought to one
/// depth so that one threshold (fixed or Otsu's) means the same grey in every frame: the depth
/// most frames have (the first frame's on a tie) is the series'; a frame of the other depth is
/// scaled full range to full range (8 -> 16 bits: x 257, 16 -> 8 bits: / 257, kept in floating
/// point). Labels are identities, not greys: never scaled.
struct SeriesDepth {
  int bits = 8;                    ///< the series' depth: 8 or 16
  std::vector<double> grey_scale;  ///< per slice: 1, 257 or 1/257
  std::string warning;             ///< names the frames scaled, when any is
};

SeriesDepth seriesDepth(const std::vector<int>& bits, const SegmentationParams& params) {
  SeriesDepth d;
  const auto deep = [](int b) { return b > 8; };
  const std::size_t n16 = std::size_t(std::count_if(bits.begin(), bits.end(), deep));
  if (bits.empty()) return d;
  d.bits = 2 * n16 > bits.size() || (2 * n16 == bits.size() && deep(bits.front())) ? 16 : 8;
  d.grey_scale.assign(bits.size(), 1.0);
  if (n16 == 0 || n16 == bits.size() || params.method == SegmentationMethod::labels) return d;
  std::string names;
  int scaled = 0;
  for (std::size_t i = 0; i < bits.size(); ++i) {
    if ((deep(bits[i]) ? 16 : 8) == d.bits) continue;
    d.grey_scale[i] = d.bits == 16 ? 257.0 : 1.0 / 257.0;
    if (scaled++ < 5) names += (names.empty() ? "" : ", ") + std::to_string(i);
  }
  d.warning = "the series mixes 8- and 16-bit images: " + std::to_string(scaled) + " of " +
              std::to_string(bits.size()) + " (slice " + names + (scaled > 5 ? ", ..." : "") + ") are " +
              (d.bits == 16 ? "8-bit" : "16-bit") + " among " + (d.bits == 16 ? "16-bit" : "8-bit") +
              " ones; their grey values were scaled full range to full range (" +
              (d.bits == 16 ? "x 257" : "/ 257") + ") so that segmentation.threshold (" + std::to_string(d.bits) +
              "-bit units) and Otsu's threshold mean the same grey in every frame";
  return d;
}

Frame readFrame(const SliceRecord& slice, int i, const std::string& listing_file, const SharedFieldsOfView& all,
                double grey_scale) {
  const std::map<std::string, SharedFieldOfView>& shared = all.byFile;
  const std::string key = "slices[" + std::to_string(i) + "]";
  Frame f;
  f.spacing = pixelSpacing(slice);
  f.image = readGreyImage(slice.image_resolved, listing_file, key + ".image");
  if (grey_scale != 1.0) f.image.convertTo(f.image, CV_32F, grey_scale);
  if (slice.fov_resolved) {
    const auto it = shared.find(*slice.fov_resolved);
    if (it != shared.end() && it->second.error) std::rethrow_exception(it->second.error);
    f.fov = it != shared.end() ? it->second.mask : readFieldOfView(*slice.fov_resolved, listing_file, key + ".fov");
    if (f.fov.size() != f.image.size())
      throw InputError(listing_file, key + ".fov", "field-of-view mask size differs from the image");
  }
  return f;
}

/// The frames worked on so far, for a progress callback: with Otsu's method the series is read
/// twice (histograms, then segmentation), each reading of a frame counting for half of it.
class FrameCount {
 public:
  FrameCount(const std::function<void(std::int64_t, std::int64_t)>& report, int frames, int readings)
      : report_(report), frames_(frames), readings_(readings) {}
  /// One frame read and worked on (from any thread).
  void operator()() {
    if (report_) report_((readings_done_.fetch_add(1, std::memory_order_relaxed) + 1) / readings_, frames_);
  }

 private:
  const std::function<void(std::int64_t, std::int64_t)>& report_;
  const std::int64_t frames_, readings_;
  std::atomic<std::int64_t> readings_done_{0};
};

/// How many times the series is read: twice for Otsu's threshold or the automatic inside side
/// (seriesParams).
int readingsOf(const SegmentationParams& params) {
  return params.method != SegmentationMethod::labels &&
                 (params.method == SegmentationMethod::otsu || params.method == SegmentationMethod::min_error ||
                  params.inside == InsideSide::automatic)
             ? 2
             : 1;
}

/// Runs work(i, frame) for every frame, in parallel; each task decodes its frame and releases it
/// when done, so that at most one frame per thread is held. A failure is reported for the first
/// failing frame (the lowest index), as a sequential reading would. `count` ticks per frame.
template <typename Work>
void forEachFrame(const std::vector<SliceRecord>& slices, const std::string& listing_file,
                  const SharedFieldsOfView& shared, const SeriesDepth& depth, FrameCount& count, const Work& work) {
  const int n = int(slices.size());
  std::vector<std::exception_ptr> failed(static_cast<std::size_t>(n));
  tbb::parallel_for(0, n, [&](int i) {
    try {
      work(i, readFrame(slices[std::size_t(i)], i, listing_file, shared, depth.grey_scale[std::size_t(i)]));
    } catch (...) {
      failed[std::size_t(i)] = std::current_exception();
    }
    count();
  });
  for (const std::exception_ptr& e : failed)
    if (e) std::rethrow_exception(e);
}

/// The pixel axes of a pose that are not orthogonal (a calibration fitted by least squares, as
/// PLUS's ImageToProbe): segmentation works in (i sx, j sy); this is the exact in-plane map from
/// there to the plane's (u, v) frame (identity for orthogonal axes).
Eigen::Matrix2d pixelShear(const Mat4& pose, const Plane& plane) {
  const Vec3 c1 = pose.block<3, 1>(0, 1);
  const double sy = c1.norm();
  Eigen::Matrix2d m;
  m << 1.0, c1.dot(plane.u) / sy, 0.0, c1.dot(plane.v) / sy;
  return m;
}

void shearRing(const Eigen::Matrix2d& m, Ring& ring) {
  for (Vec2& q : ring) q = m * q;
}

/// Refuses a segmentation setting the image cannot take (segmentation/setting_limits.h), naming the
/// key in the settings' file and the frame.
void checkSettings(const SegmentationParams& params, cv::Size size, const Vec2& spacing, double observed_pixels,
                   const std::string& settings_file, const std::string& frame) {
  if (const std::optional<SettingProblem> p = segmentationSettingProblem(params, size, spacing, observed_pixels))
    throw InputError(settings_file, "segmentation." + p->key, p->what + " (" + frame + ")");
}

/// What planeOfFrame says of a frame, bits of one char per frame.
constexpr char kTouches = 1;   ///< a section reaches the edge of the image or field of view
constexpr char kRepaired = 2;  ///< simplified contours crossed and were made simple

/// One frame segmented into its cutting plane (stage 2): the plane of its pose, the image
/// rectangle and field of view, the sections in the plane's (u, v) mm frame. Method labels also
/// give `labelled`, the sections of each label value; `touches` receives the frame's flags
/// (kTouches, kRepaired).
CuttingPlane planeOfFrame(int slice, const std::string& name, const Mat4& pose, const Frame& frame,
                          const std::vector<Ring>* sharedRings, const SegmentationParams& perSlice,
                          const std::string& settings_file, std::vector<Section>* labelled, char* touches) {
  Vec2 spacing;
  CuttingPlane cp;
  cp.slice = slice;
  cp.name = name;
  cp.plane = planeOfPose(pose, &spacing);
  const int observed = frame.fov.empty() ? int(frame.image.total()) : cv::countNonZero(frame.fov);
  const SegmentationParams params = inPixels(perSlice, spacing);
  checkSettings(params, frame.image.size(), spacing, double(observed), settings_file, name);
  cp.pixel_mm = std::min(spacing.x(), spacing.y());
  cp.extent.min = Vec2::Zero();
  cp.extent.max = Vec2((frame.image.cols - 1) * spacing.x(), (frame.image.rows - 1) * spacing.y());
  if (observed == 0) cp.extent = PlaneRect{};  // observed nowhere
  const bool perLabel = params.method == SegmentationMethod::labels && labelled;
  SegmentedSlice seg;
  try {
    bool labelsRepaired = false;
    if (perLabel && !params.merge_labels) {
      SegmentedSlice labels = segmentSlice(frame.image, frame.fov, spacing, params);
      *labelled = std::move(labels.sections);
      labelsRepaired = labels.contours_repaired;
    }
    cv::Mat input = frame.image;
    if (params.method == SegmentationMethod::labels) {  // the union of the labels: the geometry reconstructed
      input = cv::Mat(frame.image.size(), CV_8U);
      input.setTo(0);
      input.setTo(1, frame.image != 0);
    }
    seg = segmentSlice(input, frame.fov, spacing, params);
    seg.contours_repaired |= labelsRepaired;
  } catch (const cv::Exception& e) {  // a setting OpenCV cannot apply to this image
    throw InputError(settings_file, "segmentation",
                     "OpenCV cannot segment " + name + " with these settings: " + e.err);
  } catch (const std::invalid_argument& e) {  // simplified contours no repair can hold in doubles
    throw InputError(settings_file, "segmentation.simplify_mm", std::string(e.what()) + " (" + name + ")");
  }
  cp.sections = std::move(seg.sections);
  // The field of view: the frame's, or what its shadows left of it (segmentation.shadows).
  cp.field_of_view = !seg.observed.empty() ? fieldOfViewRings(seg.observed, spacing)
                     : sharedRings         ? *sharedRings
                                           : fieldOfViewRings(frame.fov, spacing);
  // No ring from a mask that is not all observed: nothing was (every beam in shadow, or slivers
  // under a pixel); an empty field_of_view would say the whole plane was.
  const cv::Mat& seen = !seg.observed.empty() ? seg.observed : frame.fov;
  if (cp.field_of_view.empty() && !seen.empty() && cv::countNonZero(seen) < int(seen.total())) cp.extent = PlaneRect{};
  *touches = char((seg.touches_fov_edge ? kTouches : 0) | (seg.contours_repaired ? kRepaired : 0));
  const Vec3 c0 = pose.block<3, 1>(0, 0), c1 = pose.block<3, 1>(0, 1);
  if (std::abs(c0.dot(c1)) > 1e-9 * c0.norm() * c1.norm()) {
    // Skewed pixel axes: every ring through the exact map; the image rectangle becomes a
    // parallelogram, kept as its bounds and, unless a field of view already says it, its ring.
    const Eigen::Matrix2d m = pixelShear(pose, cp.plane);
    const auto shearSections = [&](std::vector<Section>& sections) {
      for (Section& sec : sections) {
        shearRing(m, sec.outer);
        for (Ring& hole : sec.holes) shearRing(m, hole);
      }
    };
    shearSections(cp.sections);
    if (labelled) shearSections(*labelled);
    if (cp.field_of_view.empty() && cp.extent.max != cp.extent.min)
      cp.field_of_view = {Ring{cp.extent.min, Vec2(cp.extent.max.x(), cp.extent.min.y()), cp.extent.max,
                               Vec2(cp.extent.min.x(), cp.extent.max.y())}};
    for (Ring& ring : cp.field_of_view) shearRing(m, ring);
    if (cp.extent.max != cp.extent.min) {
      Vec2 lo = Vec2::Constant(1e300), hi = -lo;
      for (const Ring& ring : cp.field_of_view)
        for (const Vec2& q : ring) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
      cp.extent = {lo, hi};
    }
  }
  return cp;
}

/// The segmentation of every frame of a series: Otsu's method gives one threshold for the series,
/// from the histogram pooled over a first reading of the frames (series_threshold.h; integer
/// counts: the same whatever the order), applied as a fixed threshold; inside: auto is resolved
/// from the same reading (the border histogram, insideOfBorder), once for the series.
/// @param bits        the series' sample depth (8 or 16), from its first frame
/// @param readFrames  runs its argument on every frame (i, frame), in any order
SegmentationParams seriesParamsOfFrames(const SegmentationParams& params, int bits,
                                const std::function<void(const std::function<void(int, const Frame&)>&)>& readFrames,
                                int n) {
  SegmentationParams perSlice = params;
  const double scale = seriesGreyScale(bits);
  perSlice.grey_to_8bit = scale;
  // The series' threshold of a histogram, in grey units (a fixed one stays as given).
  const auto thresholdOf = [&](const GreyHistogram& h) {
    if (params.method == SegmentationMethod::otsu) return otsuThresholdOfPooled(h, scale);
    if (params.method == SegmentationMethod::min_error) return minimumErrorThresholdOfHistogram(h) / scale;
    return params.threshold;
  };
  if (params.method == SegmentationMethod::labels) {
    perSlice.threshold = 0.5;
  } else if (readingsOf(params) == 2 && n > 0) {
    ObservedHistograms pooled;
    if (params.shadows == ShadowRule::unobserved) {
      // Shadows are out of the view, so out of the histogram: a first threshold from every
      // observed pixel (shadows are darker than anything), then the histogram of the pixels out
      // of its shadows gives the threshold applied (shadows, object and tissue are three classes;
      // a two-class rule would split the shadows from the rest).
      ShadowedHistograms joint;
      std::mutex pooling;
      readFrames([&](int, const Frame& f) {
        const SegmentationParams px = inPixels(perSlice, f.spacing);
        const cv::Mat grey = greyField(f.image, f.fov, px);
        const ShadowedHistograms h = shadowedHistograms(grey, f.fov, beamTailMaximum(grey, f.fov, px.beam_apex_px), scale);
        const std::lock_guard<std::mutex> lock(pooling);
        joint.add(h);
      });
      if (params.method == SegmentationMethod::threshold) {
        pooled = outsideShadow(joint, params.threshold * scale);
      } else {
        const double t8 = thresholdOutOfShadows(joint, [&](const GreyHistogram& g) { return thresholdOf(g) * scale; });
        perSlice.method = SegmentationMethod::threshold;
        perSlice.threshold = t8 / scale;
        pooled = outsideShadow(joint, t8);
      }
    } else {
      std::vector<ObservedHistograms> histograms(static_cast<std::size_t>(n));
      readFrames([&](int i, const Frame& f) {
        histograms[std::size_t(i)] = observedHistograms(greyField(f.image, f.fov, inPixels(perSlice, f.spacing)), f.fov, scale);
      });
      for (const ObservedHistograms& h : histograms)
        for (std::size_t b = 0; b < 256; ++b) pooled.observed[b] += h.observed[b], pooled.border[b] += h.border[b];
    }
    if (perSlice.method != SegmentationMethod::threshold) {
      perSlice.method = SegmentationMethod::threshold;
      perSlice.threshold = thresholdOf(pooled.observed);
    }
    if (params.inside == InsideSide::automatic) perSlice.inside = insideOfBorder(pooled.border, perSlice.threshold * scale);
    if (params.method == SegmentationMethod::min_error)
      perSlice.core_threshold = coreThresholdOfClasses(minimumErrorClassesAt(pooled.observed, perSlice.threshold * scale), perSlice.inside) / scale;
  }
  if (perSlice.inside == InsideSide::automatic) perSlice.inside = InsideSide::above;  // no frame
  return perSlice;
}

/// seriesParamsOfFrames, with what OpenCV cannot do with these settings on these frames (a
/// filter larger than a frame, a beam apex beyond any image) an input error naming the settings.
SegmentationParams seriesParams(const SegmentationParams& params, int bits,
                                const std::function<void(const std::function<void(int, const Frame&)>&)>& readFrames,
                                int n, const std::string& settings_file) {
  try {
    return seriesParamsOfFrames(params, bits, readFrames, n);
  } catch (const cv::Exception& e) {
    throw InputError(settings_file, "segmentation", "OpenCV cannot read the series with these settings: " + e.err);
  }
}

/// "N slice(s) have a section touching the edge..." and "N slice(s) had contours that
/// segmentation.simplify_mm made cross...", each when any frame's flags (kTouches, kRepaired) say so.
void touchingWarning(const std::vector<char>& flags, std::vector<std::string>& warnings) {
  for (const char flag : {kTouches, kRepaired}) {
    int count = 0;
    std::string first;
    for (std::size_t i = 0; i < flags.size(); ++i)
      if (flags[i] & flag) {
        if (count++ < 5) first += (first.empty() ? "" : ", ") + std::to_string(i);
      }
    if (!count) continue;
    warnings.push_back(std::to_string(count) + (flag == kTouches
                                                     ? " slice(s) have a section touching the edge of the image or field "
                                                       "of view (the object is not fully in view), e.g. slice "
                                                     : " slice(s) had contours that segmentation.simplify_mm made "
                                                       "cross: made simple (input.repair_contours), e.g. slice ") +
                        first);
  }
}

}  // namespace

std::vector<ImageHeader> sliceImageHeaders(const std::vector<SliceRecord>& slices, const std::string& listing_file) {
  std::vector<ImageHeader> headers;
  headers.reserve(slices.size());
  for (std::size_t i = 0; i < slices.size(); ++i) {
    const std::string key = "slices[" + std::to_string(i) + "]";
    headers.push_back(greyImageHeader(slices[i].image_resolved, listing_file, key + ".image"));
    if (slices[i].fov_resolved) greyImageHeader(*slices[i].fov_resolved, listing_file, key + ".fov");
  }
  return headers;
}

SegmentedSeries sectionsFromSlices(const std::vector<SliceRecord>& slices, const std::string& listing_file,
                                   const SegmentationParams& params, const std::string& settings_file,
                                   std::vector<ImageHeader> headers,
                                   const std::function<void(std::int64_t, std::int64_t)>& progress) {
  const int n = int(slices.size());
  SegmentedSeries out;
  std::vector<CuttingPlane>& planes = out.planes;
  planes.resize(std::size_t(n));
  std::vector<char> touches(n, 0);
  // Every header is read before any image is decoded (sliceImageHeaders), and the settings are
  // checked against each image's size then (issue 48), before any work. The frames are then read
  // and segmented as a stream (issue 17): each is decoded, segmented and released by one task, so
  // that loading holds the sections, not the series' images.
  if (headers.size() != slices.size()) headers = sliceImageHeaders(slices, listing_file);
  std::vector<int> bits(static_cast<std::size_t>(n), 8);
  for (int i = 0; i < n; ++i) {
    const ImageHeader& h = headers[std::size_t(i)];
    bits[std::size_t(i)] = h.bits_per_sample;
    const cv::Size size(int(h.width), int(h.height));
    checkSettings(inPixels(params, pixelSpacing(slices[i])), size, pixelSpacing(slices[i]), double(size.area()), settings_file,
                  "slice " + std::to_string(i) + ", " + slices[i].image);
  }
  const SeriesDepth depth = seriesDepth(bits, params);
  if (!depth.warning.empty()) out.warnings.push_back(depth.warning);
  const SharedFieldsOfView shared = sharedFieldsOfView(slices, listing_file);
  FrameCount count(progress, n, readingsOf(params));
  SegmentationParams perSlice = seriesParams(params, depth.bits,
                                             [&](const std::function<void(int, const Frame&)>& each) {
                                               forEachFrame(slices, listing_file, shared, depth, count, each);
                                             },
                                             n, settings_file);
  out.applied = perSlice;
  out.labelled.assign(std::size_t(n), {});
  forEachFrame(slices, listing_file, shared, depth, count, [&](int i, const Frame& frame) {
    planes[std::size_t(i)] = planeOfFrame(i, slices[std::size_t(i)].image, slices[std::size_t(i)].image_to_world, frame,
                                          shared.ringsOfSlice[std::size_t(i)], perSlice, settings_file,
                                          &out.labelled[std::size_t(i)], &touches[std::size_t(i)]);
  });
  touchingWarning(touches, out.warnings);
  return out;
}

SegmentedSeries sectionsFromMasks(const std::vector<PosedMask>& masks, const SegmentationParams& params,
                                  const std::string& settings_file) {
  SegmentedSeries out;
  // A mask is 0 outside and 1 (any non-zero) inside: segmented at 0.5 with every other setting
  // the configuration's (smoothing, opening, closing, minimum area, simplification).
  SegmentationParams perSlice = params;
  perSlice.method = SegmentationMethod::threshold;
  perSlice.threshold = 0.5;
  perSlice.inside = InsideSide::above;
  out.applied = perSlice;
  out.planes.resize(masks.size());
  out.labelled.assign(masks.size(), {});
  std::vector<char> touches(masks.size(), 0);
  for (std::size_t i = 0; i < masks.size(); ++i) {
    Frame frame;
    frame.image = cv::Mat(masks[i].mask.size(), CV_8U);
    frame.image.setTo(0);
    frame.image.setTo(1, masks[i].mask != 0);
    planeOfPose(masks[i].image_to_world, &frame.spacing);
    out.planes[i] = planeOfFrame(int(i), "mask " + std::to_string(i), masks[i].image_to_world, frame, nullptr,
                                 perSlice, settings_file, nullptr, &touches[i]);
  }
  touchingWarning(touches, out.warnings);
  return out;
}

namespace {

/// Runs work(k, frame) for every kept frame k of a PLUS sequence (k indexes seq.frames). The
/// compressed stream is read in order, in batches of a few frames per thread, each batch then
/// worked on in parallel and released: memory holds one batch, not the recording (issue 17).
/// `count` ticks per frame.
void forEachSequenceFrame(const PlusSequence& seq, bool labels, FrameCount& count,
                          const std::function<void(int, const Frame&)>& work) {
  MetaImageFrames reader(seq.header);
  // input.plus_masks: the masks are read in step with the frames and segmented instead; a mask's
  // non-zero pixels are inside (0/255 for thresholds; labels keep their values).
  std::optional<MetaImageFrames> masks;
  if (seq.masks) masks.emplace(*seq.masks);
  const int kept = int(seq.frames.size());
  const int batch = 32;
  std::vector<Frame> frames;
  int k = 0;
  for (int first = 0; first < kept; first += batch) {
    const int last = std::min(kept, first + batch);
    frames.assign(std::size_t(last - first), Frame{});
    for (; k < last; ++k) {
      while (reader.index() < seq.frames[std::size_t(k)]) reader.next();  // a skipped frame
      frames[std::size_t(k - first)].image = orientedFrame(seq, reader.next());
      if (masks) {
        while (masks->index() < seq.frames[std::size_t(k)]) masks->next();
        cv::Mat mask = orientedMask(seq, masks->next());
        if (!labels) mask = mask != 0;
        frames[std::size_t(k - first)].image = mask;
      }
      frames[std::size_t(k - first)].fov = seq.field_of_view;
      planeOfPose(seq.image_to_reference[std::size_t(k)], &frames[std::size_t(k - first)].spacing);
    }
    tbb::parallel_for(first, last, [&](int q) {
      work(q, frames[std::size_t(q - first)]);
      count();
    });
  }
  // Skipped frames after the last kept one are still read: the last frame verifies the compressed
  // stream's checksum and that it holds no more than DimSize says.
  while (reader.index() < reader.frames()) reader.next();
  if (masks)
    while (masks->index() < masks->frames()) masks->next();
}

}  // namespace

SegmentedSeries sectionsFromPlusSequence(const PlusSequence& seq, const SegmentationParams& settings,
                                         const std::string& settings_file,
                                         const std::function<void(std::int64_t, std::int64_t)>& progress) {
  const int n = int(seq.frames.size());
  SegmentedSeries out;
  // The beams start at the device set's fan apex, unless the configuration says where.
  SegmentationParams params = settings;
  if (!params.beam_apex_px && seq.device_set.fan)
    params.beam_apex_px = Vec2(seq.device_set.fan->origin_px[0], seq.device_set.fan->origin_px[1]);
  // input.plus_masks: the masks' non-zero pixels are inside (as 255 against a threshold of half);
  // what grey frames need (threshold, side, shadows, speckle) does not apply, the cleaning does.
  const bool labels = params.method == SegmentationMethod::labels;
  if (seq.masks && !labels) {
    std::vector<std::string> unused;
    if (settings.method != SegmentationMethod::threshold || settings.threshold != SegmentationParams().threshold)
      unused.push_back("method/threshold");
    if (settings.inside != InsideSide::above) unused.push_back("inside");
    if (settings.shadows != ShadowRule::keep) unused.push_back("shadows");
    if (settings.speckle_filter_mm > 0 || settings.speckle_filter_px > 0) unused.push_back("speckle_filter_mm");
    if (!unused.empty()) {
      std::string keys;
      for (const std::string& k : unused) keys += (keys.empty() ? "segmentation." : ", segmentation.") + k;
      out.warnings.push_back("input.plus_masks: the masks are segmented as masks (non-zero inside, at half their "
                          "range); " + keys + " apply to grey frames and were not used (report.json's "
                          "segmentation block shows them as configured)");
    }
    params.method = SegmentationMethod::threshold;
    params.threshold = 127.5;
    params.inside = InsideSide::above;
    params.shadows = ShadowRule::keep;
    params.speckle_filter_mm = 0;
    params.speckle_filter_px = 0;
  }
  std::vector<CuttingPlane>& planes = out.planes;
  planes.resize(std::size_t(n));
  std::vector<char> touches(static_cast<std::size_t>(n), 0);
  if (n > 0) {
    Vec2 spacing;
    planeOfPose(seq.image_to_reference.front(), &spacing);
    const cv::Size size(seq.header.width, seq.header.height);
    checkSettings(inPixels(params, spacing), size, spacing,
                  seq.field_of_view.empty() ? double(size.area()) : double(cv::countNonZero(seq.field_of_view)),
                  settings_file, "frame " + std::to_string(seq.frames.front()));
  }
  FrameCount count(progress, n, readingsOf(params));
  const SegmentationParams perSlice = seriesParams(
      params, seq.header.pixel == MetaPixelType::uint8 ? 8 : 16,
      [&](const std::function<void(int, const Frame&)>& each) { forEachSequenceFrame(seq, labels, count, each); }, n,
      settings_file);
  out.applied = perSlice;
  // The field of view is the device set's, one for the recording: traced once per pixel spacing.
  std::map<std::pair<double, double>, std::vector<Ring>> rings;
  std::vector<const std::vector<Ring>*> ringsOf(static_cast<std::size_t>(n), nullptr);
  if (!seq.field_of_view.empty())
    for (int k = 0; k < n; ++k) {
      Vec2 spacing;
      planeOfPose(seq.image_to_reference[std::size_t(k)], &spacing);
      auto r = rings.find({spacing.x(), spacing.y()});
      if (r == rings.end())
        r = rings.emplace(std::make_pair(spacing.x(), spacing.y()), fieldOfViewRings(seq.field_of_view, spacing)).first;
      ringsOf[std::size_t(k)] = &r->second;
    }
  out.labelled.assign(std::size_t(n), {});
  forEachSequenceFrame(seq, labels, count, [&](int k, const Frame& frame) {
    planes[std::size_t(k)] =
        planeOfFrame(k, "frame " + std::to_string(seq.frames[std::size_t(k)]), seq.image_to_reference[std::size_t(k)],
                     frame, ringsOf[std::size_t(k)], perSlice, settings_file, &out.labelled[std::size_t(k)],
                     &touches[std::size_t(k)]);
  });
  touchingWarning(touches, out.warnings);
  return out;
}

}  // namespace xsect

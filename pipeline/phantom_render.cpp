// Phantom slice rendering (see phantom_render.h).
#include "pipeline/phantom_render.h"

#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "geometry/core/plane_of_pose.h"
#include "geometry/core/random_streams.h"
#include "geometry/phantoms/vessel_tree.h"

namespace xsect {
namespace {

constexpr std::uint64_t kNoiseStream = 0x6e6f697365ULL;   // "noise"
constexpr std::uint64_t kJitterStream = 0x6a6974ULL;      // "jit"
constexpr std::uint64_t kDropStream = 0x64726f70ULL;      // "drop"
constexpr std::uint64_t kUltrasoundStream = 0x6563686fULL;  // "echo"

/// For a vessel tree, the sdf is the minimum over junctions of a value that is at least the
/// distance to the junction's nearest capsule minus its blend offset (vessel_tree.h). A junction
/// whose capsules all stay farther than radius + offset + 2 pixels from the plane is >= 2 pixels
/// everywhere on it, so it never decides a pixel below 1 pixel (the only ones not clamped to 0):
/// dropping it makes rendering ~N times faster and leaves every pixel value identical. (Shapes
/// without junctions, the plain union of capsules, drop tubes by the same rule.)
PhantomShape cullTubes(const PhantomShape& shape, const Plane& plane, double pixel_mm) {
  if (shape.tubes.empty()) return shape;
  auto farFrom = [&](const PhantomShape::Tube& t, double margin) {
    const double da = plane.signedDistance(shape.centre + shape.rotation * t.a);
    const double db = plane.signedDistance(shape.centre + shape.rotation * t.b);
    const double d = (da > 0) != (db > 0) ? 0.0 : std::min(std::abs(da), std::abs(db));
    return d > t.radius + margin;
  };
  PhantomShape out = shape;
  if (shape.junctions.empty()) {
    out.tubes.clear();
    for (const auto& t : shape.tubes)
      if (!farFrom(t, 2.0 * pixel_mm)) out.tubes.push_back(t);
    return out;
  }
  const double margin = vesselBlendOffset(shape) + 2.0 * pixel_mm;
  out.junctions.clear();
  for (const auto& J : shape.junctions) {
    bool near = !farFrom(shape.tubes[J.parent], margin);
    for (const int c : J.children) near = near || !farFrom(shape.tubes[c], margin);
    if (near) out.junctions.push_back(J);
  }
  return out;
}

/// The shape's signed distance at every pixel of the slice `pose` images, in pixels (CV_64F;
/// +1e6 where no tube of a vessel tree comes near), and whether the shape crosses the image's edge
/// or the field of view's (the slice is clipped).
cv::Mat pixelSignedDistances(const PhantomShape& shape, const Mat4& pose, int width, int height, const cv::Mat& fov,
                             bool* clipped) {
  const double px = pose.block<3, 1>(0, 0).norm();
  const PhantomShape local = cullTubes(shape, planeOfPose(pose), px);
  const bool noTubes =
      local.kind == ShapeKind::vessel_tree &&
      (local.tubes.empty() || (!shape.junctions.empty() && local.junctions.empty()));
  cv::Mat d(height, width, CV_64F, cv::Scalar(1e6));
  std::vector<char> rowClipped(std::size_t(height), 0);
  const Vec3 o = pose.block<3, 1>(0, 3), du = pose.block<3, 1>(0, 0), dv = pose.block<3, 1>(0, 1);
  if (!noTubes)
    tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
      for (int j = rows.begin(); j != rows.end(); ++j) {
        double* row = d.ptr<double>(j);
        const std::uint8_t* mask = fov.empty() ? nullptr : fov.ptr<std::uint8_t>(j);
        for (int i = 0; i < width; ++i) {
          const double sdf = signedDistance(local, o + double(i) * du + double(j) * dv);
          row[i] = sdf / px;
          if (sdf < 0 && (i == 0 || j == 0 || i == width - 1 || j == height - 1 || (mask && mask[i] == 0)))
            rowClipped[std::size_t(j)] = 1;
        }
      }
    });
  *clipped = std::find(rowClipped.begin(), rowClipped.end(), 1) != rowClipped.end();
  return d;
}

}  // namespace

RenderedSlice renderSlice(const PhantomShape& shape, const Mat4& pose, int width, int height,
                          const cv::Mat& fov, const PhantomDegradations& degr, std::uint64_t seed,
                          int index) {
  RenderedSlice out;
  const cv::Mat distance = pixelSignedDistances(shape, pose, width, height, fov, &out.clipped);
  cv::Mat img(height, width, CV_32F);
  for (int j = 0; j < height; ++j) {
    const double* d = distance.ptr<double>(j);
    float* row = img.ptr<float>(j);
    for (int i = 0; i < width; ++i) row[i] = float(std::clamp(127.5 * (1.0 - d[i]), 0.0, 255.0));
  }
  // Degradations in the order a scanner produces them: speckle (multiplicative, in the tissue),
  // blur (the point-spread function), then additive electronic noise.
  if (degr.speckle > 0 || degr.noise_sigma > 0 || degr.blur_sigma_px > 0) {
    std::mt19937_64 rng = makeStream(seed, kNoiseStream, std::uint64_t(index));
    if (degr.speckle > 0)
      for (int j = 0; j < height; ++j) {
        float* row = img.ptr<float>(j);
        for (int i = 0; i < width; ++i)
          row[i] *= float(std::max(0.0, 1.0 + degr.speckle * standardNormal(rng)));
      }
    if (degr.blur_sigma_px > 0)
      cv::GaussianBlur(img, img, cv::Size(0, 0), degr.blur_sigma_px, degr.blur_sigma_px,
                       cv::BORDER_REPLICATE);
    if (degr.noise_sigma > 0)
      for (int j = 0; j < height; ++j) {
        float* row = img.ptr<float>(j);
        for (int i = 0; i < width; ++i) row[i] += float(degr.noise_sigma * standardNormal(rng));
      }
  }
  img.convertTo(out.image, CV_8U);  // rounds and saturates to [0, 255]
  if (!fov.empty()) out.image.setTo(0, fov == 0);
  return out;
}

RenderedSlice renderUltrasoundSlice(const PhantomShape& shape, const Mat4& pose, int width, int height,
                                    const cv::Mat& fov, const std::optional<SectorFov>& sector,
                                    const PhantomDegradations& degr, std::uint64_t seed, int index) {
  const UltrasoundLook& look = degr.ultrasound;
  const double px = pose.block<3, 1>(0, 0).norm();
  RenderedSlice out;
  // The signed distance of every pixel, in pixels (far outside where no tube comes near).
  cv::Mat sdf;
  pixelSignedDistances(shape, pose, width, height, fov, &out.clipped).convertTo(sdf, CV_32F);
  cv::min(sdf, 1e6, sdf);

  // Beam coordinates: (angle, radius) from the sector's apex, or (column, row).
  const auto beam = [&](double i, double j) -> std::pair<double, double> {
    if (!sector) return {i, j};
    return {std::atan2(i - sector->apex_i, j - sector->apex_j), std::hypot(i - sector->apex_i, j - sector->apex_j)};
  };
  double across0 = 0.1 * width, across1 = 0.9 * width, depth0 = 0.15 * height, depth1 = 0.5 * height;
  double halfWidth = 0.05 * width;
  if (sector) {
    across0 = -0.8 * sector->half_angle_rad, across1 = -across0;
    depth0 = sector->near_px + 0.15 * (sector->far_px - sector->near_px);
    depth1 = sector->near_px + 0.5 * (sector->far_px - sector->near_px);
    halfWidth = 0.1 * sector->half_angle_rad;
  }
  struct Reflector {
    double across, depth;
  };
  std::mt19937_64 rng = makeStream(seed, kUltrasoundStream, std::uint64_t(index));
  std::vector<Reflector> reflectors;
  const double thick = 3.0;  // pixels along the beam
  for (int k = 0; k < look.reflectors; ++k)
    for (int attempt = 0; attempt < 30; ++attempt) {
      const Reflector r{uniform(rng, across0, across1), uniform(rng, depth0, depth1)};
      bool clear = true;
      for (int j = 0; j < height && clear; ++j)
        for (int i = 0; i < width && clear; ++i) {
          const auto [a, d] = beam(i, j);
          if (std::abs(a - r.across) <= halfWidth && d >= r.depth && sdf.at<float>(j, i) < 2.0f) clear = false;
        }
      if (!clear) continue;
      reflectors.push_back(r);
      break;
    }

  std::sort(reflectors.begin(), reflectors.end(), [](const Reflector& a, const Reflector& b) { return a.depth < b.depth; });

  // Speckle: the modulus of a complex Gaussian field smoothed to the grain, unit mean.
  cv::Mat re(height, width, CV_32F), im(height, width, CV_32F);
  for (int j = 0; j < height; ++j) {
    float *a = re.ptr<float>(j), *b = im.ptr<float>(j);
    for (int i = 0; i < width; ++i) a[i] = float(standardNormal(rng)), b[i] = float(standardNormal(rng));
  }
  const double grain = std::max(0.5, look.grain_mm / px);
  cv::GaussianBlur(re, re, cv::Size(0, 0), grain, grain, cv::BORDER_REFLECT);
  cv::GaussianBlur(im, im, cv::Size(0, 0), grain, grain, cv::BORDER_REFLECT);
  cv::Mat amplitude;
  cv::magnitude(re, im, amplitude);
  const double meanAmplitude = cv::mean(amplitude)[0];

  cv::Mat img(height, width, CV_32F);
  for (int j = 0; j < height; ++j) {
    const float* d = sdf.ptr<float>(j);
    const float* a = amplitude.ptr<float>(j);
    float* out = img.ptr<float>(j);
    for (int i = 0; i < width; ++i) {
      const double w = std::clamp(0.5 - double(d[i]), 0.0, 1.0);  // inside fraction of the pixel
      double echo = (1.0 - w) + w * look.object_echo;
      const auto [across, depth] = beam(i, j);
      // Along the beam, each reflector passed leaves 5% of the echo; a reflector is itself seen
      // through those above it (one inside another's shadow stays dark).
      double passed = 1.0;
      bool onReflector = false;
      for (const Reflector& r : reflectors) {  // by depth
        if (std::abs(across - r.across) > halfWidth || depth < r.depth) continue;
        if (depth < r.depth + thick) {
          onReflector = true;
          break;
        }
        passed *= 0.05;
      }
      echo = (onReflector ? 3.0 : echo) * passed;
      out[i] = float(100.0 * echo * a[i] / meanAmplitude);
    }
  }
  if (degr.noise_sigma > 0)
    for (int j = 0; j < height; ++j) {
      float* row = img.ptr<float>(j);
      for (int i = 0; i < width; ++i) row[i] += float(degr.noise_sigma * standardNormal(rng));
    }
  img.convertTo(out.image, CV_8U);
  if (!fov.empty()) out.image.setTo(0, fov == 0);
  return out;
}

RenderedSlice renderLabelSlice(const PhantomShape& shape, const Mat4& pose, int width, int height,
                               const cv::Mat& fov) {
  const double px = pose.block<3, 1>(0, 0).norm();
  const PhantomShape local = cullTubes(shape, planeOfPose(pose), px);
  const bool noTubes =
      local.kind == ShapeKind::vessel_tree &&
      (local.tubes.empty() || (!shape.junctions.empty() && local.junctions.empty()));
  RenderedSlice out;
  out.image = cv::Mat(height, width, CV_8U, cv::Scalar(0));
  if (noTubes) return out;
  std::vector<char> rowClipped(height, 0);
  const Vec3 o = pose.block<3, 1>(0, 3), du = pose.block<3, 1>(0, 0), dv = pose.block<3, 1>(0, 1);
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
    for (int j = rows.begin(); j != rows.end(); ++j) {
      std::uint8_t* row = out.image.ptr<std::uint8_t>(j);
      const std::uint8_t* mask = fov.empty() ? nullptr : fov.ptr<std::uint8_t>(j);
      for (int i = 0; i < width; ++i) {
        const int label = materialLabel(local, o + double(i) * du + double(j) * dv);
        if (label == 0) continue;
        if (i == 0 || j == 0 || i == width - 1 || j == height - 1 || (mask && mask[i] == 0))
          rowClipped[j] = 1;
        if (!mask || mask[i] != 0) row[i] = std::uint8_t(label);
      }
    }
  });
  out.clipped = std::find(rowClipped.begin(), rowClipped.end(), 1) != rowClipped.end();
  return out;
}

cv::Mat sectorMask(const SectorFov& sector, int width, int height) {
  cv::Mat m(height, width, CV_8U, cv::Scalar(0));
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i)
      if (sector.contains(i, j)) m.at<std::uint8_t>(j, i) = 255;
  return m;
}

Mat4 jitterPose(const Mat4& pose, int width, int height, double jitter_mm, double jitter_deg,
                std::uint64_t seed, int index) {
  if (jitter_mm <= 0 && jitter_deg <= 0) return pose;
  std::mt19937_64 rng = makeStream(seed, kJitterStream, std::uint64_t(index));
  const Vec3 axis = randomUnitVector(rng);
  const double angle = jitter_deg * M_PI / 180.0 * standardNormal(rng);
  const Vec3 t(jitter_mm * standardNormal(rng), jitter_mm * standardNormal(rng),
               jitter_mm * standardNormal(rng));
  const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
  const Vec3 pivot = (pose * Eigen::Vector4d(0.5 * (width - 1), 0.5 * (height - 1), 0, 1)).head<3>();
  Mat4 out = pose;
  out.block<3, 3>(0, 0) = R * pose.block<3, 3>(0, 0);
  out.block<3, 1>(0, 3) = R * (pose.block<3, 1>(0, 3) - pivot) + pivot + t;
  return out;
}

bool dropFrame(double p, std::uint64_t seed, int index) {
  if (p <= 0) return false;
  std::mt19937_64 rng = makeStream(seed, kDropStream, std::uint64_t(index));
  return uniform01(rng) < p;
}

}  // namespace xsect

// Phantom slice rendering (see phantom_render.h).
#include "pipeline/phantom_render.h"

#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "geometry/plane_of_pose.h"
#include "geometry/random_streams.h"

namespace xsect {
namespace {

constexpr std::uint64_t kNoiseStream = 0x6e6f697365ULL;   // "noise"
constexpr std::uint64_t kJitterStream = 0x6a6974ULL;      // "jit"
constexpr std::uint64_t kDropStream = 0x64726f70ULL;      // "drop"

/// For a vessel tree, only the tubes that come within one pixel of the plane can change a
/// clamped intensity (farther tubes give sdf >= pixel_mm, i.e. 0): dropping the others makes
/// rendering ~N times faster and leaves every pixel value identical.
PhantomShape cullTubes(const PhantomShape& shape, const Plane& plane, double pixel_mm) {
  if (shape.tubes.empty()) return shape;
  PhantomShape out = shape;
  out.tubes.clear();
  for (const auto& t : shape.tubes) {
    const double da = plane.signedDistance(shape.centre + shape.rotation * t.a);
    const double db = plane.signedDistance(shape.centre + shape.rotation * t.b);
    const double d = (da > 0) != (db > 0) ? 0.0 : std::min(std::abs(da), std::abs(db));
    if (d <= t.radius + 2.0 * pixel_mm) out.tubes.push_back(t);
  }
  return out;
}

}  // namespace

RenderedSlice renderSlice(const PhantomShape& shape, const Mat4& pose, int width, int height,
                          const cv::Mat& fov, const PhantomDegradations& degr, std::uint64_t seed,
                          int index) {
  const double px = pose.block<3, 1>(0, 0).norm();
  const PhantomShape local = cullTubes(shape, planeOfPose(pose), px);
  const bool noTubes = local.kind == "vessel_tree" && local.tubes.empty();
  cv::Mat img(height, width, CV_32F, cv::Scalar(0));
  std::vector<char> rowClipped(height, 0);
  const Vec3 o = pose.block<3, 1>(0, 3), du = pose.block<3, 1>(0, 0), dv = pose.block<3, 1>(0, 1);
  if (!noTubes) {
    tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
      for (int j = rows.begin(); j != rows.end(); ++j) {
        float* row = img.ptr<float>(j);
        const std::uint8_t* mask = fov.empty() ? nullptr : fov.ptr<std::uint8_t>(j);
        for (int i = 0; i < width; ++i) {
          const double sdf = signedDistance(local, o + double(i) * du + double(j) * dv);
          row[i] = float(std::clamp(127.5 * (1.0 - sdf / px), 0.0, 255.0));
          if (sdf < 0 && (i == 0 || j == 0 || i == width - 1 || j == height - 1 ||
                          (mask && mask[i] == 0)))
            rowClipped[j] = 1;
        }
      }
    });
  }
  RenderedSlice out;
  out.clipped = std::find(rowClipped.begin(), rowClipped.end(), 1) != rowClipped.end();
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

// Slicing patterns (see slicing_pattern.h).
#include "geometry/phantoms/slicing_pattern.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "geometry/core/plane_of_pose.h"
#include "geometry/core/random_streams.h"

namespace xsect {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr std::uint64_t kPatternStream = 0x70617474ULL;  // "patt"

/// Extent of the box [bmin, bmax] projected on unit direction n, mm.
double extentAlong(const Vec3& n, const Vec3& bmin, const Vec3& bmax) {
  return n.cwiseAbs().dot(bmax - bmin);
}

/// Cell-centred positions: count values splitting [lo, lo + length] into equal cells.
std::vector<double> cellCentres(double lo, double length, int count) {
  std::vector<double> out(count);
  for (int i = 0; i < count; ++i) out[i] = lo + length * (i + 0.5) / count;
  return out;
}

/// A smooth function of t in [0, 1] with values in [-1, 1]: three low-frequency sinusoids with
/// random phases and weights summing to 1.
struct SmoothDrift {
  double phase[3], weight[3];
  explicit SmoothDrift(std::mt19937_64& rng) {
    double sum = 0;
    for (int k = 0; k < 3; ++k) {
      phase[k] = uniform(rng, 0.0, 2.0 * M_PI);
      weight[k] = uniform(rng, 0.2, 1.0);
      sum += weight[k];
    }
    for (double& w : weight) w /= sum;
  }
  double operator()(double t) const {
    static constexpr double freq[3] = {0.5, 1.0, 1.5};  // cycles per sweep
    double s = 0;
    for (int k = 0; k < 3; ++k) s += weight[k] * std::sin(2.0 * M_PI * freq[k] * t + phase[k]);
    return s;
  }
};

SlicePlan freehandPlan(const SlicingPattern& p, SlicePlan plan, const Vec3& c, double radius,
                       const Vec3& bmin, const Vec3& bmax, std::uint64_t seed) {
  const Vec3 d = p.direction.normalized();
  Vec3 u0, v0;
  planeFrame(d, &u0, &v0);
  const double length = p.span_mm.value_or(extentAlong(d, bmin, bmax));
  std::mt19937_64 rng = makeStream(seed, kPatternStream, 1);
  const SmoothDrift tiltA(rng), tiltB(rng), driftU(rng), driftV(rng);
  const double speedPhase = uniform(rng, 0.0, 2.0 * M_PI);
  const double speedVariation = 0.3;  // probe speed varies by +-30%, never stops or reverses
  auto sweep = [&](double t) {
    return t + speedVariation * (std::sin(2 * M_PI * t + speedPhase) - std::sin(speedPhase)) /
                   (2 * M_PI);
  };
  const int n = p.count;
  double amplitude = p.tilt_deg * kDeg;
  for (int attempt = 0; attempt < 60; ++attempt) {
    plan.poses.clear();
    for (int i = 0; i < n; ++i) {
      const double t = (i + 0.5) / n;
      const double s = c.dot(d) - 0.5 * length + length * sweep(t);
      const Eigen::Matrix3d R = (Eigen::AngleAxisd(amplitude * tiltA(t), u0) *
                                 Eigen::AngleAxisd(amplitude * tiltB(t), v0))
                                    .toRotationMatrix();
      const Vec3 centre = c + (s - c.dot(d)) * d + p.drift_mm * (driftU(t) * u0 + driftV(t) * v0);
      plan.poses.push_back(
          centredPose(centre, R * u0, R * v0, plan.pixel_mm, plan.width, plan.height));
    }
    bool ok = true;
    for (int i = 0; i + 1 < n && ok; ++i)
      ok = planesSeparatedInBall(plan.poses[i], plan.poses[i + 1], c, radius);
    if (ok) break;
    if (amplitude == 0.0) throw std::runtime_error("freehand: consecutive planes coincide");
    amplitude = attempt < 50 ? 0.7 * amplitude : 0.0;
  }
  if (p.sector) {
    SectorFov f;
    f.apex_i = 0.5 * (plan.width - 1);
    f.apex_j = -(p.apex_px > 0 ? p.apex_px : 0.25 * plan.height);
    f.near_px = -f.apex_j;
    f.far_px = f.near_px + plan.height - 1;
    f.half_angle_rad = p.sector_angle_deg > 0
                           ? 0.5 * p.sector_angle_deg * kDeg
                           : std::asin(std::min(1.0, f.apex_i / f.far_px));
    plan.sector = f;
  }
  return plan;
}

}  // namespace

bool SectorFov::contains(double i, double j) const {
  const double di = i - apex_i, dj = j - apex_j;
  const double r = std::hypot(di, dj);
  if (r < near_px || r > far_px) return false;
  return std::atan2(std::abs(di), dj) <= half_angle_rad;
}

void planeFrame(const Vec3& normal, Vec3* u, Vec3* v) {
  const Vec3 n = normal.normalized();
  if (std::abs(n.y()) < 0.9)
    *u = Vec3::UnitY().cross(n).normalized();
  else
    *u = n.cross(Vec3::UnitZ()).normalized();
  *v = n.cross(*u);
}

Mat4 centredPose(const Vec3& centre, const Vec3& u, const Vec3& v, double pixel_mm, int width,
                 int height) {
  Mat4 m = Mat4::Identity();
  m.block<3, 1>(0, 0) = u * pixel_mm;
  m.block<3, 1>(0, 1) = v * pixel_mm;
  m.block<3, 1>(0, 2) = u.cross(v) * pixel_mm;
  m.block<3, 1>(0, 3) =
      centre - 0.5 * (width - 1) * pixel_mm * u - 0.5 * (height - 1) * pixel_mm * v;
  return m;
}

bool planesSeparatedInBall(const Mat4& prev, const Mat4& next, const Vec3& centre, double radius) {
  const Plane a = planeOfPose(prev), b = planeOfPose(next);
  const double h = b.signedDistance(centre);
  if (std::abs(h) >= radius) return true;  // the next plane misses the ball
  const Vec3 q = centre - h * b.normal;
  const double rho = std::sqrt(radius * radius - h * h);
  const Vec3 tangential = a.normal - a.normal.dot(b.normal) * b.normal;
  return a.signedDistance(q) - rho * tangential.norm() > 0.0;
}

SlicePlan planSlices(const SlicingPattern& p, const ImageSpec& image, const Vec3& bmin,
                     const Vec3& bmax, std::uint64_t seed) {
  SlicePlan plan;
  plan.pixel_mm = image.pixel_mm;
  const Vec3 c = 0.5 * (bmin + bmax);
  const double radius = 0.5 * (bmax - bmin).norm();
  const int autoSize = 2 * int(std::ceil(radius / image.pixel_mm)) + 1 + 2 * image.margin_px;
  plan.width = image.width > 0 ? image.width : autoSize;
  plan.height = image.height > 0 ? image.height : autoSize;
  // A plane through `point` with normal n, imaged around the projection of the bounds' centre.
  auto addPlane = [&](const Vec3& n, const Vec3& point) {
    Vec3 u, v;
    planeFrame(n, &u, &v);
    const Vec3 nn = u.cross(v);
    const Vec3 centre = c - (c - point).dot(nn) * nn;
    plan.poses.push_back(centredPose(centre, u, v, plan.pixel_mm, plan.width, plan.height));
  };
  if (p.kind == PatternKind::parallel) {
    const Vec3 n = p.direction.normalized();
    std::vector<double> offsets = p.positions_mm;  // n . x = offset
    if (offsets.empty()) {
      const double mid = n.dot(c);
      if (p.spacing_mm || p.span_mm) {
        const double step =
            p.spacing_mm ? *p.spacing_mm : (p.count > 1 ? *p.span_mm / (p.count - 1) : 0.0);
        for (int i = 0; i < p.count; ++i) offsets.push_back(mid + (i - 0.5 * (p.count - 1)) * step);
      } else {
        const double e = extentAlong(n, bmin, bmax);
        offsets = cellCentres(mid - 0.5 * e, e, p.count);
      }
    }
    std::mt19937_64 rng = makeStream(seed, kPatternStream, 0);
    for (const double o : offsets) {
      Vec3 normal = n;
      if (p.tilt_deg > 0) {
        Vec3 u, v;
        planeFrame(n, &u, &v);
        const double az = uniform(rng, 0.0, 2.0 * M_PI);
        const double tilt = uniform(rng, 0.0, p.tilt_deg * kDeg);
        normal = Eigen::AngleAxisd(tilt, std::cos(az) * u + std::sin(az) * v) * n;
      }
      addPlane(normal, c + (o - n.dot(c)) * n);
    }
  } else if (p.kind == PatternKind::multiaxial) {
    for (int axis = 0; axis < 3; ++axis) {
      const int k = p.counts[axis] > 0 ? p.counts[axis] : p.count;
      const Vec3 n = Vec3::Unit(axis);
      for (const double o : cellCentres(bmin[axis], bmax[axis] - bmin[axis], k))
        addPlane(n, c + (o - c[axis]) * n);
    }
  } else if (p.kind == PatternKind::random) {
    std::mt19937_64 rng = makeStream(seed, kPatternStream, 2);
    for (int i = 0; i < p.count; ++i) {
      const Vec3 n = randomUnitVector(rng);
      const double t = uniform(rng, -radius, radius);
      addPlane(n, c + t * n);
    }
  } else if (p.kind == PatternKind::fan) {
    const Vec3 a = p.axis.normalized();
    Vec3 e1, e2;
    planeFrame(a, &e1, &e2);
    for (int i = 0; i < p.count; ++i) {
      const double theta = (-0.5 * p.span_deg + p.span_deg * (i + 0.5) / p.count) * kDeg;
      const Vec3 n = std::cos(theta) * e1 + std::sin(theta) * e2;
      // Rows run along the axis: v = a, u = a x n, so u x v = n.
      const Vec3 u = a.cross(n);
      plan.poses.push_back(centredPose(c, u, a, plan.pixel_mm, plan.width, plan.height));
    }
  } else if (p.kind == PatternKind::freehand) {
    return freehandPlan(p, std::move(plan), c, radius, bmin, bmax, seed);
  } else {
    throw std::invalid_argument(std::string("unknown slicing pattern ") + nameOf(kPatternKinds, p.kind));
  }
  return plan;
}

}  // namespace xsect

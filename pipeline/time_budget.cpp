// Time estimate and budget of a run (see time_budget.h). The rates are the slowest measured on
// this project's bench scenarios (2 cores; bench/results.json and the segmentation trials of
// issue 48: 400 frames of 320 x 240 pixels, 0.11 s plain, 0.47 s with sigma_px 20, 1.0 s with an
// opening of 30 pixels, 10.1 s with a closing of 100).
#include "pipeline/time_budget.h"

#include <algorithm>
#include <random>
#include <cmath>
#include <sstream>

#include "geometry/scene/section_scene.h"
#include "io/input_error.h"
#include "segmentation/pixel_settings.h"

namespace xsect {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kPixelS = 4e-9;             ///< reading and thresholding one pixel
constexpr double kPixelSigmaS = 6e-10;       ///< Gaussian smoothing, per pixel and pixel of sigma
constexpr double kPixelDiskS = 1.1e-11;      ///< morphology, per pixel and pixel of the disk
// B-mode frames (segmentation.preset: ultrasound), per pixel and reading, 2 cores: the median
// filter on 8 bits (28 ns on one core for 1 mm at 0.1 mm pixels, O(1) in the width), the beams'
// polar resampling and runs of the shadows (about 110 ns on one core for both passes).
constexpr double kPixelMedianS = 1.5e-8;
constexpr double kPixelShadowS = 5e-8;
constexpr double kEdgeNodeS = 2e-9;          ///< one raster node within the band of one edge
constexpr double kPlaneS = 2e-3;             ///< per plane: its traces, its share of the diagnosis
constexpr double kPairS = 6e-5;              ///< per pair of planes meeting in the grid's box
constexpr double kVoxelS = 2.5e-7;           ///< one voxel evaluated, meshed, diagnosed and written
constexpr double kPairQueryS = 1.1e-5;       ///< methods 1 and 2: the cells' queries, per pair
constexpr double kDelaunayPairS = 3e-4;      ///< method 3: tetrahedra per cell, per pair
constexpr double kDelaunayPlaneS = 2e-3;     ///< method 3: per plane (corners, branching)
constexpr double kSmoothVoxelS = 1e-6;       ///< smoothing, per voxel
constexpr double kWriteS = 0.5;              ///< the report, the graphs and the page
constexpr double kAdvisedSliceS = 0.03;      ///< one slice of advice.yaml (the Ω-cells' greedy)

std::string seconds(double s) {
  std::ostringstream o;
  o.precision(2);
  if (s < 120) o << s << " s";
  else if (s < 7200) o << s / 60 << " min";
  else o << s / 3600 << " h";
  return o.str();
}

/// Whether the common line of planes p and q crosses the box of centre `centre` and half-sides
/// `half` (parallel planes: no).
bool lineMeetsBox(const Plane& p, const Plane& q, const Vec3& centre, const Vec3& half) {
  const Vec3 d = p.normal.cross(q.normal);
  const double d2 = d.squaredNorm();
  if (d2 < 1e-12) return false;
  // The point of the line nearest the box's centre, then the line clipped by the box's slabs.
  const double hp = p.normal.dot(p.origin - centre), hq = q.normal.dot(q.origin - centre);
  const Vec3 x = (hp * q.normal.cross(d) + hq * d.cross(p.normal)) / d2;
  double t0 = -1e300, t1 = 1e300;
  for (int i = 0; i < 3; ++i) {
    if (std::abs(d[i]) < 1e-15) {
      if (std::abs(x[i]) > half[i]) return false;
      continue;
    }
    double s0 = (-half[i] - x[i]) / d[i], s1 = (half[i] - x[i]) / d[i];
    if (s0 > s1) std::swap(s0, s1);
    t0 = std::max(t0, s0), t1 = std::min(t1, s1);
    if (t0 > t1) return false;
  }
  return true;
}

/// Pairs of planes whose common line crosses the box [lo, hi]: all pairs up to 4 million, beyond
/// that a sample of 4 million drawn with a fixed seed (deterministic), scaled up.
double pairsMeetingInBox(const std::vector<CuttingPlane>& planes, const Vec3& lo, const Vec3& hi) {
  const std::size_t n = planes.size();
  const double all = double(n) * double(n - (n > 0)) / 2;
  const Vec3 centre = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  const auto meets = [&](std::size_t a, std::size_t b) {
    return lineMeetsBox(planes[a].plane, planes[b].plane, centre, half);
  };
  double meeting = 0;
  if (all <= 4e6) {
    for (std::size_t a = 0; a < n; ++a)
      for (std::size_t b = a + 1; b < n; ++b) meeting += meets(a, b);
    return meeting;
  }
  std::mt19937_64 rng(48);
  for (int k = 0; k < 4000000;) {
    const std::size_t a = std::size_t(rng() % n), b = std::size_t(rng() % n);
    if (a == b) continue;
    meeting += meets(a, b);
    ++k;
  }
  return all * meeting / 4e6;
}

}  // namespace

double segmentSeconds(double pixels, const SegmentationParams& params, const Vec2& spacing) {
  const SegmentationParams p = spacing.minCoeff() > 0 ? inPixels(params, spacing) : params;
  double disk = kPi * (double(p.open_radius_px) * p.open_radius_px + double(p.close_radius_px) * p.close_radius_px);
  if (p.method == SegmentationMethod::min_error) {
    // The core (SegmentationParams::core_threshold): its opening, its growth by the reach, and
    // the closing of the cut mask.
    const double reach = std::max(1.0, std::ceil(p.sigma_px)), r = double(p.open_radius_px);
    disk += kPi * (std::pow(std::max(0.0, r - reach), 2) + reach * reach + r * r);
  }
  const double readings =
      p.method == SegmentationMethod::otsu || p.method == SegmentationMethod::min_error || p.inside == InsideSide::automatic
          ? 2.0
          : 1.0;
  const double perReading = kPixelS + kPixelSigmaS * p.sigma_px + (p.speckle_filter_px >= 3 ? kPixelMedianS : 0.0) +
                            (p.shadows == ShadowRule::unobserved ? kPixelShadowS : 0.0);
  return pixels * (readings * perReading + kPixelDiskS * disk);
}

TimeEstimate sceneOnwardSeconds(const std::vector<CuttingPlane>& planes, double voxel_mm, double voxels,
                                const RunConfig& c) {
  TimeEstimate e;
  Vec3 lo = Vec3::Constant(1e300), hi = -lo;
  double nodes = 0;
  for (const CuttingPlane& P : planes) {
    // The raster of sectionScene: nodes within 3 voxels (or 3 nodes) of each edge.
    const double step = rasterStep(P.pixel_mm, voxel_mm);
    const double band = std::max(ReconstructionParams{}.band_voxels * voxel_mm, 3 * step);
    const double perEdge = std::pow(2 * band / step + 2, 2);
    for (const Section& s : P.sections) {
      double edges = double(s.outer.size());
      for (const Ring& h : s.holes) edges += double(h.size());
      nodes += edges * perEdge;
      for (const Vec2& q : s.outer) {
        const Vec3 x = P.plane.toWorld(q);
        lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
      }
    }
  }
  e.scene_s = kEdgeNodeS * nodes;
  const double n = double(planes.size());
  const double pairs = lo.x() <= hi.x() ? pairsMeetingInBox(planes, lo, hi) : 0.0;
  // The advice: the configured count, or by default up to 30 slices (sampling_stage.cpp).
  const double advised = c.sampling.advice_count ? double(*c.sampling.advice_count) : std::min(n, 30.0);
  e.arrange_s = kPlaneS * n + kPairS * pairs + kAdvisedSliceS * advised;
  e.reconstruct_s = kWriteS;
  if (c.reconstruction_method == ReconstructionMethod::delaunay) {
    e.delaunay_s = kDelaunayPairS * pairs + kDelaunayPlaneS * n;
    e.reconstruct_s += e.delaunay_s + kVoxelS * voxels;
  }
  else
    e.reconstruct_s += kPairQueryS * pairs + kVoxelS * voxels;
  // The level-set smoothing's curvature flow runs smoothing.iterations steps (8 by default).
  if (c.smoothing_method != SmoothingMethod::none)
    e.reconstruct_s += kSmoothVoxelS * voxels *
                       (c.smoothing_method == SmoothingMethod::level_set ? std::max(1.0, c.smoothing_iterations / 8.0) : 1.0);
  return e;
}

void checkTimeBudget(const TimeEstimate& e, double elapsed_s, const RunConfig& c) {
  const double total = elapsed_s + e.total();
  if (total <= c.max_seconds) return;
  // The setting behind the largest part.
  const double parts[] = {e.segment_s, e.scene_s, e.arrange_s, e.reconstruct_s};
  const int worst = int(std::max_element(std::begin(parts), std::end(parts)) - std::begin(parts));
  std::string key, fix;
  if (worst == 0) {
    key = "segmentation";
    fix = "smaller segmentation.sigma_px, open_radius_px and close_radius_px (their cost grows with the kernel's size)";
  } else if (worst == 2 || (worst == 3 && e.delaunay_s > e.reconstruct_s - e.delaunay_s)) {
    key = "input";
    fix = "fewer slices (the arrangement's cost grows with the pairs of planes that meet)";
  } else {
    key = "reconstruction.voxel_size_mm";
    fix = "a larger reconstruction.voxel_size_mm or auto";
  }
  throw InputError(c.path, key,
                   "the run is estimated to take " + seconds(total) + " (segment " + seconds(e.segment_s) + ", scene " +
                       seconds(e.scene_s) + ", arrangement and diagnosis " + seconds(e.arrange_s) + ", reconstruction " +
                       seconds(e.reconstruct_s) + (elapsed_s > 0 ? ", already spent " + seconds(elapsed_s) : "") +
                       "), more than run.max_seconds = " + seconds(c.max_seconds) + ": use " + fix +
                       ", or raise run.max_seconds if the time is acceptable");
}

}  // namespace xsect

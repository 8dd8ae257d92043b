// Slicing patterns of the phantom generator (docs/inputs.md, phantoms): the true image_to_world poses
// of the slices that cut a shape, from its bounds and a seed. Pure functions, deterministic.
// Poses follow the docs/inputs.md convention: column 0 = u * pixel_mm, column 1 = v * pixel_mm, column 2 =
// normal * pixel_mm, column 3 = world position of the centre of pixel (0, 0).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "geometry/core/named_choice.h"
#include "geometry/core/types.h"

namespace xsect {

/// The slicing patterns (`pattern.kind` of a phantom specification).
enum class PatternKind { parallel, multiaxial, random, fan, freehand };
constexpr std::array<NamedChoice<PatternKind>, 5> kPatternKinds{{
    {PatternKind::parallel, "parallel"},
    {PatternKind::multiaxial, "multiaxial"},
    {PatternKind::random, "random"},
    {PatternKind::fan, "fan"},
    {PatternKind::freehand, "freehand"},
}};

struct SlicingPattern {
  PatternKind kind = PatternKind::parallel;
  int count = 0;                     ///< number of planes (multiaxial: per axis unless counts set)
  std::array<int, 3> counts{0, 0, 0};///< multiaxial: planes normal to world x, y, z
  Vec3 direction = Vec3::UnitZ();    ///< parallel: plane normal; freehand: sweep direction (unit)
  std::optional<double> spacing_mm;  ///< parallel: distance between consecutive planes, mm
  std::optional<double> span_mm;    ///< parallel / freehand: distance first..last plane, mm
                                     ///< (default: the bounds' extent along the direction)
  std::vector<double> positions_mm;  ///< parallel: explicit planes {x : direction . x = p}, mm
  double tilt_deg = 0.0;             ///< parallel: max random tilt per plane, degrees;
                                     ///< freehand: amplitude of the smooth tilt drift, degrees
  Vec3 axis = Vec3::UnitZ();         ///< fan: common axis (through the bounds' centre), unit
  double span_deg = 180.0;           ///< fan: angular span of the planes, degrees, (0, 180]
  double drift_mm = 1.0;             ///< freehand: amplitude of the smooth in-plane drift, mm
  bool sector = false;               ///< freehand: sector-shaped (fan) field of view
  double sector_angle_deg = 0.0;     ///< freehand: full opening angle of the sector, 0 = auto
  double apex_px = 0.0;              ///< freehand: apex distance above row 0, px, 0 = height / 4
};

struct ImageSpec {
  double pixel_mm = 0.5;  ///< pixel size, mm (> 0)
  int width = 0;          ///< pixels; 0 = auto: cover the bounding sphere's projection
  int height = 0;         ///< pixels; 0 = auto
  int margin_px = 4;      ///< auto size: extra pixels on each side
};

/// Fan-shaped field of view in pixel coordinates: apex (i, j), half opening angle about +j,
/// near and far radii in pixels.
struct SectorFov {
  double apex_i = 0, apex_j = 0;
  double half_angle_rad = 0;
  double near_px = 0, far_px = 0;
  bool contains(double i, double j) const;
};

struct SlicePlan {
  std::vector<Mat4> poses;          ///< true image_to_world per slice
  int width = 0, height = 0;        ///< image size, pixels
  double pixel_mm = 0.0;
  std::optional<SectorFov> sector;  ///< freehand with sector: the shared FOV
};

/// @param pattern  validated pattern (counts > 0, unit directions, ...)
/// @param image    pixel size and image size
/// @param bmin     world bounds of the shape, mm
/// @param bmax
/// @param seed     drives random normals/offsets/tilts/drifts
/// Freehand sweeps are monotonic: consecutive planes do not cross inside the bounding sphere
/// (the tilt drift amplitude is reduced until they do not).
SlicePlan planSlices(const SlicingPattern& pattern, const ImageSpec& image, const Vec3& bmin,
                     const Vec3& bmax, std::uint64_t seed);

/// Right-handed orthonormal (u, v) with u x v = normal; u = x, v = y for normal = z.
void planeFrame(const Vec3& normal, Vec3* u, Vec3* v);

/// Pose of an image of width x height pixels whose centre lies at `centre` (mm) with pixel axes
/// u, v (unit) and pixel size pixel_mm.
Mat4 centredPose(const Vec3& centre, const Vec3& u, const Vec3& v, double pixel_mm, int width,
                 int height);

/// True when the planes of two poses do not meet inside the ball (centre, radius): the plane of
/// `next` lies strictly on the positive-normal side of the plane of `prev` within the ball.
bool planesSeparatedInBall(const Mat4& prev, const Mat4& next, const Vec3& centre, double radius);

}  // namespace xsect

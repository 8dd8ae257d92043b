// Analytic phantom shapes (see phantom_shape.h): signed distances, nearest boundary points, Betti
// numbers, reach (interior / exterior), bounds, material labels.
// Parameters per kind (all lengths in mm, angles in degrees):
//   sphere            radius
//   ellipsoid         a, b, c (semi-axes along shape x, y, z)
// Reach is given as (reach_i, reach_e): distances of the boundary to the inner / outer medial axis.
//   sphere            (radius, inf): convex, no outer medial axis
//   ellipsoid         (c^2 / a, inf) with a the longest, c the shortest semi-axis (smallest radius
//                     of curvature, at the end of the longest axis)
//   torus             major_radius R, minor_radius r (axis = shape z); (r, R - r): core circle,
//                     and the axis of the hole
//   genus2            disk_radius, hole_radius, hole_offset, offset_radius r: the r-offset of the
//                     flat disk in z = 0 with two holes centred at (+-hole_offset, 0); exact SDF
//                     d(x, D) - r; (r, hole_radius - r): the disk, and the holes' axes;
//                     Betti (1, 2, 0)
//   hollow_sphere     outer_radius, inner_radius: Betti (1, 0, 1); ((Ro - Ri) / 2, Ri): the middle
//                     sphere, and the cavity's centre
//   two_spheres       radius, separation (centres at +-separation/2 on x); (radius, half the gap
//                     (separation - 2 radius) / 2)
//   vessel_tree       length, radius, levels, branch_angle_deg, length_ratio, radius_ratio, seed,
//                     blend_mm (vessel_tree.h): capsules smoothly joined at the junctions (blend_mm
//                     = 0: their plain union, concave creases, reach_e = 0); reach bounds from
//                     vesselTreeReach (tube radii, gaps, sampled fillet curvature);
//                     nominal_reach = thinnest tube
//   twisted_cylinder  inner_radius, outer_radius, gap_deg, height H, extension e: the C-shaped
//                     annular sector (gap centred on angle 0 at z = 0) swept from z = -e to H + e
//                     with a twist of 180 degrees over H (thesis ch. 1, Fig. 1.11, the original)
//   notched_torus     the same radii, gap_deg, height, extension, notch: the full annular cylinder
//                     from -e to H + e with the gap cut from the bottom end up to z = notch and
//                     (rotated 180 degrees) from z = H - notch to the top end (Fig. 1.11, the
//                     reconstruction): a solid torus, Betti (1, 1, 0). Both share the sections on
//                     z = 0 and z = H. Both: (0, 0) (convex edges where the gap's walls meet the
//                     annulus; the notched torus also has concave ones).
//   cup               radius, height, wall, bottom, handle_radius, handle_thickness: a cylinder of
//                     the radius from z = 0 to the height, hollowed from z = bottom up (inner
//                     radius radius - wall), with a handle: the torus of major radius
//                     handle_radius and minor radius handle_thickness / 2 around the axis y at
//                     (radius, 0, height / 2), less the cup's hollow. Betti (1, 1, 0) (the mug of
//                     the contour literature, synthetic); (0, 0): creases where the handle
//                     meets the wall and at the rim.
#include "geometry/phantoms/phantom_shape.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <tbb/parallel_for.h>

#include "geometry/core/digital_topology.h"
#include "geometry/phantoms/ellipsoid_distance.h"
#include "geometry/phantoms/implicit_surface.h"
#include "geometry/phantoms/vessel_tree.h"

namespace xsect {
namespace {

double P(const PhantomShape& s, const char* key) { return s.params.at(key); }

/// Exact 2D signed distance to the infinite wedge with half-angle h < pi/2 around angle 0,
/// divided by rho: g(delta) with |delta| the angular offset from the wedge's axis.
double wedgeProfile(double delta, double h) {
  delta = std::abs(delta);
  if (delta <= h) return -std::sin(h - delta);
  if (delta - h <= M_PI / 2) return std::sin(delta - h);
  return 1.0;
}

/// Wrap an angle to (-pi, pi].
double wrapAngle(double a) {
  a = std::fmod(a + M_PI, 2.0 * M_PI);
  if (a < 0) a += 2.0 * M_PI;
  return a - M_PI;
}

/// Exact SDF of a 2D shape (signed distance d2) extruded over z in [z0, z1].
double extrude(double d2, double z, double z0, double z1) {
  const double wz = std::abs(z - 0.5 * (z0 + z1)) - 0.5 * (z1 - z0);
  const double ox = std::max(d2, 0.0), oz = std::max(wz, 0.0);
  return std::min(std::max(d2, wz), 0.0) + std::sqrt(ox * ox + oz * oz);
}

double annulusSdf(double rho, double ri, double ro) { return std::max(rho - ro, ri - rho); }

double shapeFrameSdf(const PhantomShape& s, const Vec3& q) {
  const ShapeKind k = s.kind;
  if (k == ShapeKind::sphere) return q.norm() - P(s, "radius");
  if (k == ShapeKind::ellipsoid) return ellipsoidSignedDistance(Vec3(P(s, "a"), P(s, "b"), P(s, "c")), q);
  if (k == ShapeKind::torus) {
    const double a = std::hypot(q.x(), q.y()) - P(s, "major_radius");
    return std::hypot(a, q.z()) - P(s, "minor_radius");
  }
  if (k == ShapeKind::genus2) {
    const double rho = std::hypot(q.x(), q.y());
    double d2 = 0.0;
    if (rho > P(s, "disk_radius")) {
      d2 = rho - P(s, "disk_radius");
    } else {
      const double c = P(s, "hole_offset"), rh = P(s, "hole_radius");
      for (const double cx : {-c, c}) {
        const double dh = std::hypot(q.x() - cx, q.y());
        if (dh < rh) d2 = rh - dh;
      }
    }
    return std::hypot(q.z(), d2) - P(s, "offset_radius");
  }
  if (k == ShapeKind::hollow_sphere) {
    const double r = q.norm();
    return std::max(r - P(s, "outer_radius"), P(s, "inner_radius") - r);
  }
  if (k == ShapeKind::two_spheres) {
    const double h = 0.5 * P(s, "separation");
    return std::min((q - Vec3(-h, 0, 0)).norm(), (q - Vec3(h, 0, 0)).norm()) - P(s, "radius");
  }
  if (k == ShapeKind::vessel_tree) return vesselTreeSdf(s, q);
  if (k == ShapeKind::twisted_cylinder || k == ShapeKind::notched_torus) {
    const double ri = P(s, "inner_radius"), ro = P(s, "outer_radius");
    const double H = P(s, "height"), e = P(s, "extension");
    const double half = 0.5 * P(s, "gap_deg") * M_PI / 180.0;
    const double rho = std::hypot(q.x(), q.y()), phi = std::atan2(q.y(), q.x());
    const double body = extrude(annulusSdf(rho, ri, ro), q.z(), -e, H + e);
    if (k == ShapeKind::twisted_cylinder) {
      // Twisted gap: angle of its axis pi z / H. The in-plane wedge distance is rescaled so the
      // 3D function stays 1-Lipschitz: with rho capped at ro its gradient is at most
      // sqrt(1 + (k ro)^2), k = pi / H (the twist rate).
      const double twist = M_PI / H;
      const double lip = std::sqrt(1.0 + twist * twist * ro * ro);
      const double gap = std::min(rho, ro) * wedgeProfile(wrapAngle(phi - twist * q.z()), half);
      return std::max(body, -gap / lip);
    }
    const double notch = P(s, "notch");
    const double cut0 = extrude(rho * wedgeProfile(wrapAngle(phi), half), q.z(), -e - 1.0, notch);
    const double cutH =
        extrude(rho * wedgeProfile(wrapAngle(phi - M_PI), half), q.z(), H - notch, H + e + 1.0);
    return std::max({body, -cut0, -cutH});
  }
  if (k == ShapeKind::cup) {
    // Unions and differences of exact distances (min, max): the sign is exact, the value a
    // 1-Lipschitz lower bound of the distance.
    const double R = P(s, "radius"), H = P(s, "height"), Ri = R - P(s, "wall"), b = P(s, "bottom");
    const double rho = std::hypot(q.x(), q.y());
    const double body = extrude(rho - R, q.z(), 0.0, H);
    const double hollow = extrude(rho - Ri, q.z(), b, H + R);  // open above the rim
    const Vec3 h = q - Vec3(R, 0.0, 0.5 * H);                  // the handle's centre, its axis y
    const double handle = std::hypot(std::hypot(h.x(), h.z()) - P(s, "handle_radius"), h.y()) -
                          0.5 * P(s, "handle_thickness");
    return std::max(std::min(body, handle), -hollow);
  }
  throw std::invalid_argument(std::string("no signed distance for shape kind ") + nameOf(kShapeKinds, k));
}

void shapeFrameBox(const PhantomShape& s, Vec3* lo, Vec3* hi) {
  const ShapeKind k = s.kind;
  Vec3 h;
  *lo = Vec3::Zero();
  if (k == ShapeKind::sphere) {
    h.setConstant(P(s, "radius"));
  } else if (k == ShapeKind::ellipsoid) {
    h = Vec3(P(s, "a"), P(s, "b"), P(s, "c"));
  } else if (k == ShapeKind::torus) {
    const double o = P(s, "major_radius") + P(s, "minor_radius");
    h = Vec3(o, o, P(s, "minor_radius"));
  } else if (k == ShapeKind::genus2) {
    const double o = P(s, "disk_radius") + P(s, "offset_radius");
    h = Vec3(o, o, P(s, "offset_radius"));
  } else if (k == ShapeKind::hollow_sphere) {
    h.setConstant(P(s, "outer_radius"));
  } else if (k == ShapeKind::two_spheres) {
    const double r = P(s, "radius");
    h = Vec3(0.5 * P(s, "separation") + r, r, r);
  } else if (k == ShapeKind::twisted_cylinder || k == ShapeKind::notched_torus) {
    const double ro = P(s, "outer_radius"), e = P(s, "extension"), H = P(s, "height");
    *lo = Vec3(-ro, -ro, -e);
    *hi = Vec3(ro, ro, H + e);
    return;
  } else if (k == ShapeKind::cup) {
    const double R = P(s, "radius"), H = P(s, "height");
    const double out = P(s, "handle_radius") + 0.5 * P(s, "handle_thickness");
    *lo = Vec3(-R, -R, 0);
    *hi = Vec3(R + out, R, H);
    return;
  } else {
    throw std::invalid_argument(std::string("shapeFrameBox: unsupported kind ") + nameOf(kShapeKinds, k));
  }
  *lo = -h;
  *hi = h;
}

}  // namespace

std::map<std::string, std::optional<double>> phantomShapeParams(ShapeKind k) {
  using M = std::map<std::string, std::optional<double>>;
  const std::optional<double> req;
  if (k == ShapeKind::sphere) return M{{"radius", req}};
  if (k == ShapeKind::ellipsoid) return M{{"a", req}, {"b", req}, {"c", req}};
  if (k == ShapeKind::torus) return M{{"major_radius", req}, {"minor_radius", req}};
  if (k == ShapeKind::genus2)
    return M{{"disk_radius", req}, {"hole_radius", req}, {"hole_offset", req},
             {"offset_radius", req}};
  if (k == ShapeKind::hollow_sphere) return M{{"outer_radius", req}, {"inner_radius", req}};
  if (k == ShapeKind::two_spheres) return M{{"radius", req}, {"separation", req}};
  if (k == ShapeKind::vessel_tree)
    return M{{"length", req},         {"radius", req},         {"levels", 3.0},
             {"branch_angle_deg", 30.0}, {"length_ratio", 0.8}, {"radius_ratio", 0.85},
             {"seed", 1.0},         {"blend_mm", 0.5}};
  if (k == ShapeKind::twisted_cylinder)
    return M{{"inner_radius", req}, {"outer_radius", req}, {"gap_deg", 60.0},
             {"height", req},       {"extension", 3.0}};
  if (k == ShapeKind::notched_torus)
    return M{{"inner_radius", req}, {"outer_radius", req}, {"gap_deg", 60.0},
             {"height", req},       {"extension", 3.0},    {"notch", 1.0}};
  if (k == ShapeKind::cup)
    return M{{"radius", req},        {"height", req},         {"wall", req},
             {"bottom", req},        {"handle_radius", req},  {"handle_thickness", req}};
  return {};
}

std::optional<ShapeProblem> checkPhantomShape(const PhantomShape& s) {
  const auto spec = phantomShapeParams(s.kind);
  auto value = [&](const std::string& key) {
    const auto it = s.params.find(key);
    return it != s.params.end() ? it->second : spec.at(key).value_or(0.0);
  };
  for (const auto& [key, def] : spec) {
    if (!def && !s.params.count(key)) return ShapeProblem{key, "missing (required for " + std::string(nameOf(kShapeKinds, s.kind)) + ")"};
    if (!std::isfinite(value(key))) return ShapeProblem{key, "must be a finite number"};
  }
  auto positive = [&](std::initializer_list<const char*> keys) -> std::optional<ShapeProblem> {
    for (const char* key : keys)
      if (!(value(key) > 0.0)) {
        std::ostringstream os;
        os << "must be positive (got " << value(key) << ")";
        return ShapeProblem{key, os.str()};
      }
    return std::nullopt;
  };
  const ShapeKind k = s.kind;
  std::optional<ShapeProblem> p;
  if (k == ShapeKind::sphere) return positive({"radius"});
  if (k == ShapeKind::ellipsoid) return positive({"a", "b", "c"});
  if (k == ShapeKind::torus) {
    if ((p = positive({"major_radius", "minor_radius"}))) return p;
    if (value("minor_radius") >= value("major_radius"))
      return ShapeProblem{"minor_radius", "must be smaller than major_radius"};
    return std::nullopt;
  }
  if (k == ShapeKind::genus2) {
    if ((p = positive({"disk_radius", "hole_radius", "hole_offset", "offset_radius"}))) return p;
    const double r = value("offset_radius"), rh = value("hole_radius"), c = value("hole_offset");
    if (rh <= r) return ShapeProblem{"hole_radius", "must exceed offset_radius (else the holes close)"};
    if (2 * c - 2 * rh <= 2 * r)
      return ShapeProblem{"hole_offset",
                          "holes too close: their gap 2*(hole_offset - hole_radius) must exceed "
                          "2*offset_radius"};
    if (value("disk_radius") - c - rh <= 2 * r)
      return ShapeProblem{"disk_radius",
                          "holes too close to the rim: disk_radius - hole_offset - hole_radius "
                          "must exceed 2*offset_radius"};
    return std::nullopt;
  }
  if (k == ShapeKind::hollow_sphere) {
    if ((p = positive({"outer_radius", "inner_radius"}))) return p;
    if (value("inner_radius") >= value("outer_radius"))
      return ShapeProblem{"inner_radius", "must be smaller than outer_radius"};
    return std::nullopt;
  }
  if (k == ShapeKind::two_spheres) {
    if ((p = positive({"radius", "separation"}))) return p;
    if (value("separation") <= 2 * value("radius"))
      return ShapeProblem{"separation", "must exceed 2*radius (the spheres must be disjoint)"};
    return std::nullopt;
  }
  if (k == ShapeKind::vessel_tree) {
    if ((p = positive({"length", "radius", "length_ratio", "radius_ratio"}))) return p;
    const double levels = value("levels");
    if (levels != std::floor(levels) || levels < 0 || levels > 8)
      return ShapeProblem{"levels", "must be an integer in [0, 8]"};
    const double angle = value("branch_angle_deg");
    if (!(angle > 0 && angle <= 80)) return ShapeProblem{"branch_angle_deg", "must be in (0, 80]"};
    if (value("length_ratio") > 1) return ShapeProblem{"length_ratio", "must be in (0, 1]"};
    if (value("radius_ratio") > 1) return ShapeProblem{"radius_ratio", "must be in (0, 1]"};
    const double seed = value("seed");
    if (seed != std::floor(seed) || seed < 0 || seed > 9007199254740992.0)
      return ShapeProblem{"seed", "must be a non-negative integer"};
    if (value("radius") >= 0.5 * value("length"))
      return ShapeProblem{"radius", "must be smaller than length / 2"};
    if (value("blend_mm") < 0)
      return ShapeProblem{"blend_mm", "must be >= 0 (0 = the plain union of the tubes)"};
    if (value("blend_mm") > value("length"))
      return ShapeProblem{"blend_mm", "must not exceed length"};
    return std::nullopt;
  }
  if (k == ShapeKind::twisted_cylinder || k == ShapeKind::notched_torus) {
    if ((p = positive({"inner_radius", "outer_radius", "gap_deg", "height", "extension"}))) return p;
    if (value("inner_radius") >= value("outer_radius"))
      return ShapeProblem{"inner_radius", "must be smaller than outer_radius"};
    if (value("gap_deg") >= 180) return ShapeProblem{"gap_deg", "must be in (0, 180)"};
    if (k == ShapeKind::notched_torus) {
      if ((p = positive({"notch"}))) return p;
      if (value("notch") >= 0.5 * value("height"))
        return ShapeProblem{"notch", "must be smaller than height / 2"};
    }
    return std::nullopt;
  }
  if (k == ShapeKind::cup) {
    if ((p = positive({"radius", "height", "wall", "bottom", "handle_radius", "handle_thickness"}))) return p;
    if (value("wall") >= value("radius")) return ShapeProblem{"wall", "must be smaller than radius"};
    if (value("bottom") >= value("height")) return ShapeProblem{"bottom", "must be smaller than height"};
    // The handle's hole must lie outside the wall (else it is no handle), and the handle within
    // the cup's height (else it is cut by the rim or the floor).
    if (value("handle_radius") - 0.5 * value("handle_thickness") <= 0)
      return ShapeProblem{"handle_thickness", "must be smaller than twice handle_radius (else the handle has no hole)"};
    if (value("handle_radius") + 0.5 * value("handle_thickness") >= 0.5 * value("height"))
      return ShapeProblem{"handle_radius", "handle_radius + handle_thickness / 2 must be below height / 2"};
    return std::nullopt;
  }
  return std::nullopt;
}

PhantomShape completePhantomShape(PhantomShape s) {
  for (const auto& [key, def] : phantomShapeParams(s.kind))
    if (def && !s.params.count(key)) s.params[key] = *def;
  if (s.kind == ShapeKind::vessel_tree) {
    if (s.tubes.empty()) {
      VesselTreeParams v;
      v.length = P(s, "length");
      v.radius = P(s, "radius");
      v.levels = int(P(s, "levels"));
      v.branch_angle_deg = P(s, "branch_angle_deg");
      v.length_ratio = P(s, "length_ratio");
      v.radius_ratio = P(s, "radius_ratio");
      v.seed = std::uint64_t(P(s, "seed"));
      v.blend_mm = P(s, "blend_mm");
      s.tubes = growVesselTree(v);
    }
    s.junctions = linkVesselJunctions(s.tubes);
    double thinnest = std::numeric_limits<double>::infinity();
    for (const auto& t : s.tubes) thinnest = std::min(thinnest, t.radius);
    s.params["nominal_reach"] = thinnest;
    if (!s.reach_interior_mm || !s.reach_exterior_mm) {
      const VesselReach r = vesselTreeReach(s);
      if (!s.reach_interior_mm) s.reach_interior_mm = r.interior;
      if (!s.reach_exterior_mm) s.reach_exterior_mm = r.exterior;
    }
  }
  return s;
}

double signedDistance(const PhantomShape& shape, const Vec3& x) {
  return shapeFrameSdf(shape, shape.rotation.transpose() * (x - shape.centre));
}

bool hasExactDistance(const PhantomShape& shape) {
  return shape.kind != ShapeKind::vessel_tree && shape.kind != ShapeKind::twisted_cylinder &&
         shape.kind != ShapeKind::notched_torus && shape.kind != ShapeKind::cup;
}

Betti bettiNumbers(const PhantomShape& s) {
  if (s.kind == ShapeKind::torus || s.kind == ShapeKind::notched_torus || s.kind == ShapeKind::cup) return {1, 1, 0};
  if (s.kind == ShapeKind::genus2) return {1, 2, 0};
  if (s.kind == ShapeKind::hollow_sphere) return {1, 0, 1};
  if (s.kind == ShapeKind::two_spheres) return {2, 0, 0};
  return {1, 0, 0};
}

double reachInterior(const PhantomShape& s) {
  if (s.reach_interior_mm) return *s.reach_interior_mm;
  const ShapeKind k = s.kind;
  if (k == ShapeKind::sphere) return P(s, "radius");
  if (k == ShapeKind::ellipsoid) {
    // Smallest radius of curvature: c^2 / a at the end of the longest axis (a >= b >= c).
    const double lo = std::min({P(s, "a"), P(s, "b"), P(s, "c")});
    const double hi = std::max({P(s, "a"), P(s, "b"), P(s, "c")});
    return lo * lo / hi;
  }
  if (k == ShapeKind::torus) return P(s, "minor_radius");
  if (k == ShapeKind::genus2) return P(s, "offset_radius");
  if (k == ShapeKind::hollow_sphere) return 0.5 * (P(s, "outer_radius") - P(s, "inner_radius"));
  if (k == ShapeKind::two_spheres) return P(s, "radius");
  if (k == ShapeKind::vessel_tree) return vesselTreeReach(s).interior;
  return 0.0;  // twisted_cylinder, notched_torus, cup: convex edges
}

double reachExterior(const PhantomShape& s) {
  if (s.reach_exterior_mm) return *s.reach_exterior_mm;
  const ShapeKind k = s.kind;
  if (k == ShapeKind::sphere || k == ShapeKind::ellipsoid) return std::numeric_limits<double>::infinity();
  if (k == ShapeKind::torus) return P(s, "major_radius") - P(s, "minor_radius");
  if (k == ShapeKind::genus2) return P(s, "hole_radius") - P(s, "offset_radius");
  if (k == ShapeKind::hollow_sphere) return P(s, "inner_radius");
  if (k == ShapeKind::two_spheres) return 0.5 * (P(s, "separation") - 2 * P(s, "radius"));
  if (k == ShapeKind::vessel_tree) return vesselTreeReach(s).exterior;
  return 0.0;  // twisted_cylinder, notched_torus, cup: not derived (creases)
}

double reach(const PhantomShape& s) { return std::min(reachInterior(s), reachExterior(s)); }

void bounds(const PhantomShape& s, Vec3* min, Vec3* max) {
  if (s.kind == ShapeKind::vessel_tree) {
    // The blended surface lies within vesselBlendOffset of the capsules.
    const double grow = vesselBlendOffset(s);
    min->setConstant(std::numeric_limits<double>::infinity());
    max->setConstant(-std::numeric_limits<double>::infinity());
    for (const auto& t : s.tubes)
      for (const Vec3& p : {t.a, t.b}) {
        const Vec3 w = s.centre + s.rotation * p;
        *min = min->cwiseMin(w - Vec3::Constant(t.radius + grow));
        *max = max->cwiseMax(w + Vec3::Constant(t.radius + grow));
      }
    if (s.tubes.empty()) *min = *max = s.centre;
    return;
  }
  Vec3 lo, hi;
  shapeFrameBox(s, &lo, &hi);
  if (s.kind == ShapeKind::sphere || s.kind == ShapeKind::hollow_sphere) {  // rotation-invariant: tight
    *min = s.centre + lo;
    *max = s.centre + hi;
    return;
  }
  // The world box of the rotated shape-frame box (tight for the box, conservative for the shape).
  const Vec3 mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  const Vec3 c = s.centre + s.rotation * mid;
  const Vec3 r = s.rotation.cwiseAbs() * half;
  *min = c - r;
  *max = c + r;
}

namespace {

Vec3 numericGradient(const PhantomShape& s, const Vec3& q) {
  const double h = 1e-6 * std::max(1.0, q.cwiseAbs().maxCoeff());
  Vec3 g;
  for (int c = 0; c < 3; ++c) {
    const Vec3 e = h * Vec3::Unit(c);
    g[c] = (shapeFrameSdf(s, q + e) - shapeFrameSdf(s, q - e)) / (2 * h);
  }
  return g;
}

/// The shape's signed distance in its own frame, as geometry/phantoms/implicit_surface.h reads it.
struct ShapeFrameSurface {
  const PhantomShape& s;
  double value(const Vec3& q) const { return shapeFrameSdf(s, q); }
  Vec3 gradient(const Vec3& q) const { return numericGradient(s, q); }
  double check(const Vec3& q) const { return shapeFrameSdf(s, q); }
};

/// Newton steps onto the zero set (shape frame); false when it does not converge.
bool projectOnto(const PhantomShape& s, const Vec3& q, Vec3* out) {
  return projectOntoSurface(ShapeFrameSurface{s}, q, ImplicitSurfaceSteps{}, out);
}

/// A local minimum of |q - p| over the zero set from p on it (tangent steps, halved until the
/// distance decreases, projected back).
Vec3 descendOnto(const PhantomShape& s, const Vec3& q, const Vec3& p) {
  return descendToNearest(ShapeFrameSurface{s}, q, p, ImplicitSurfaceSteps{});
}

}  // namespace

Vec3 closestBoundaryPoint(const PhantomShape& s, const Vec3& x) {
  const Vec3 q = s.rotation.transpose() * (x - s.centre);
  Vec3 p = q;
  if (s.kind == ShapeKind::vessel_tree) {
    p = vesselTreeClosestPoint(s, q);
  } else if (s.kind == ShapeKind::ellipsoid) {
    ellipsoidSignedDistance(Vec3(P(s, "a"), P(s, "b"), P(s, "c")), q, &p);
  } else if (hasExactDistance(s)) {
    // An exact distance: the foot is q - f grad f (off the medial axis), polished by Newton.
    const double f = shapeFrameSdf(s, q);
    const Vec3 g = numericGradient(s, q);
    const Vec3 foot = g.norm() > 1e-12 ? Vec3(q - f * g.normalized()) : q;
    if (!projectOnto(s, foot, &p)) p = foot;
  } else {
    // Piecewise-smooth surfaces (edges): the best of descents started from the projections of
    // q and of the 6 points at distance |f(q)| along the axes around it (the nearest point lies
    // no nearer), skipping starts that project where an earlier one did.
    const double f = std::abs(shapeFrameSdf(s, q));
    double best = std::numeric_limits<double>::infinity();
    std::vector<Vec3> tried;
    for (int d = 0; d < 7; ++d) {
      const Vec3 from = d == 0 ? q : Vec3(q + (d % 2 ? f : -f) * Vec3::Unit((d - 1) / 2));
      Vec3 start;
      if (!projectOnto(s, from, &start)) continue;
      bool seen = false;
      for (const Vec3& t : tried) seen = seen || (t - start).norm() < 1e-3 * (1.0 + f);
      if (seen) continue;
      tried.push_back(start);
      const Vec3 c = descendOnto(s, q, start);
      if ((c - q).norm() < best) {
        best = (c - q).norm();
        p = c;
      }
    }
  }
  return s.centre + s.rotation * p;
}

int materialLabel(const PhantomShape& s, const Vec3& x) {
  if (!(signedDistance(s, x) < 0)) return 0;
  if (!s.label_split) return 1;
  const Vec3 q = s.rotation.transpose() * (x - s.centre);
  return s.label_split->normal.dot(q - s.label_split->point) < 0 ? 1 : 2;
}

namespace {

/// Betti numbers of the union, label 1 and label 2 on a grid of voxel v over the shape's bounds.
std::array<Betti, 3> gridBetti(const PhantomShape& s, double v) {
  Vec3 lo, hi;
  bounds(s, &lo, &hi);
  GridSpec g;
  g.voxel = v;
  g.origin = lo - Vec3::Constant(1.5 * v);
  for (int c = 0; c < 3; ++c) g.dims[c] = int(std::ceil((hi[c] - lo[c]) / v)) + 4;
  std::vector<std::uint8_t> label(std::size_t(g.count()));
  tbb::parallel_for(0, g.dims[2], [&](int k) {
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i)
        label[std::size_t(g.index(i, j, k))] = std::uint8_t(materialLabel(s, g.centre(i, j, k)));
  });
  std::array<Betti, 3> out;
  for (int l = 0; l < 3; ++l) {
    std::vector<std::uint8_t> in(label.size());
    for (std::size_t i = 0; i < in.size(); ++i) in[i] = l == 0 ? label[i] != 0 : label[i] == l;
    out[l] = voxelBetti(in, g);
  }
  return out;
}

}  // namespace

std::map<int, Betti> labelBettiNumbers(const PhantomShape& s) {
  if (!s.label_split) return {};
  if (s.label_betti) return *s.label_betti;
  Vec3 lo, hi;
  bounds(s, &lo, &hi);
  const double size = (hi - lo).maxCoeff();
  const double r = reach(s);
  double v = (r > 0 ? std::min(r, size / 30.0) : size / 30.0) / 2.5;
  const double cells = (hi - lo).prod() / (v * v * v);
  if (cells > 1e7) v *= std::cbrt(cells / 1e7);
  // Two resolutions must agree with each other, and the union with the analytic Betti numbers.
  const std::array<Betti, 3> a = gridBetti(s, v), b = gridBetti(s, 0.8 * v);
  if (a != b || a[0] != bettiNumbers(s))
    throw std::runtime_error(
        "label_split: the Betti numbers of the two materials could not be established on a voxel "
        "grid (the split plane may graze the surface); move the plane");
  return {{1, a[1]}, {2, a[2]}};
}

Eigen::Matrix3d rotationFromEulerXyzDeg(const Vec3& deg) {
  const Vec3 r = deg * (M_PI / 180.0);
  return (Eigen::AngleAxisd(r.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(r.y(), Vec3::UnitY()) *
          Eigen::AngleAxisd(r.x(), Vec3::UnitX()))
      .toRotationMatrix();
}

}  // namespace xsect

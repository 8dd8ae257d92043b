// Analytic phantom shapes (GUIDE.md, Phantoms): exact signed distance (negative inside), Betti
// numbers, reach (thesis Def. 5 / Def. 21: distance of the boundary to its medial axis) and bounds.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "geometry/types.h"

namespace xsect {

/// A shape in its own frame, placed in the world by `centre` and `rotation` (world <- shape):
/// world = centre + rotation * shape_point.
/// `kind` is one of: sphere, ellipsoid, torus, genus2, hollow_sphere, two_spheres, vessel_tree,
/// twisted_cylinder, notched_torus. `params` holds its named dimensions in mm (see
/// phantomShapeParams() and phantom_shape.cpp for each kind's keys).
struct PhantomShape {
  std::string kind;
  std::map<std::string, double> params;
  Vec3 centre = Vec3::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  /// vessel_tree only: the tree's segments in the shape frame (mm), each a capsule of the given
  /// radius (mm) around segment ab. Filled by completePhantomShape() from the params.
  struct Tube { Vec3 a, b; double radius; };
  std::vector<Tube> tubes;
};

/// Signed distance in mm from x (world) to the boundary; negative inside.
/// For shapes with hasExactDistance() false, a conservative estimate: correct sign, zero exactly
/// on the boundary, 1-Lipschitz (hence |value| <= true distance).
double signedDistance(const PhantomShape& shape, const Vec3& x);
/// True when signedDistance is the exact Euclidean signed distance everywhere.
bool hasExactDistance(const PhantomShape& shape);
Betti bettiNumbers(const PhantomShape& shape);
/// Reach of the boundary in mm (0 where the boundary has creases).
double reach(const PhantomShape& shape);
/// Axis-aligned world bounds of the solid (conservative: may be slightly larger than tight).
void bounds(const PhantomShape& shape, Vec3* min, Vec3* max);

/// The kinds known to signedDistance(), in a fixed order.
const std::vector<std::string>& phantomShapeKinds();

/// For a kind: its parameter names, each with its default value (nullopt = required).
/// Returns an empty map for an unknown kind.
std::map<std::string, std::optional<double>> phantomShapeParams(const std::string& kind);

/// What is wrong with a shape's parameters: the parameter name ("" for the kind) and why.
struct ShapeProblem {
  std::string param;
  std::string message;
};

/// Checks kind and parameter values (positivity, non-overlap constraints of each kind).
std::optional<ShapeProblem> checkPhantomShape(const PhantomShape& shape);

/// Fills defaults of missing optional params and derived data (vessel_tree tubes and
/// params["nominal_reach"] = smallest tube radius, mm). Assumes checkPhantomShape() passed.
/// Throws std::runtime_error when no vessel tree without self-contact can be grown.
PhantomShape completePhantomShape(PhantomShape shape);

/// Rotation matrix from xyz Euler angles in degrees: R = Rz(z) * Ry(y) * Rx(x)
/// (rotate about world x first, then y, then z).
Eigen::Matrix3d rotationFromEulerXyzDeg(const Vec3& degrees);

}  // namespace xsect

// Analytic phantom shapes (GUIDE.md, Phantoms): exact signed distance (negative inside), Betti
// numbers, reach (thesis Def. 5 / Def. 21: distance of the boundary to its medial axis) and bounds.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "geometry/types.h"

namespace xsect {

/// A shape in its own frame, placed in the world by `centre` and `rotation` (world <- shape).
/// `kind` is one of: sphere, ellipsoid, torus, genus2, hollow_sphere, two_spheres, vessel_tree,
/// twisted_cylinder, notched_torus. `params` holds its named dimensions in mm (see phantom_shape.cpp).
struct PhantomShape {
  std::string kind;
  std::map<std::string, double> params;
  Vec3 centre = Vec3::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  /// vessel_tree only: the tree's segments (world coordinates of the shape frame) with radii.
  struct Tube { Vec3 a, b; double radius; };
  std::vector<Tube> tubes;
};

/// Signed distance in mm from x (world) to the boundary; negative inside.
double signedDistance(const PhantomShape& shape, const Vec3& x);
/// True when signedDistance is the exact Euclidean signed distance everywhere.
bool hasExactDistance(const PhantomShape& shape);
Betti bettiNumbers(const PhantomShape& shape);
/// Reach of the boundary in mm (0 where the boundary has creases).
double reach(const PhantomShape& shape);
/// Axis-aligned world bounds of the solid.
void bounds(const PhantomShape& shape, Vec3* min, Vec3* max);

}  // namespace xsect

// A deterministic branching tree of tubes (capsules) growing along +z: the thin branching
// structures of thesis ch. 2 (reach_i much smaller than reach_e). Every branch direction keeps a
// positive z component, so every plane z = const between the root and the tips crosses each
// branch at most once, and a sweep along z crosses every branch.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/phantom_shape.h"

namespace xsect {

struct VesselTreeParams {
  double length = 10.0;           ///< root segment length, mm (> 0)
  double radius = 1.0;            ///< root tube radius, mm (> 0)
  int levels = 3;                 ///< branching generations after the root (0 = a single tube)
  double branch_angle_deg = 30.0; ///< angle of each child branch to +z, degrees, in (0, 80]
  double length_ratio = 0.8;      ///< child length / parent length
  double radius_ratio = 0.85;     ///< child radius / parent radius
  std::uint64_t seed = 1;         ///< drives the azimuth of each bifurcation
};

/// Tubes of the tree in the shape frame: root from (0,0,0) to (0,0,length); each tip splits in
/// two children at branch_angle_deg from +z, on opposite sides of a random azimuth. Tubes that are
/// not parent/child or siblings keep a clearance of at least half the smaller radius between
/// their capsules (azimuths are redrawn until they do), so the union is contractible:
/// Betti (1, 0, 0). Throws std::runtime_error if no such tree is found.
std::vector<PhantomShape::Tube> growVesselTree(const VesselTreeParams& params);

/// Distance in mm between segments [a0, a1] and [b0, b1].
double segmentDistance(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1);

}  // namespace xsect

// A deterministic branching tree of tubes (capsules) growing along +z: the thin branching
// structures of thesis ch. 2 (reach_i much smaller than reach_e). Every branch direction keeps a
// positive z component, so every plane z = const between the root and the tips crosses each
// branch at most once, and a sweep along z crosses every branch.
//
// Junction blending (blend_mm = k > 0). The solid is {f < 0} with
//   f = min over junctions J of B_J,   B_J = S_k(d_parent, S_k(d_child1, d_child2)),
// d_i the signed distance of capsule i and S_k the C^2 smooth minimum
//   S_k(a, b) = min(a, b) - k phi(|a - b| / k),  phi(t) = (1 - t)^3 (3 + t) / 16 for t < 1, else 0
// (its partial derivatives are >= 0 and sum to 1, so f is 1-Lipschitz; S_k <= min, and
// S_k >= min - 3k/16). A junction is a tube's end with the tubes starting there; each tube takes
// part in the junction where it starts (as a child) and the one where it ends (as the parent).
// Away from the fillets B_J is the plain minimum of its capsules, so two junctions sharing a tube
// agree there, and f is the union of capsules. S_k replaces each junction's concave creases by a
// fillet whose width is ~k; the surface lies at most delta = 3k/8 outside the capsules.
// Smoothness: when any two tubes that share no junction keep a surface gap > 2k + 2 delta (the
// grower keeps 3k), at every boundary point at most one junction's blend is active, so the
// boundary is C^2 wherever the capsules' distances are (C^{1,1} across the planes where a capsule's
// cylinder meets its cap): no creases. k = 0 gives back the union of capsules exactly.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/phantoms/phantom_shape.h"

namespace xsect {

struct VesselTreeParams {
  double length = 10.0;           ///< root segment length, mm (> 0)
  double radius = 1.0;            ///< root tube radius, mm (> 0)
  int levels = 3;                 ///< branching generations after the root (0 = a single tube)
  double branch_angle_deg = 30.0; ///< angle of each child branch to +z, degrees, in (0, 80]
  double length_ratio = 0.8;      ///< child length / parent length
  double radius_ratio = 0.85;     ///< child radius / parent radius
  std::uint64_t seed = 1;         ///< drives the azimuth of each bifurcation
  double blend_mm = 0.0;          ///< junction smooth-union width k, mm (>= 0)
};

/// Tubes of the tree in the shape frame: root from (0,0,0) to (0,0,length); each tip splits in
/// two children at branch_angle_deg from +z, on opposite sides of a random azimuth. Tubes that are
/// not parent/child or siblings keep a clearance of at least max(half the smaller radius,
/// 3 blend_mm) between their capsules (azimuths are redrawn until they do), so the union is
/// contractible, Betti (1, 0, 0), and the blends of different junctions never meet.
/// Throws std::runtime_error if no such tree is found.
std::vector<PhantomShape::Tube> growVesselTree(const VesselTreeParams& params);

/// Distance in mm between segments [a0, a1] and [b0, b1].
double segmentDistance(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1);

/// The junctions of a set of tubes: for every tube with children (the tubes whose start is
/// exactly its end) one junction {tube, children}; a tube that is neither a child nor a parent
/// (a lone root) gets a junction without children. In tube order.
std::vector<PhantomShape::Junction> linkVesselJunctions(
    const std::vector<PhantomShape::Tube>& tubes);

/// The C^2 smooth minimum S_k(a, b) above; k = 0 gives min(a, b).
double smoothMin(double a, double b, double k);

/// Largest distance by which the blended surface lies outside the union of capsules:
/// 3k/16 per smooth minimum of a junction (3k/8 for two children).
double vesselBlendOffset(const PhantomShape& shape);

/// f above at q (shape frame, mm): negative inside; exactly 0 on the boundary; 1-Lipschitz.
double vesselTreeSdf(const PhantomShape& shape, const Vec3& q);

/// f with its gradient and Hessian at q (shape frame), from the capsules' exact derivatives.
struct SdfJet {
  double value = 0.0;
  Vec3 gradient = Vec3::Zero();
  Eigen::Matrix3d hessian = Eigen::Matrix3d::Zero();
};
SdfJet vesselTreeJet(const PhantomShape& shape, const Vec3& q);

/// A nearest point of the boundary {f = 0} to q (shape frame), by numerical projection: starts
/// from the Newton projection of q and of the nearest point of every capsule that can hold the
/// nearest boundary point, each refined by a descent of |x - q| along the surface (projected
/// tangent steps, Newton back onto f = 0). Accurate to ~1e-7 mm where the nearest point is unique.
Vec3 vesselTreeClosestPoint(const PhantomShape& shape, const Vec3& q);

/// Reach bounds of the tree's boundary, mm (see vessel_tree.cpp for the derivation).
struct VesselReach {
  double interior = 0.0;  ///< distance of the boundary to the inner medial axis (lower bound)
  double exterior = 0.0;  ///< distance to the outer medial axis (lower bound; inf: none)
};
VesselReach vesselTreeReach(const PhantomShape& shape);

}  // namespace xsect

// Analytic phantom shapes (docs/inputs.md, phantoms): exact signed distance (negative inside), Betti
// numbers, reach (thesis Def. 5 / Def. 21: distance of the boundary to its medial axis) and bounds.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "geometry/core/named_choice.h"
#include "geometry/core/types.h"

namespace xsect {

/// The kinds of phantom shape (`shape.kind` of a phantom specification or truth file).
enum class ShapeKind {
  sphere,
  ellipsoid,
  torus,
  genus2,
  hollow_sphere,
  two_spheres,
  vessel_tree,
  twisted_cylinder,
  notched_torus,
  cup
};
constexpr std::array<NamedChoice<ShapeKind>, 10> kShapeKinds{{
    {ShapeKind::sphere, "sphere"},
    {ShapeKind::ellipsoid, "ellipsoid"},
    {ShapeKind::torus, "torus"},
    {ShapeKind::genus2, "genus2"},
    {ShapeKind::hollow_sphere, "hollow_sphere"},
    {ShapeKind::two_spheres, "two_spheres"},
    {ShapeKind::vessel_tree, "vessel_tree"},
    {ShapeKind::twisted_cylinder, "twisted_cylinder"},
    {ShapeKind::notched_torus, "notched_torus"},
    {ShapeKind::cup, "cup"},
}};

/// A shape in its own frame, placed in the world by `centre` and `rotation` (world <- shape):
/// world = centre + rotation * shape_point.
/// `params` holds the kind's named dimensions in mm (see phantomShapeParams() and
/// phantom_shape.cpp for each kind's keys).
struct PhantomShape {
  ShapeKind kind = ShapeKind::sphere;
  std::map<std::string, double> params;
  Vec3 centre = Vec3::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  /// vessel_tree only: the tree's segments in the shape frame (mm), each a capsule of the given
  /// radius (mm) around segment ab. Filled by completePhantomShape() from the params.
  struct Tube { Vec3 a, b; double radius; };
  std::vector<Tube> tubes;
  /// vessel_tree only: each tube's end with the tubes starting there (geometry/phantoms/vessel_tree.h),
  /// indices into `tubes`. Filled by completePhantomShape().
  struct Junction {
    int parent = 0;
    std::vector<int> children;
  };
  std::vector<Junction> junctions;
  /// Reach bounds (mm) known in advance: set by completePhantomShape() for the vessel tree (whose
  /// bounds are sampled) and by readTruthFile() from the file; when unset, reachInterior() and
  /// reachExterior() compute them from the params. Infinite = no medial axis on that side.
  std::optional<double> reach_interior_mm, reach_exterior_mm;
  /// Two-label phantoms: the plane (shape frame) splitting the solid into material 1 (points x
  /// with normal . (x - point) < 0) and material 2 (the rest). Unset: one material, label 1.
  struct LabelSplit {
    Vec3 point = Vec3::Zero();
    Vec3 normal = Vec3::UnitX();  ///< unit
  };
  std::optional<LabelSplit> label_split;
  /// Betti numbers of each material (label -> Betti) known in advance (read from a truth file);
  /// when unset, labelBettiNumbers() computes them.
  std::optional<std::map<int, Betti>> label_betti;
};

/// Signed distance in mm from x (world) to the boundary; negative inside.
/// For shapes with hasExactDistance() false, a conservative estimate: correct sign, zero exactly
/// on the boundary, 1-Lipschitz (hence |value| <= true distance).
double signedDistance(const PhantomShape& shape, const Vec3& x);
/// True when signedDistance is the exact Euclidean signed distance everywhere.
bool hasExactDistance(const PhantomShape& shape);
Betti bettiNumbers(const PhantomShape& shape);
/// Reach of the boundary in mm: the smaller of reachInterior and reachExterior (0 where the
/// boundary has creases).
double reach(const PhantomShape& shape);
/// Lower bound (mm) of the distance from the boundary to the inner medial axis (thesis reach_i):
/// 0 at convex creases.
double reachInterior(const PhantomShape& shape);
/// Lower bound (mm) of the distance from the boundary to the outer medial axis (reach_e): 0 at
/// concave creases, infinite for convex shapes (sphere, ellipsoid).
double reachExterior(const PhantomShape& shape);
/// A nearest point of the boundary to x (world, mm). Exact-distance kinds: x - sdf * grad sdf,
/// polished onto the surface. Vessel tree: numerical projection (vessel_tree.h), global over
/// every capsule that can hold the nearest point. Other kinds: a local projection (gradient
/// flow onto the zero set, then a descent of the distance along the surface).
/// |x - closestBoundaryPoint(x)| is the exact unsigned distance where signedDistance is not.
Vec3 closestBoundaryPoint(const PhantomShape& shape, const Vec3& x);

/// Material label at x (world): 0 outside the solid, else 1, or 2 on the positive side of
/// label_split (always 1 without a split).
int materialLabel(const PhantomShape& shape, const Vec3& x);
/// Betti numbers of each material's solid (label -> Betti) of a shape with a label_split:
/// label_betti when set, else computed with geometry/core/digital_topology.h on two voxel grids
/// (voxel v = min(reach, the shape's size / 30) / 2.5, at most 1e7 voxels, and 0.8 v); empty
/// without a split. Throws std::runtime_error unless both grids agree and their union has the
/// shape's Betti numbers (a split plane grazing the surface, or a grid too coarse).
std::map<int, Betti> labelBettiNumbers(const PhantomShape& shape);
/// Axis-aligned world bounds of the solid (conservative: may be slightly larger than tight).
void bounds(const PhantomShape& shape, Vec3* min, Vec3* max);

/// For a kind: its parameter names, each with its default value (nullopt = required).
std::map<std::string, std::optional<double>> phantomShapeParams(ShapeKind kind);

/// What is wrong with a shape's parameters: the parameter name and why.
struct ShapeProblem {
  std::string param;
  std::string message;
};

/// Checks the parameter values (positivity, non-overlap constraints of each kind).
std::optional<ShapeProblem> checkPhantomShape(const PhantomShape& shape);

/// Fills defaults of missing optional params and derived data (vessel_tree: tubes, grown from the
/// params unless already given, junctions, params["nominal_reach"] = smallest tube radius, mm,
/// and the reach bounds unless already set). Assumes checkPhantomShape() passed.
/// Throws std::runtime_error when no vessel tree without self-contact can be grown.
PhantomShape completePhantomShape(PhantomShape shape);

/// Rotation matrix from xyz Euler angles in degrees: R = Rz(z) * Ry(y) * Rx(x)
/// (rotate about world x first, then y, then z).
Eigen::Matrix3d rotationFromEulerXyzDeg(const Vec3& degrees);

}  // namespace xsect

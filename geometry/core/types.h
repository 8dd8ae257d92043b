// Value types shared by every stage: planes, sections, cutting planes, grids, meshes.
// Vocabulary of the thesis (Introduction §3.1-3.2): a cutting plane P carries sections, the
// connected components of O ∩ P; each section is a planar region bounded by section-contours.
// Units: millimetres. World frame right-handed.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace xsect {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat4 = Eigen::Matrix4d;

/// A plane with an orthonormal, right-handed frame (u, v, normal) and an origin.
/// Plane coordinates (a, b) in mm map to origin + a*u + b*v.
struct Plane {
  Vec3 origin = Vec3::Zero();
  Vec3 u = Vec3::UnitX();
  Vec3 v = Vec3::UnitY();
  Vec3 normal = Vec3::UnitZ();

  Vec3 toWorld(const Vec2& p) const { return origin + p.x() * u + p.y() * v; }
  /// Plane coordinates of the orthogonal projection of x on the plane.
  Vec2 toPlane(const Vec3& x) const {
    const Vec3 d = x - origin;
    return {d.dot(u), d.dot(v)};
  }
  /// Signed distance of x to the plane (positive on the normal's side).
  double signedDistance(const Vec3& x) const { return (x - origin).dot(normal); }
};

/// A closed polygonal curve in plane coordinates (mm); the last vertex connects to the first.
using Ring = std::vector<Vec2>;

/// A section: one connected planar region, an outer contour (counter-clockwise) with holes
/// (clockwise), in the (u, v) frame of its plane.
struct Section {
  Ring outer;
  std::vector<Ring> holes;
  int label = 1;  ///< material label (1 for single-material inputs)
};

/// Axis-aligned rectangle in plane coordinates (mm): the part of the plane that was observed.
struct PlaneRect {
  Vec2 min = Vec2::Zero();
  Vec2 max = Vec2::Zero();
  bool contains(const Vec2& p) const {
    return p.x() >= min.x() && p.x() <= max.x() && p.y() >= min.y() && p.y() <= max.y();
  }
};

/// A cutting plane P_i with its sections S_i = O ∩ P_i.
struct CuttingPlane {
  int slice = -1;          ///< index of the input slice; -1 for a virtual plane
  std::string name;        ///< e.g. the image path, or "end-plane +x"
  Plane plane;
  std::vector<Section> sections;
  PlaneRect extent;        ///< observed part of the plane (image bounds) in plane coordinates
  /// The field of view within the extent when a mask narrowed it (a probe's sector): its rings in
  /// plane coordinates (mm). Empty: the whole extent was observed (a mask with no observed pixel
  /// leaves the extent empty instead).
  std::vector<Ring> field_of_view;
  /// Contours given directly (.csl): the whole plane counts as observed, the sections are all of
  /// O ∩ P (the extent is only the sections' bounds).
  bool observed_everywhere = false;
  double pixel_mm = 0.0;   ///< image pixel size (finest detail the sections carry); 0 if unknown
  bool is_virtual = false; ///< virtual empty plane added to close open cells (issue: open ends)
};

/// A regular grid of voxel centres: centre (i, j, k) is at origin + voxel * (i, j, k).
struct GridSpec {
  Vec3 origin = Vec3::Zero();
  double voxel = 1.0;
  std::array<int, 3> dims{0, 0, 0};
  std::int64_t count() const {
    return std::int64_t(dims[0]) * dims[1] * dims[2];
  }
  std::int64_t index(int i, int j, int k) const {
    return (std::int64_t(k) * dims[1] + j) * dims[0] + i;
  }
  Vec3 centre(int i, int j, int k) const { return origin + voxel * Vec3(i, j, k); }
  /// The (i, j, k) of the voxel at `index` (the inverse of index()).
  std::array<int, 3> coordinates(std::int64_t index) const {
    return {int(index % dims[0]), int((index / dims[0]) % dims[1]), int(index / (std::int64_t(dims[0]) * dims[1]))};
  }
  /// The centre of the voxel at `index`.
  Vec3 centre(std::int64_t index) const {
    const std::array<int, 3> c = coordinates(index);
    return centre(c[0], c[1], c[2]);
  }
};

/// Dense scalar field on a GridSpec, x fastest. Negative = inside.
struct ScalarField {
  GridSpec grid;
  std::vector<float> values;
  float at(int i, int j, int k) const { return values[grid.index(i, j, k)]; }
};

/// A narrow-band level set on the voxel lattice of a GridSpec (OpenVDB's sparse layout, without its
/// types, so that stages and file formats share it): signed distances in mm, negative inside, at the
/// active voxels; every other voxel holds ±background (the band's half-width, mm), negative when it
/// is enclosed by the surface. Voxel (i, j, k) is centred at grid.origin + grid.voxel * (i, j, k);
/// coordinates may lie outside grid.dims (the band can reach past the sampled box).
struct NarrowBandLevelSet {
  GridSpec grid;
  float background = 0.0f;                 ///< half-width of the band, mm (> 0)
  std::vector<std::array<int, 3>> coords;  ///< active voxels, sorted by (k, j, i)
  std::vector<float> values;               ///< signed distance at each active voxel, mm
};

/// Triangle mesh, consistently oriented with outward normals when closed.
struct TriangleMesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

/// Betti numbers of a solid: components, tunnels (total genus of its boundary), cavities.
using Betti = std::array<int, 3>;

}  // namespace xsect

// OpenVDB meshing of a dense field (see volume_mesher.h). OpenVDB headers stay in this file.
#include "geometry/volume_mesher.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <algorithm>

namespace xsect {

TriangleMesh meshZeroLevel(const ScalarField& field, double adaptivity) {
  openvdb::initialize();  // idempotent
  const auto& g = field.grid;
  float background = 0.0f;
  for (float v : field.values) background = std::max(background, v);
  background = std::max(background, 1e-3f);
  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(background);
  {
    const openvdb::CoordBBox bbox(openvdb::Coord(0, 0, 0),
                                  openvdb::Coord(g.dims[0] - 1, g.dims[1] - 1, g.dims[2] - 1));
    openvdb::tools::Dense<const float, openvdb::tools::LayoutXYZ> dense(bbox, field.values.data());
    openvdb::tools::copyFromDense(dense, *grid, 0.0f);
  }
  grid->setTransform(openvdb::math::Transform::createLinearTransform(g.voxel));
  grid->transform().postTranslate(openvdb::Vec3d(g.origin.x(), g.origin.y(), g.origin.z()));

  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> tris;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(*grid, points, tris, quads, 0.0, adaptivity);

  TriangleMesh mesh;
  mesh.vertices.reserve(points.size());
  for (const auto& p : points) mesh.vertices.emplace_back(p.x(), p.y(), p.z());
  mesh.triangles.reserve(tris.size() + 2 * quads.size());
  for (const auto& t : tris) mesh.triangles.push_back({t[0], t[1], t[2]});
  for (const auto& q : quads) {
    const auto& v = mesh.vertices;
    const float d02 = (v[q[0]] - v[q[2]]).squaredNorm(), d13 = (v[q[1]] - v[q[3]]).squaredNorm();
    if (d02 <= d13) {
      mesh.triangles.push_back({q[0], q[1], q[2]});
      mesh.triangles.push_back({q[0], q[2], q[3]});
    } else {
      mesh.triangles.push_back({q[0], q[1], q[3]});
      mesh.triangles.push_back({q[1], q[2], q[3]});
    }
  }
  double volume = 0;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[t[0]].cast<double>(), b = mesh.vertices[t[1]].cast<double>(),
                          c = mesh.vertices[t[2]].cast<double>();
    volume += a.dot(b.cross(c)) / 6.0;
  }
  if (volume < 0)
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  return mesh;
}

}  // namespace xsect

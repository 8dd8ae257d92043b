// The solid kept by blocks (issue 17): a grid the dense layout could not hold (more than 2^31
// voxels: one byte each would already be 2 GB, the dense field and plane arrays 26 GB)
// reconstructs, with the object's topology, in no more memory than the estimate made before
// (solid_memory.h), and the estimate does not undercount the blocks a run keeps.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "geometry/meshing/mesh_topology.h"
#include "geometry/meshing/volume_mesher.h"
#include "geometry/reconstruction/sampled_reconstruction.h"
#include "geometry/reconstruction/solid_memory.h"
#include "section_fixtures.h"

using namespace xsect;

namespace {

/// This process's resident memory now ("VmRSS") or at its peak ("VmHWM"), bytes.
double statusBytes(const std::string& key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key + ":", 0) == 0) return std::stod(line.substr(key.size() + 1)) * 1024.0;
  return 0;
}

/// A ball of radius 1 mm cut by three orthogonal planes through its centre.
std::vector<CuttingPlane> ballThroughThreePlanes() {
  std::vector<CuttingPlane> planes;
  for (int axis = 0; axis < 3; ++axis) {
    CuttingPlane cp;
    cp.slice = axis;
    cp.plane = test::axisPlane(axis, 0.0);
    cp.sections = test::shellSections(cp.plane, Vec3::Zero(), 1.0, 0.0);
    planes.push_back(cp);
  }
  return planes;
}

}  // namespace

TEST(SparseSolid, GridPastTwoToThe31VoxelsFitsItsEstimate) {
  if (statusBytes("VmRSS") == 0) GTEST_SKIP() << "no /proc/self/status to measure memory with";
  const std::vector<CuttingPlane> planes = ballThroughThreePlanes();
  ReconstructionParams p;
  p.voxel_mm = 0.0324;     // the ball is 62 voxels across ...
  p.end_margin_mm = 40.0;  // ... in a grid of about 1300^3 voxels
  const ReconstructionLayout layout = reconstructionLayout(planes, p);
  ASSERT_GT(layout.grid.count(), std::int64_t(1) << 31);

  const SolidMemoryEstimate estimate = estimateSolidMemory(planes, p, 0);
  const double before = statusBytes("VmRSS");
  const SampledReconstruction rec = reconstructOnGrid(sectionScene(planes, p));
  const double solidPeak = statusBytes("VmHWM") - before;
  EXPECT_EQ(rec.voxel_betti, (Betti{1, 0, 0}));
  const MeshTopology mesh = meshTopology(meshZeroLevel(rec.field));
  const double peak = statusBytes("VmHWM") - before;
  EXPECT_TRUE(mesh.watertight);
  EXPECT_EQ(mesh.betti, (Betti{1, 0, 0}));
  // The solid lies within the ball's bounding cube (method 1 from three great circles), and
  // holds at least the octahedron the three disks span.
  const double h = p.voxel_mm, voxel3 = h * h * h;
  EXPECT_LT(double(rec.voxels_inside) * voxel3, 8.0);
  EXPECT_GT(double(rec.voxels_inside) * voxel3, 4.0 / 3.0);

  // Memory: the run's measured peaks within the estimate's parts, which count the blocks kept.
  EXPECT_LE(solidPeak, estimate.table_bytes + estimate.leaf_bytes) << "estimate " << estimate.total() / 1e6 << " MB";
  EXPECT_LE(peak, estimate.total());
  EXPECT_GE(estimate.boundary_blocks, rec.storage.field_leaves);
  EXPECT_GE(estimate.solid_blocks, rec.storage.section_leaves);
  EXPECT_LE(estimate.total(), 4e9);  // the budget for such a grid
  std::cerr << "grid " << layout.grid.count() << " voxels, " << rec.storage.blocks << " blocks; leaves: field "
            << rec.storage.field_leaves << ", section " << rec.storage.section_leaves << ", anchors "
            << rec.storage.anchor_leaves << "; peak " << solidPeak / 1e6 << " MB (solid), " << peak / 1e6
            << " MB (with the mesh); estimate " << (estimate.table_bytes + estimate.leaf_bytes) / 1e6 << " MB + mesh "
            << estimate.mesh_bytes / 1e6 << " MB\n";
}

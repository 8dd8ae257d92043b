// The memory a reconstruction keeps, from a coarse trial (see solid_memory.h).
#include "geometry/reconstruction/solid_memory.h"

#include <algorithm>
#include <cmath>

#include "geometry/core/block_grid.h"
#include "geometry/reconstruction/sampled_reconstruction.h"

namespace xsect {

namespace {

// Per block, the table entries of the block grids held at once (field, section planes, solid,
// its unrepaired copy, the two evidence sets, labels, the per-cell check's components, the
// longest lift): a value and a leaf pointer each.
constexpr double kTableBytesPerBlock = (4 + 8) + (4 + 8) + 4 * (1 + 8) + (2 + 8) + (4 + 8) + 4;
// Per leaf (512 voxels, plus the allocation's header): a boundary block holds the field (float),
// the solid and its copy (bytes) and labels (uint16); a block of the solid its deciding planes and
// the check's components (int); a block next to a plane its evidence (bytes).
constexpr double kLeafOverhead = 16;
constexpr double kBoundaryLeafBytes = 512 * (4 + 1 + 1 + 2) + 4 * kLeafOverhead;
constexpr double kSolidLeafBytes = 512 * (4 + 4) + 2 * kLeafOverhead;
constexpr double kPlaneLeafBytes = 512 * 1 + kLeafOverhead;
// Meshes: at most 2 triangles per voxel of a boundary block (measured: 1.6 on freehand-2000),
// about 100 bytes per triangle while the mesh stage holds the method's mesh, its conformal cut
// and the topology's edge lists (measured: 95).
constexpr double kMeshBytesPerBoundaryBlock = 2.0 * 512 * 100;
// Per row of voxels (ny nz of them): the repair's and Betti numbers' runs of the background (at
// least one per row: first run, ends, component, union-find parent) while the per-slab parts and
// the foreground's runs are alive too.
constexpr double kBytesPerRow = 8 + 2 * (4 + 4 + 4 + 8) + 16;
// The trial's size: small enough to cost a fraction of the run, fine enough to see the shape.
constexpr double kTrialVoxels = 2e6;

}  // namespace

double worstCaseSolidBytes(double blocks, double rows) {
  return blocks * (kTableBytesPerBlock + kBoundaryLeafBytes + kSolidLeafBytes + 2 * kPlaneLeafBytes +
                   kMeshBytesPerBoundaryBlock) +
         rows * kBytesPerRow;
}

SolidMemoryEstimate estimateSolidMemory(const std::vector<CuttingPlane>& real_planes,
                                        const ReconstructionParams& params, double dense_bytes_per_voxel) {
  const ReconstructionLayout layout = reconstructionLayout(real_planes, params);
  SolidMemoryEstimate e;
  e.voxels = layout.grid.count();
  e.blocks = blockCountOf(layout.grid);

  // The trial: method 1 on a grid at least twice as coarse, over the same box.
  ReconstructionParams coarse = params;
  coarse.method = ReconstructionMethod::nearest_plane;
  coarse.voxel_mm = params.voxel_mm * std::max(2.0, std::cbrt(double(e.voxels) / kTrialVoxels));
  coarse.end_margin_mm = layout.end_margin_mm;
  const SampledReconstruction trial = reconstructOnGrid(sectionScene(real_planes, coarse));
  const double f = coarse.voxel_mm / params.voxel_mm;
  e.coarse_factor = f;
  const auto capped = [&](double n, double cap) { return std::int64_t(std::min(std::ceil(n), cap)); };
  const double blocks = double(e.blocks);
  e.boundary_blocks = capped(double(trial.storage.field_leaves) * f * f, blocks);
  e.plane_blocks = capped(double(trial.storage.anchor_leaves) * f * f, 2 * blocks);
  e.solid_blocks = capped(double(trial.storage.section_leaves) * f * f + double(trial.voxels_inside) * f * f * f / 512, blocks);

  e.table_bytes = blocks * kTableBytesPerBlock +
                  double(layout.grid.dims[1]) * double(layout.grid.dims[2]) * kBytesPerRow;
  e.leaf_bytes = double(e.boundary_blocks) * kBoundaryLeafBytes + double(e.solid_blocks) * kSolidLeafBytes +
                 double(e.plane_blocks) * kPlaneLeafBytes;
  e.mesh_bytes = double(e.boundary_blocks) * kMeshBytesPerBoundaryBlock;
  e.dense_bytes = double(e.voxels) * dense_bytes_per_voxel;
  return e;
}

}  // namespace xsect

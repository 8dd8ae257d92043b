// Method 3 per material (see delaunay_materials.h).
#include "pipeline/delaunay_materials.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>

#include "geometry/arrangement/section_arrangement.h"
#include "geometry/delaunay/branching_diagram.h"
#include "geometry/delaunay/tetrahedra_components.h"
#include "geometry/delaunay/tetrahedra_voxels.h"
#include "pipeline/arrange_stage.h"
#include "pipeline/material_sections.h"

namespace xsect {

namespace {

/// Voxels of `solid` not yet labelled take `label` (block by block; voxels beyond the grid follow
/// the block's first voxel in both grids, so uniform blocks stay tiles).
void addLabel(BlockGrid<std::uint16_t>& labels, const BlockGrid<std::uint8_t>& solid, std::uint16_t label) {
  tbb::parallel_for(std::int64_t(0), solid.blockCount(), [&](std::int64_t b) {
    const std::uint8_t* in = solid.leaf(b);
    if (!in && !solid.tile(b)) return;
    const std::uint16_t* was = labels.leaf(b);
    std::array<std::uint16_t, BlockGrid<std::uint16_t>::kVoxels> values;
    for (std::size_t q = 0; q < values.size(); ++q) {
      const std::uint16_t l = was ? was[q] : labels.tile(b);
      const bool inSolid = (in ? in[q] : solid.tile(b)) != 0;
      values[q] = l != 0 ? l : inSolid ? label : std::uint16_t(0);
    }
    labels.setBlock(b, values.data());
  });
}

}  // namespace

DelaunayMaterials delaunayMaterials(const RunInputs& in, const std::vector<std::uint16_t>& labels,
                                    const SectionScene& scene,
                                    const std::function<void(std::int64_t, std::int64_t)>& progress) {
  DelaunayMaterials out;
  const GridSpec& grid = scene.grid();
  out.labels = BlockGrid<std::uint16_t>(grid, 0);
  ReconstructionParams params = scene.params;
  params.end_margin_mm = scene.layout.end_margin_mm;  // the run's end planes' distance
  float band = 0;
  for (const auto& f : scene.fields) band = std::max(band, f.band);
  if (!(band > 0)) band = float(params.band_voxels * params.voxel_mm);
  for (std::size_t k = 0; k < labels.size(); ++k) {
    DelaunayMaterial m;
    m.label = labels[k];
    const SectionScene own = sectionScene(materialPlanes(in, m.label), params);
    const SectionArrangement arrangement =
        arrangeSections(own.planes, arrangementSpacing(in.config, own.planes, own.real_planes));
    const BranchingDiagram branching = branchingDiagram(own, arrangement);
    DelaunayReconstruction r =
        delaunayReconstruction(own.planes, arrangement, branching.points, {}, &branching.g_double_prime,
                               in.config.cell_tunnels);
    m.tetrahedra_components = tetrahedraComponents(r.tetrahedra, r.tolerances);
    m.opened_copies = repeatedVertexCopies(r.mesh);
    m.mesh = std::move(r.mesh);
    m.stats = r.stats;
    m.connections = std::int64_t(r.connections.size());
    m.branching_points = std::int64_t(branching.points.size());
    const SampledReconstruction solid = tetrahedraOnGrid(r.tetrahedra, own.planes, own.real_planes, grid, band);
    m.voxels = solid.voxels_inside;
    m.voxel_betti = solid.voxel_betti;
    addLabel(out.labels, solid.inside, m.label);
    out.materials.push_back(std::move(m));
    if (progress) progress(std::int64_t(k) + 1, std::int64_t(labels.size()));
  }
  out.labels.compact();
  return out;
}

}  // namespace xsect

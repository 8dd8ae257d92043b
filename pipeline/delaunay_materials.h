// Method 3 with several materials (thesis ch. 3, closing remark: "interpolate the corresponding
// sections using the Delaunay triangulation of each material independently"): for each label, the
// run's planes holding only that label's sections, their own scene (the run's end margin),
// arrangement and branching diagram, and delaunayReconstruction on them; its mesh is that
// material's mesh, its tetrahedra are sampled on the run's grid for labels.nrrd. Materials
// reconstructed independently may overlap where their sections come close: a voxel in several
// solids takes the lowest label. The union's solid (mesh.<fmt>, the voxel checks) is method 3 on
// the union of the sections, as for methods 1 and 2.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "geometry/core/block_grid.h"
#include "geometry/core/digital_topology.h"
#include "geometry/delaunay/delaunay_reconstruction.h"
#include "geometry/scene/section_scene.h"
#include "pipeline/input_stage.h"

namespace xsect {

struct DelaunayMaterial {
  std::uint16_t label = 0;
  TriangleMesh mesh;                   ///< ∂R'' of the label's sections
  DelaunayStats stats;
  std::int64_t connections = 0;        ///< section pairs its tetrahedra join
  std::int64_t branching_points = 0;   ///< on its branching diagrams
  int tetrahedra_components = 0;       ///< components of its tetrahedra's union
  std::int64_t opened_copies = 0;      ///< vertex copies its mesh's opened pinches added
  std::int64_t voxels = 0;             ///< voxel centres in its tetrahedra (before overlaps are resolved)
  Betti voxel_betti{0, 0, 0};          ///< of those voxels
};

struct DelaunayMaterials {
  std::vector<DelaunayMaterial> materials;  ///< ascending labels, every label (an empty R'' too)
  BlockGrid<std::uint16_t> labels;          ///< labels.nrrd: per voxel the lowest label holding it, 0 elsewhere
};

/// @param labels  the labels to reconstruct (material_sections.h), at least two.
/// @param scene   the run's scene: its grid, end margin and parameters.
/// @param progress  optional, called with (labels done, labels).
DelaunayMaterials delaunayMaterials(const RunInputs& in, const std::vector<std::uint16_t>& labels,
                                    const SectionScene& scene,
                                    const std::function<void(std::int64_t, std::int64_t)>& progress = {});

}  // namespace xsect

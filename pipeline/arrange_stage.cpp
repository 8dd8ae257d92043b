// Stage 4: arrangement, graphs and their check (see arrange_stage.h).
#include "pipeline/arrange_stage.h"

#include <algorithm>
#include <cmath>

#include "geometry/core/polygon.h"

namespace xsect {

ArrangeStage arrangeStage(const RunConfig& c, const std::vector<CuttingPlane>& planes,
                          const ReconstructStage& reconstruction, std::vector<std::string>* warnings) {
  const SampledReconstruction& rec = reconstruction.solid;
  const ReconstructionParams& rp = reconstruction.params;
  ArrangeStage a;
  a.all_planes = planes;
  a.all_planes.insert(a.all_planes.end(), rec.end_planes.begin(), rec.end_planes.end());
  double area = 0;
  for (const auto& p : planes)
    for (const auto& s : p.sections) area += sectionArea(s);
  // Lattice of section points: the voxel size, coarser when it would exceed 250 000 points.
  const double spacing = std::max(c.voxel_size_mm, std::sqrt(area / 250000.0));
  a.arrangement = arrangeSections(a.all_planes, spacing);
  SectionVoronoiParams vp;
  vp.slab_mm = rp.slab_voxels * rp.voxel_mm;
  a.method2 = rp.method == ReconstructionMethod::section_voronoi;
  // rec.fields: the real planes' rasters, then the end planes'.
  a.graphs = connectivityGraphs(a.all_planes, rec.fields, a.arrangement, vp, a.method2);
  a.graph_check = compareWithVoxels(a.methodEdges(), planes, a.arrangement, rec.fields, rec.inside, rec.field.grid);
  // The same, cell by cell (thesis: R_C's components are the classes of S_C the lifts join).
  a.cell_check =
      compareCellsWithVoxels(a.methodEdges(), a.all_planes, a.arrangement, rec.fields, rec.inside, rec.field.grid);
  for (const GraphEdge& e : a.graphs.g)
    a.g_in_g_prime = a.g_in_g_prime && std::binary_search(a.graphs.g_prime.begin(), a.graphs.g_prime.end(), e);
  const GraphVoxelCheck& g = a.graph_check;
  if (!g.same_partition)
    warnings->push_back("the connectivity graph and the voxel solid group the sections differently (" +
                        std::to_string(g.pairs_joined_by_graph_only) + " pairs joined by the graph only, " +
                        std::to_string(g.pairs_joined_by_voxels_only) + " by the voxels only, " +
                        std::to_string(g.sections_unlocated) + " sections not located)");
  return a;
}

}  // namespace xsect

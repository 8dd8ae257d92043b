// Stage 5: the solid on the scene's grid and its check against the graph (see reconstruct_stage.h).
#include "pipeline/reconstruct_stage.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "geometry/core/digital_topology.h"
#include "geometry/delaunay/tetrahedra_components.h"
#include "geometry/delaunay/tetrahedra_voxels.h"
#include "geometry/meshing/mesh_topology.h"
#include "io/input_error.h"
#include "pipeline/material_sections.h"

namespace xsect {

namespace {

double secondsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

/// Method 3: R'' on the scene's planes and arrangement, its tetrahedra sampled on the grid, and per
/// material when there are several labels.
void delaunayOnGrid(const RunInputs& in, const SceneStage& built, const ArrangeStage& a, Progress& progress,
                    ReconstructStage& r) {
  const RunConfig& c = in.config;
  const SectionScene& scene = built.scene;
  auto t0 = std::chrono::steady_clock::now();
  DelaunayStage& m3 = r.delaunay.emplace();
  m3.result = delaunayReconstruction(scene.planes, a.arrangement, a.branching, progress.counter(),
                                     &a.graphs.g_double_prime, c.cell_tunnels);
  m3.delaunay_s = secondsSince(t0);
  const DelaunayReconstruction& d = m3.result;
  if (d.tetrahedra.empty())
    throw InputError(c.path, "reconstruction.method",
                     built.counts.planes_with_sections <= 1
                         ? "method 3 (delaunay) joins sections of different planes, and only one plane holds "
                           "sections: use nearest_plane or section_voronoi"
                         : "method 3 (delaunay) kept no tetrahedron: no two planes' sections face each other in a "
                           "cell of the arrangement (every tetrahedron was external); use nearest_plane or "
                           "section_voronoi");
  float band = 0;
  for (const auto& f : scene.fields) band = std::max(band, f.band);
  if (!(band > 0)) band = float(scene.params.band_voxels * scene.params.voxel_mm);
  // The checks' numbers beside the voxelisation (both read the tetrahedra only).
  tbb::parallel_invoke(
      [&] {
        // What the mesh's b0 is checked against (mesh_stage.h; tetrahedra_components.h).
        m3.components = tetrahedraComponents(d.tetrahedra, d.tolerances);
        m3.opened_copies = repeatedVertexCopies(d.mesh);
        m3.connections_not_in_graph = edgesMissing(d.connections, a.graphs.g_double_prime);
        m3.graph_edges_not_realised = edgesMissing(a.graphs.g_double_prime, d.connections);
      },
      [&] {
        // One solid (issue 49): the voxels as the boundary is, by centres or by cubes; the glued
        // boundary with open edges is replaced by the voxels' mesh anyway.
        const auto tv = std::chrono::steady_clock::now();
        if (d.stats.open_edges > 0) {
          r.solid = tetrahedraOnGrid(d.tetrahedra, scene.planes, scene.real_planes, scene.grid(), band);
        } else {
          // Refined grids (the voxel halved up to twice, sparse: the blocks the boundary and the
          // solid fill) only without smoothing: the smoothing works on the scene's lattice.
          m3.boundary_betti = meshTopology(d.mesh).betti;
          // Nor with several materials: their solids are made from dense copies of the grid.
          const int refinements =
              c.smoothing_method == SmoothingMethod::none && materialLabels(in).size() < 2 ? 2 : 0;
          r.solid = tetrahedraOnGridLike(d.tetrahedra, scene.planes, scene.real_planes, scene.grid(), band,
                                         m3.boundary_betti, refinements, &m3.voxels);
        }
        m3.voxelise_s = secondsSince(tv);
      });
  r.solid.evaluate_seconds = m3.delaunay_s + m3.voxelise_s;
  // Where the grid cannot hold the topology of R'' by either rule (or its boundary has open edges),
  // the voxels, made well-composed, are the solid and the mesh is theirs: mesh, labels.nrrd and the
  // Betti numbers describe one object (mesh_stage.cpp).
  if (r.solid.voxels_inside > 0 && (d.stats.open_edges > 0 || r.solid.voxel_betti != m3.boundary_betti)) {
    m3.mesh_from_voxels = true;
    m3.voxels_added_well_composed = makeWellComposed(r.solid.inside);
    imposeSolid(r.solid.field, r.solid.inside, float(0.05 * r.solid.inside.grid().voxel));
    r.solid.raw_inside = r.solid.inside;
    r.solid.voxels_inside = r.solid.inside.count(1);
    r.solid.voxel_betti = voxelBetti(r.solid.inside);
  }
  if (r.solid.voxels_inside == 0)
    r.warnings.push_back("method 3's solid holds no voxel centre at " + std::to_string(scene.params.voxel_mm) +
                        " mm (it is thinner than a voxel): labels.nrrd and the voxel checks are empty; the mesh is "
                        "R'' itself");
}

}  // namespace

ReconstructStage reconstructStage(const RunInputs& in, const SceneStage& built, const ArrangeStage& a,
                                  Progress& progress) {
  const RunConfig& c = in.config;
  const SectionScene& scene = built.scene;
  ReconstructStage r;
  const bool delaunay = scene.params.method == ReconstructionMethod::delaunay;
  if (delaunay) delaunayOnGrid(in, built, a, progress, r);
  else  // the unrepaired set is read only by the smoothing (smooth_stage.cpp)
    r.solid = reconstructOnGrid(scene, progress.counter(), c.smoothing_method != SmoothingMethod::none);
  const SampledReconstruction& rec = r.solid;
  if (rec.voxels_inside == 0 && !delaunay) {
    // A voxel so coarse that nothing is left: the configuration must change (exit 2, issue 48: an
    // explicit size as an automatic one), and the message says to what.
    const VoxelSizeReport& v = built.voxel_size;
    const bool budget = v.automatic && v.choice.limited_by == VoxelSizeLimit::voxel_budget;
    throw InputError(c.path, budget ? "reconstruction.voxel_budget" : "reconstruction.voxel_size_mm",
                     emptySolidMessage(v, built.counts.sections));
  }
  r.graph_check = compareWithVoxels(a.methodEdges(), scene, a.arrangement, rec.inside);
  r.cell_check = compareCellsWithVoxels(a.methodEdges(), scene, a.arrangement, rec.inside);
  const GraphVoxelCheck& g = r.graph_check;
  if (!g.same_partition)
    r.warnings.push_back("the connectivity graph and the voxel solid group the sections differently (" +
                        std::to_string(g.pairs_joined_by_graph_only) + " pairs joined by the graph only, " +
                        std::to_string(g.pairs_joined_by_voxels_only) + " by the voxels only, " +
                        std::to_string(g.sections_unlocated) + " sections not located)");
  return r;
}

}  // namespace xsect

// Stage 5: the method's solid on the grid, its topology as asked, and its check against the graph
// (see reconstruct_stage.h).
#include "pipeline/reconstruct_stage.h"

#include <algorithm>
#include <cstdio>
#include <iterator>

#include "geometry/core/section_ids.h"
#include "geometry/reconstruction/voxel_labels.h"
#include "io/input_error.h"

namespace xsect {

namespace {

std::string bettiList(const Betti& b) {
  return "[" + std::to_string(b[0]) + ", " + std::to_string(b[1]) + ", " + std::to_string(b[2]) + "]";
}

/// The smallest tunnels and cavities of the solid reached, with their sizes and places (at most
/// three), so that a refusal says whether they are pinholes (about a voxel) or the sections' own.
std::string featuresLeft(const TopologyControl& t, double voxel) {
  if (!t.features_computed || t.features.empty()) return "";
  std::string s = " (the smallest left: ";
  for (std::size_t i = 0; i < t.features.size() && i < 3; ++i) {
    const TopologyFeature& f = t.features[i];
    char text[160];
    std::snprintf(text, sizeof text, "%sa %s of %.3g mm (%.2g voxels) at (%.4g, %.4g, %.4g) mm", i ? "; " : "",
                  f.dimension == 1 ? "tunnel" : "cavity", f.size_mm, f.size_mm / voxel, f.born_at.x(), f.born_at.y(),
                  f.born_at.z());
    s += text;
  }
  return s + "; one about a voxel in size is a pinhole where lifts meet within a voxel of a plane, whose voxels "
             "only that plane's sections decide)";
}

/// reconstruction.topology (issue 51): each voxel labelled with the section its lift comes from,
/// joins cut and added cell by cell until the solid has the topology asked for (topology_control.h); the
/// solid, its field (for the mesh) and its Betti numbers then describe the solid chosen.
TopologyControl chooseTopology(const RunConfig& c, const SectionScene& scene, const ArrangeStage& a,
                               SampledReconstruction& rec, Progress& progress) {
  const SectionIds ids = scene.ids();
  if (ids.count() > 65534)
    throw InputError(c.path, "reconstruction.topology",
                     "labels each voxel with its section, at most 65534 sections; these slices hold " +
                         std::to_string(ids.count()) + ": use reconstruction.topology: free");
  std::vector<std::vector<Section>> bySection(scene.planes.size());
  for (std::size_t p = 0; p < scene.real_planes; ++p) {
    bySection[p] = scene.planes[p].sections;
    for (std::size_t s = 0; s < bySection[p].size(); ++s)
      bySection[p][s].label = int(ids.of(int(p), int(s)) + 1);
  }
  const GridSpec& grid = rec.inside.grid();
  std::vector<std::uint8_t> inside = denseValues(rec.inside);
  TopologyControl t =
      controlTopology(inside, grid, denseValues(voxelLabels(rec.inside, rec.section_plane, scene.planes, bySection,
                                                            &scene.pieces)),
                      scene.planes, scene.real_planes, scene.fields, a.arrangement, c.topology,
                      progress.counter());
  if (!t.reached)
    throw InputError(c.path, "reconstruction.topology",
                     "the method's solid has Betti numbers " + bettiList(t.before) + "; cutting and adding joins "
                     "and mending gaps and necks inside cells (" + std::to_string(t.joins) + " joins made, " +
                     std::to_string(t.joins_possible) + " possible, " + std::to_string(t.mends_possible) +
                     " mends found, " + std::to_string(t.evaluated) + " changes tried) came no nearer to " +
                     bettiList(c.topology.target) + " than " + bettiList(t.after) + featuresLeft(t, grid.voxel) +
                     ": check the target, or use reconstruction.topology: simplest (the fewest components, "
                     "tunnels and cavities found) or free");
  if (!t.changes.empty()) {
    rec.inside = blockValues(inside, grid);
    rec.raw_inside = rec.inside;
    rec.voxels_inside = rec.inside.count(1);
    rec.voxel_betti = t.after;
    imposeSolid(rec.field, rec.inside, float(0.05 * grid.voxel));
  }
  return t;
}

}  // namespace

ReconstructStage reconstructStage(const RunInputs& in, const SceneStage& built, const ArrangeStage& a,
                                  const Method& method, Progress& progress) {
  ReconstructStage r = method.reconstruct(in, built, a, progress);
  const SectionScene& scene = built.scene;
  if (in.config.topology.mode != TopologyMode::free) {
    progress.stage("topology", "changes");
    r.topology = chooseTopology(in.config, scene, a, r.solid, progress);
    const std::vector<GraphEdge>& method = a.methodEdges();
    std::vector<GraphEdge> kept;
    std::set_difference(method.begin(), method.end(), r.topology->edges_cut.begin(), r.topology->edges_cut.end(),
                        std::back_inserter(kept));
    std::set_union(kept.begin(), kept.end(), r.topology->edges_added.begin(), r.topology->edges_added.end(),
                   std::back_inserter(r.joins_chosen));
  }
  const std::vector<GraphEdge>& joins = r.joins(a.methodEdges());
  r.graph_check = compareWithVoxels(joins, scene, a.arrangement, r.solid.inside);
  r.cell_check = compareCellsWithVoxels(joins, scene, a.arrangement, r.solid.inside);
  const GraphVoxelCheck& g = r.graph_check;
  if (!g.same_partition)
    r.warnings.push_back("the connectivity graph and the voxel solid group the sections differently (" +
                         std::to_string(g.pairs_joined_by_graph_only) + " pairs joined by the graph only, " +
                         std::to_string(g.pairs_joined_by_voxels_only) + " by the voxels only, " +
                         std::to_string(g.sections_unlocated) + " sections not located)");
  return r;
}

}  // namespace xsect

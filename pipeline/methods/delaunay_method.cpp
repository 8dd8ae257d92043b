// Method 3: R'' on the grid, its mesh and its report (see delaunay_method.h).
#include "pipeline/methods/delaunay_method.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <stdexcept>

#include "geometry/core/digital_topology.h"
#include "geometry/delaunay/tetrahedra_components.h"
#include "geometry/delaunay/tetrahedra_voxels.h"
#include "geometry/meshing/volume_mesher.h"
#include "io/input_error.h"
#include "pipeline/material_sections.h"
#include "pipeline/mesh_bounds.h"
#include "pipeline/reconstruct_stage.h"
#include "pipeline/run_outputs.h"

namespace xsect {

using json = nlohmann::ordered_json;

namespace {

double secondsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

/// R'' on the scene's planes and arrangement; InputError naming reconstruction.method when it has
/// no tetrahedron.
DelaunayReconstruction prunedDelaunay(const RunInputs& in, const SceneStage& built, const ArrangeStage& a,
                                      Progress& progress) {
  const RunConfig& c = in.config;
  DelaunayReconstruction d = delaunayReconstruction(built.scene.planes, a.arrangement, a.branching,
                                                    progress.counter(), &a.graphs.g_double_prime, c.cell_tunnels);
  if (d.tetrahedra.empty())
    throw InputError(c.path, "reconstruction.method",
                     built.counts.planes_with_sections <= 1
                         ? "method 3 (delaunay) joins sections of different planes, and only one plane holds "
                           "sections: use nearest_plane or section_voronoi"
                         : "method 3 (delaunay) kept no tetrahedron: no two planes' sections face each other in a "
                           "cell of the arrangement (every tetrahedron was external); use nearest_plane or "
                           "section_voronoi");
  return d;
}

/// The mesh is ∂R'' itself, so it must be closed and have one outer surface per component of the
/// union of the tetrahedra it bounds (issue 14, as requireMeshBoundsSolid); where it opened
/// pinches, each vertex copy may split one more piece off (tetrahedra_components.h).
void requireMeshBoundsTetrahedra(const MeshTopology& mesh, int components, std::int64_t copies,
                                 const std::string& what) {
  if (components == 0 || mesh.betti[0] == 0)
    throw std::runtime_error(what + " is empty although the sections are not (method 3's tetrahedra form " +
                             std::to_string(components) + " components): nothing written");
  if (mesh.watertight && mesh.betti[0] >= components && mesh.betti[0] <= components + copies) return;
  throw std::runtime_error(what + " has " + std::to_string(mesh.betti[0]) + " outer surfaces" +
                           (mesh.watertight ? "" : " and is not watertight") +
                           " while the union of method 3's tetrahedra it bounds has " + std::to_string(components) +
                           " components" +
                           (copies > 0 ? " (" + std::to_string(copies) + " vertex copies at opened pinches allow up to " +
                                             std::to_string(components + copies) + ")"
                                       : std::string()) +
                           "; nothing written (a defect of xsect: please report it with the configuration)");
}

/// The pruning's counts (thesis ch. 3, Def. 47-50), as DelaunayStats has them.
json delaunayStatsJson(const DelaunayStats& s) {
  return {{"cells", s.cells},
          {"section_vertices", s.section_vertices},
          {"branching_points", s.branching_points},
          {"conformity_points", s.conformity_points},
          {"contour_edges_not_delaunay", s.contour_edges_not_delaunay},
          {"d0", {{"vf", s.d0.vf}, {"ee", s.d0.ee}, {"evv", s.d0.evv}, {"vvvv", s.d0.vvvv}, {"flat", s.d0.flat}}},
          {"external", s.external},
          {"unjoined", s.unjoined},
          {"d1", s.d1},
          {"d2", s.d2},
          {"d3", s.d3},
          {"flat_faces", s.flat_faces},
          {"constraint_crossings", s.constraint_crossings},
          {"singular_edges", s.singular_edges},
          {"singular_vertices", s.singular_vertices},
          {"open_edges", s.open_edges},
          {"welded_vertices", s.welded_vertices},
          {"holes_closed", s.holes_closed},
          {"flat_shells_dropped", s.flat_shells_dropped},
          {"cells_unseen", s.cells_unseen},
          {"rings_below_spacing_dropped", s.rings_dropped},
          {"cell_pairs_cut", s.cell_pairs_cut},
          {"cell_tunnels_cut", s.cell_tunnels_cut},
          {"cell_tetrahedra_cut", s.cell_tetrahedra_cut}};
}

/// report.json `reconstruction.delaunay`: the pruning's counts, the solid's components and Betti
/// numbers (mesh and voxels), and the connections R'' realises against G'' and G'.
json delaunayJson(const RunResults& r) {
  const ReconstructStage& rs = r.reconstruction;
  const DelaunayStage& m3 = *rs.delaunay;
  const DelaunayReconstruction& d = m3.result;
  const ArrangeStage& a = r.arrangement;
  const Betti& mesh = r.diagnosis.method_topology.betti;
  json j = delaunayStatsJson(d.stats);
  j.update(json{{"mesh_source", m3.mesh_from_voxels ? "voxels" : "boundary"},
                {"tetrahedra", d.tetrahedra.size()},
                {"tetrahedra_components", m3.components},
                {"opened_vertex_copies", m3.opened_copies},
                {"mesh_betti", mesh},
                {"mesh_triangles", r.smooth ? r.meshes.method_mesh.triangles.size() : r.meshes.mesh.triangles.size()},
                {"voxel_betti", rs.solid.voxel_betti},
                {"voxel_betti_matches_mesh", rs.solid.voxel_betti == mesh},
                // One solid (issue 49): the rule whose voxels have the boundary's Betti numbers
                {"voxel_rule", m3.voxels.rule == VoxelRule::cube ? "cube" : "centre"},
                {"voxel_mm", rs.solid.inside.grid().voxel},  // the scene's, halved `refinement` times
                {"voxel_refinement", m3.voxels.refinement},
                {"boundary_betti", d.stats.open_edges > 0 ? json(nullptr) : json(m3.boundary_betti)},
                // mesh_source voxels: the mesh bounds the voxelisation made well-composed
                {"mesh_voxel_betti", m3.mesh_from_voxels ? json(rs.solid.voxel_betti) : json(nullptr)},
                {"mesh_voxels_added", m3.voxels_added_well_composed},
                {"connections", d.connections.size()},
                {"connections_not_in_g_double_prime", m3.connections_not_in_graph},
                {"g_double_prime_edges_not_realised", m3.graph_edges_not_realised},
                {"edges_g_double_prime", a.graphs.g_double_prime.size()},
                {"g_not_in_g_prime", a.g_not_in_g_prime},
                {"g_prime_not_in_g_double_prime", a.g_prime_not_in_g_double_prime},
                {"branching_diagram", {{"points", a.branching.size()},
                                       {"rays", a.branching_rays},
                                       {"rays_labelled", a.branching_labelled}}}});
  return j;
}

}  // namespace

void DelaunayMethod::requireArrangement(const RunConfig& c, const SectionArrangement& arrangement) const {
  if (arrangement.pencil_crossings == 0) return;
  // Method 3 glues cells along sub-sections whose corners lie on two planes at a time (general
  // position, ch. 3 §2.4); where three planes of a pencil meet on a contour, the cells around
  // the common line are decided by rounding (the fan of configs/phantoms/ellipsoid-fan.yaml
  // made 614 cells and an open mesh). Methods 1 and 2 need no such position.
  std::array<int, 3> p = arrangement.pencil_planes;
  std::sort(p.begin(), p.end());
  throw InputError(c.path, "reconstruction.method",
                   "delaunay (method 3) needs planes in general position along the sections, but " +
                       std::to_string(arrangement.pencil_crossings) +
                       " contour crossings lie on three or more planes through one line (a fan of planes; "
                       "e.g. planes " + std::to_string(p[0]) + ", " + std::to_string(p[1]) + " and " +
                       std::to_string(p[2]) + "): use nearest_plane or section_voronoi for these slices");
}

ReconstructStage DelaunayMethod::reconstruct(const RunInputs& in, const SceneStage& built, const ArrangeStage& a,
                                             Progress& progress) const {
  const RunConfig& c = in.config;
  const SectionScene& scene = built.scene;
  ReconstructStage r;
  DelaunayStage& m3 = r.delaunay.emplace();
  const auto t0 = std::chrono::steady_clock::now();
  m3.result = prunedDelaunay(in, built, a, progress);
  m3.delaunay_s = secondsSince(t0);
  const DelaunayReconstruction& d = m3.result;
  float band = 0;
  for (const auto& f : scene.fields) band = std::max(band, f.band);
  if (!(band > 0)) band = float(scene.params.band_voxels * scene.params.voxel_mm);
  // The checks' numbers beside the voxelisation (both read the tetrahedra only).
  tbb::parallel_invoke(
      [&] {
        // What the mesh's b0 is checked against (requireMeshBoundsTetrahedra; tetrahedra_components.h).
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
  return r;
}

MethodMesh DelaunayMethod::mesh(const RunConfig& c, const SectionScene& scene, const ReconstructStage& solid,
                                bool smoothed) const {
  const DelaunayStage& m3 = *solid.delaunay;
  const SampledReconstruction& rec = solid.solid;
  MethodMesh m;
  if (!m3.mesh_from_voxels) {
    m.mesh = m3.result.mesh;  // ∂R'': conformal by construction, no cut
    m.conformal_by_construction = true;
    // Pieces touching at a vertex are kept apart by copies of the vertex at one position: STL
    // stores no vertex indices, so a reader merges them back into a pinched surface.
    const bool stl = std::find(c.mesh_formats.begin(), c.mesh_formats.end(), "stl") != c.mesh_formats.end();
    if (stl && !smoothed && m3.result.stats.singular_vertices > 0)
      m.warnings.push_back(std::to_string(m3.result.stats.singular_vertices) +
                           " vertices of method 3's mesh are copied where pieces touch at a point; mesh.stl keeps no "
                           "vertex indices, so readers merge the copies (the surface is then pinched there): use "
                           "mesh.ply or mesh.obj for the Betti numbers report.json states");
    return m;
  }
  // ∂R'' with open edges: its gluing failed on some plane (the jittered torus with enforced
  // conformity, seed 2: five edges where faces of two cells nearly parallel to a plane meet it).
  // R'' itself, the union of its tetrahedra, is whole: its voxelisation is meshed instead. Or the
  // grid holds no voxel set with its topology: the solid is then the voxels, made well-composed,
  // and the mesh is theirs (one solid, issue 49).
  const double voxel = rec.inside.grid().voxel;  // the scene's, or refined (tetrahedra_voxels.h)
  m.mesh = meshZeroLevel(rec.field);
  if (c.conformal_mesh) m.cut = cutAlongSections(m.mesh, scene.planes, scene.fields, voxel);
  const std::string what = (smoothed ? "the unsmoothed mesh" : "the mesh") + std::string(" is the voxelisation of R'' at ") +
                           std::to_string(voxel) + " mm made well-composed, not its boundary through the "
                           "contours (report.json reconstruction.delaunay.mesh_source: voxels, mesh_voxel_betti)";
  if (m3.result.stats.open_edges > 0)
    m.warnings.push_back("method 3's boundary could not be glued closed (" +
                         std::to_string(m3.result.stats.open_edges) + " open edges): " + what);
  else
    m.warnings.push_back("R'' is thinner than the voxel in places: its boundary has Betti numbers " +
                         bettiText(m3.boundary_betti) + " but no voxel set on this grid (by centres or by "
                         "cubes) has them; so that the mesh, labels.nrrd and report.json describe one solid, " + what +
                         "; a smaller reconstruction.voxel_size_mm may hold the boundary's topology");
  return m;
}

void DelaunayMethod::requireMeshBoundsSolid(const MeshTopology& mesh, const ReconstructStage& solid,
                                            const std::string& what) const {
  const DelaunayStage& m3 = *solid.delaunay;
  const Betti& voxels = solid.solid.voxel_betti;
  if (m3.mesh_from_voxels) return xsect::requireMeshBoundsSolid(mesh, voxels, what);
  requireMeshBoundsTetrahedra(mesh, m3.components, m3.opened_copies, what);
  // ∂R'' and its voxels: one solid by construction (reconstruct), checked.
  if (mesh.betti != voxels)
    throw std::runtime_error("method 3's mesh has Betti numbers " + bettiText(mesh.betti) + " while its voxels have " +
                             bettiText(voxels) +
                             "; nothing written (a defect of xsect: please report it with the configuration)");
}

const std::vector<GraphEdge>* DelaunayMethod::joinsRealised(const ReconstructStage& solid) const {
  return &solid.delaunay->result.connections;  // the pairs joined by a tetrahedron of R''
}

void DelaunayMethod::addToReport(const RunResults& r, json& report) const {
  const DelaunayStage& m3 = *r.reconstruction.delaunay;
  report["reconstruction"]["delaunay"] = delaunayJson(r);
  // Without smoothing the mesh is ∂R'', conformal to the contours by construction: no cut applies
  // (its counts are zero).
  report["conformity"]["conformal_by_construction"] = r.meshes.conformal_by_construction;
  json& t = report["throughput"];
  t["method3_evaluate_s"] = r.reconstruction.solid.evaluate_seconds;
  t["method3_delaunay_s"] = m3.delaunay_s;
  t["method3_voxelise_s"] = m3.voxelise_s;
}

}  // namespace xsect

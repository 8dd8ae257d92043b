// report.json of `xsect run` (docs/outputs.md): the topology of the result, the counts,
// each stage's parameters and measurements, timings, peak memory and the warnings.
#include <algorithm>
#include <cmath>

#include "pipeline/json_values.h"
#include "pipeline/plus_summary.h"
#include "pipeline/run_outputs.h"
#include "report/run/verdict_sentence.h"

namespace xsect {

using json = nlohmann::ordered_json;

namespace {

/// A solid's connectivity against the graph, cell by cell.
json cellsJson(const CellConnectivityCheck& c) {
  return {{"cells_compared", c.cells_compared},
          {"cells_unresolved", c.cells_unresolved},
          {"cells_differing", c.cells_differing},
          {"pairs_joined_by_graph_only", c.pairs_joined_by_graph_only},
          {"pairs_joined_by_solid_only", c.pairs_joined_by_voxels_only},
          {"differing_cells", c.differing_cells}};
}

/// A surface's connectivity against the method's graph, globally and cell by cell.
json surfaceCheckJson(const GraphVoxelCheck& g, const CellConnectivityCheck& cells) {
  return json{{"same_partition_as_graph", g.same_partition},
              {"components", g.voxel_components},
              {"pairs_joined_by_graph_only", g.pairs_joined_by_graph_only},
              {"pairs_joined_by_surface_only", g.pairs_joined_by_voxels_only},
              {"sections_not_located", g.sections_unlocated},
              {"per_cell", cellsJson(cells)}};
}

json refinedCellsJson(const std::vector<CellRefinement>& cells) {
  json out = json::array();
  for (const CellRefinement& r : cells)
    out.push_back({{"cell", r.cell},
                   {"pairs_differing", r.pairs},
                   {"method_pairs_differing", r.reference_pairs},
                   {"refinement", r.factor},
                   {"lattice_dims", r.dims},
                   {"refined_pairs_differing", r.refined_pairs},
                   {"solid_leaves_box", r.leaves_box},
                   {"accepted", r.accepted}});
  return out;
}

/// The segmentation as applied: the method and preset asked for, the threshold and inside side
/// every frame got (Otsu's and auto resolved for the series), the shadows' rule, and the core's
/// level when the minimum-error rule set one (SegmentationParams::core_threshold), and what the
/// elevation median changed when it ran (segmentation/elevation_median.h).
json segmentationJson(const RunConfig& c, const SegmentationParams& applied, const ElevationMedian& median) {
  json s = {{"method", nameOf(kSegmentationMethods, c.segmentation.method)},
            {"preset", nameOf(kSegmentationPresets, c.segmentation_preset)},
            {"threshold_used", applied.threshold}};
  if (c.segmentation.method != SegmentationMethod::labels) {
    s["inside"] = nameOf(kInsideSides, c.segmentation.inside);
    s["inside_used"] = nameOf(kInsideSides, applied.inside);
    s["shadows"] = nameOf(kShadowRules, c.segmentation.shadows);
  }
  if (!std::isnan(applied.core_threshold)) s["core_threshold_used"] = applied.core_threshold;
  if (applied.elevation_median_mm > 0)
    s["elevation_median"] = {{"max_mm", applied.elevation_median_mm},
                             {"frames_changed", median.frames_changed},
                             {"area_removed_mm2", median.area_removed_mm2},
                             {"area_added_mm2", median.area_added_mm2}};
  return s;
}

json countsJson(const RunResults& r) {
  const SampledReconstruction& rec = r.reconstruction.solid;
  const SectionArrangement& a = r.arrangement.arrangement;
  return {{"slices", r.inputs.slices}, {"slices_used", r.inputs.planes.size()},
          {"planes_with_sections", r.scene_stage.counts.planes_with_sections},
          {"sections", r.scene_stage.counts.sections}, {"end_planes", r.scene_stage.scene.end_planes()},
          {"cells", a.cells}, {"sub_sections", a.sub_sections.size()},
          {"voxels", rec.field.grid().count()},
          {"voxels_inside", rec.voxels_inside},
          {"mesh_vertices", r.meshes.mesh.vertices.size()},
          {"mesh_triangles", r.meshes.mesh.triangles.size()}};
}

json reconstructionJson(const RunResults& r) {
  const SampledReconstruction& rec = r.reconstruction.solid;
  const ReconstructionLayout& layout = r.scene_stage.scene.layout;
  const RunConfig& c = r.inputs.config;
  json j = {{"method", nameOf(kReconstructionMethods, r.method.id())},
          {"planes", nameOf(kPlaneExtents, c.planes)},
          {"planes_auto", c.planes_default},
          {"cell_tunnels", nameOf(kCellTunnels, c.cell_tunnels)},
          {"voxel_size_mm", r.scene_stage.scene.params.voxel_mm},
          {"voxel_size", voxelSizeJson(r.scene_stage.voxel_size)},
          {"grid_origin_mm", vecJson(rec.field.grid().origin)},
          {"grid_dims", rec.field.grid().dims},
          {"end_margin_mm", layout.end_margin_mm},
          {"end_margin_auto", layout.end_margin_auto},
          {"max_lift_mm", rec.max_lift_mm},
          {"storage", {{"blocks", rec.storage.blocks},
                       {"boundary_blocks", rec.storage.field_leaves},
                       {"solid_blocks", rec.storage.section_leaves},
                       {"inside_leaves", rec.storage.inside_leaves},
                       {"anchor_leaves", rec.storage.anchor_leaves}}},
          {"exact_face_tests", rec.exact_face_tests},
          {"cells_clipped", rec.cells_clipped},
          {"volume_mm3", r.diagnosis.topology.volume_mm3}};
  return j;  // the method adds its own keys (Method::addToReport)
}

json materialsJson(const RunResults& r) {
  json mats = json::array();
  for (std::size_t k = 0; k < r.meshes.materials.size(); ++k) {
    const Material& m = r.meshes.materials[k];
    const MeshTopology& t = r.diagnosis.material_topology[k];
    mats.push_back({{"label", m.label}, {"betti", t.betti}, {"voxel_betti", m.voxel_betti},
                    {"watertight", t.watertight}, {"voxels", m.voxels}, {"volume_mm3", t.volume_mm3},
                    {"mesh_triangles", m.mesh.triangles.size()}});
  }
  return mats;
}

json graphSummaryJson(const RunResults& r) {
  const ArrangeStage& a = r.arrangement;
  const GraphVoxelCheck& g = r.reconstruction.graph_check;
  json j = {{"edges_g", a.graphs.g.size()},
          {"edges_g_prime", a.with_g_prime ? json(a.graphs.g_prime.size()) : json(nullptr)},
          {"g_subset_of_g_prime", a.with_g_prime ? json(a.g_in_g_prime) : json(nullptr)},
          {"components", g.graph_components},
          {"voxel_components_with_sections", g.voxel_components},
          {"same_partition_as_voxels", g.same_partition},
          {"pairs_joined_by_graph_only", g.pairs_joined_by_graph_only},
          {"pairs_joined_by_voxels_only", g.pairs_joined_by_voxels_only},
          {"sections_not_located", g.sections_unlocated},
          {"per_cell", cellsJson(r.reconstruction.cell_check)}};
  // Observed pieces: cells that lifts join through unobserved parts of faces are not compared.
  j["per_cell"]["cells_left_through_unobserved_faces"] = a.graphs.cells_left_through_unobserved.size();
  if (a.with_g_double_prime) {  // method 3: its graph is G'' (the voxel checks above are against it)
    j["edges_g_double_prime"] = a.graphs.g_double_prime.size();
    j["g_prime_subset_of_g_double_prime"] = a.g_prime_not_in_g_double_prime == 0;
    j["g_not_in_g_prime"] = a.g_not_in_g_prime;
    j["g_prime_not_in_g_double_prime"] = a.g_prime_not_in_g_double_prime;
  }
  return j;
}

json smoothingJson(const RunResults& r) {
  const SmoothStage& s = *r.smooth;
  const RunConfig& c = r.inputs.config;
  const MeshTopology& mt = r.diagnosis.method_topology;
  const bool shepard = c.smoothing_method == SmoothingMethod::shepard;
  const ContourPinning& pin = s.pinning;
  return {{"method", nameOf(kSmoothingMethods, c.smoothing_method)},
          {"surface_from", nameOf(kSmoothingMethods, s.method)},
          {"voxels_decided_by_observed_pieces", s.voxels_decided_by_pieces},
          {"exponent", std::isinf(s.exponent) ? json("inf") : json(s.exponent)},
          {"cap_mm", s.cap_mm},
          {"cap_auto", s.cap_auto},
          {"empty_plane_value_mm", s.empty_value_mm},
          {"adaptivity", c.smoothing_adaptivity},
          {"grid_dims", s.field.grid.dims},
          {"grid_origin_mm", vecJson(s.field.grid.origin)},
          {"evaluate_s", s.evaluate_s},
          {"voxels_per_s", s.evaluate_s > 0 ? double(s.field.grid.count()) / s.evaluate_s : 0.0},
          {"mean_visible_planes", s.mean_visible_planes},
          {"max_visible_planes", s.max_visible_planes},
          {"end_plane_weights", shepard ? json(s.end_plane_weights) : json(nullptr)},
          {"contour_pinning", shepard ? json{{"samples", pin.samples},
                                             {"samples_pinned", pin.samples_pinned},
                                             {"samples_outside", pin.samples_outside},
                                             {"samples_crowded", pin.samples_crowded},
                                             {"voxels_pinned", pin.voxels_pinned},
                                             {"worst_before_mm", pin.worst_before_mm}}
                                      : json(nullptr)},
          {"voxel_betti", s.voxel_betti},
          {"repair", {{"specks_removed", s.repair.specks_removed},
                      {"cavities_filled", s.repair.cavities_filled},
                      {"critical_voxels_added", s.repair.critical_voxels_added}}},
          {"adaptivity_dropped", s.adaptivity_dropped},
          {"level_set_active_voxels", s.surface.level_set.coords.size()},
          {"level_set_half_width_mm", s.surface.level_set.background},
          {"shepard_connectivity", shepard ? surfaceCheckJson(s.shepard_check, s.shepard_cells) : json(nullptr)},
          {"shepard_refined_cells", shepard ? refinedCellsJson(s.refined_cells) : json(nullptr)},
          {"shepard_keeps_connectivity", shepard ? json(s.shepard_keeps_connectivity) : json(nullptr)},
          {"fell_back_to_level_set", s.fell_back},
          {"level_set_iterations", s.iterations_applied},
          {"connectivity", surfaceCheckJson(s.final_check, s.final_cells)},
          {"unsmoothed", {{"betti", mt.betti}, {"watertight", mt.watertight},
                          {"volume_mm3", mt.volume_mm3},
                          {"mesh_triangles", r.meshes.method_mesh.triangles.size()}}}};
}

/// report.json `topology` (reconstruction.topology other than free, issue 51): the goal, the Betti
/// numbers before and after, and each change of a cell (a join cut or added: its sections as
/// graph.json numbers them, its cell, where, its size).
/// A feature's own level from its size (half the thickness of a handle or the radius of a hole,
/// topology_features.h): what the probes of topology_confidence.h would say of it alone (an opening
/// or closing by a ball of radius r unmakes features under r).
const char* featureLevel(double size_mm, const TopologyConfidence& c) {
  return nameOf(kConfidenceLevels, size_mm < c.voxel_mm                                   ? ConfidenceLevel::low
                                   : size_mm < c.probes[1].radius_voxels * c.voxel_mm ? ConfidenceLevel::medium
                                                                                          : ConfidenceLevel::high);
}

/// topology.confidence (issue 52): the level, its sentence, the probes and the kinds in doubt.
json confidenceJson(const TopologyConfidence& c) {
  json probes = json::array(), kinds = json::array();
  for (const TopologyProbe& p : c.probes) {
    const bool probed = &p == &c.probes[0] || c.scale_probed;
    probes.push_back({{"radius_voxels", p.radius_voxels},
                      {"radius_mm", p.radius_voxels * c.voxel_mm},
                      {"scale", &p == &c.probes[0] ? "one voxel" : "half the largest cell height (at least 2 voxels)"},
                      {"betti_closed", probed ? json(p.closed) : json(nullptr)},
                      {"betti_opened", probed ? json(p.opened) : json(nullptr)}});
  }
  for (const FeatureDoubt& f : c.kinds)
    kinds.push_back({{"kind", f.kind},
                     {"count", f.count},
                     {"in_doubt_at_1_voxel", f.in_doubt_1},
                     {"in_doubt_at_data_scale", c.scale_probed ? json(f.in_doubt_2) : json(nullptr)},
                     {"level", nameOf(kConfidenceLevels, f.level)}});
  return {{"level", nameOf(kConfidenceLevels, c.level)},
          {"text", confidenceText(c)},
          {"probes", probes},
          {"kinds", kinds},
          {"voxels_probed", c.voxels}};
}

json topologyJson(const RunResults& r) {
  const TopologyControl& t = *r.reconstruction.topology;
  const TopologyGoal& goal = r.inputs.config.topology;
  json changes = json::array();
  std::vector<int> cells;
  for (const CellChange& c : t.changes) {
    changes.push_back({{"change", nameOf(kCellChangeKinds, c.kind)},
                       {"sections", c.sections},
                       {"cell", c.cell},
                       {"at_mm", vecJson(c.at)},
                       {"voxels", c.voxels},
                       {"width_mm", c.width_mm},
                       {"betti_after", c.after}});
    cells.push_back(c.cell);
  }
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  json features = json::array();
  for (const TopologyFeature& f : t.features)
    features.push_back({{"kind", f.dimension == 1 ? "tunnel" : "cavity"},
                        {"size_mm", f.size_mm},
                        {"birth_mm", f.birth_mm},
                        {"death_mm", std::isfinite(f.death_mm) ? json(f.death_mm) : json(nullptr)},
                        {"born_at_mm", vecJson(f.born_at)},
                        {"dies_at_mm", vecJson(f.dies_at)},
                        {"cells", f.born_in_cell == f.dies_in_cell ? json({f.born_in_cell})
                                                                   : json({f.born_in_cell, f.dies_in_cell})},
                        {"confidence", featureLevel(f.size_mm, r.confidence.confidence)}});
  return {{"mode", goal.mode == TopologyMode::target ? "target" : nameOf(kTopologyModes, goal.mode)},
          {"target", goal.mode == TopologyMode::target ? json(goal.target) : json(nullptr)},
          {"min_feature_mm", goal.mode == TopologyMode::simplest ? json(goal.min_feature_mm) : json(nullptr)},
          {"betti_before", t.before},
          {"betti_after", t.after},
          {"reached", t.reached},
          {"joins", t.joins},
          {"joins_forced", t.joins_forced},
          {"joins_possible", t.joins_possible},
          {"mends_possible", t.mends_possible},
          {"changes_tried", t.evaluated},
          {"changes", changes},
          {"cells_changed", cells},
          {"features", t.features_computed ? features : json(nullptr)},
          {"features_voxels", t.features_voxels},
          {"search_s", t.seconds}};
}

json conformityJson(const RunResults& r) {
  const ConformalCutStats& cut = r.meshes.cut;
  json j = conformitySummaryJson(r.inputs.config.conformity, r.inputs.conformity);
  j.update(json{{"conformal_mesh", r.inputs.config.conformal_mesh},
                {"planes_cut", cut.planes_cut},
                {"cut_vertices", cut.vertices_added},
                {"cut_vertices_on_contour", cut.vertices_snapped},
                {"cut_vertices_short_of_contour", cut.vertices_shortened},
                {"cut_vertices_off_contour", cut.vertices_unsnapped},
                {"cut_max_move_mm", cut.max_move_mm}});
  return j;
}

json throughputJson(const RunResults& r) {
  const SampledReconstruction& rec = r.reconstruction.solid;
  // Each method's own times, filled by the method that ran (Method::addToReport).
  return {{"reconstruct_voxels_per_s", rec.evaluate_seconds > 0 ? double(rec.field.grid().count()) / rec.evaluate_seconds : 0.0},
          {"evaluate_s", rec.evaluate_seconds},
          {"method1_evaluate_s", nullptr},
          {"method2_evaluate_s", nullptr},
          {"method3_evaluate_s", nullptr},
          {"method3_delaunay_s", nullptr},
          {"method3_voxelise_s", nullptr}};
}

}  // namespace

json reportJson(const RunResults& r, const StageClock& clock) {
  const RunConfig& c = r.inputs.config;
  const SampledReconstruction& rec = r.reconstruction.solid;
  const SectionArrangement& a = r.arrangement.arrangement;
  json report;
  report["xsect_version"] = XSECT_VERSION;
  report["betti"] = r.diagnosis.topology.betti;
  // The solid labels.nrrd holds: the smooth one with smoothing (one solid with mesh.*, issue 49).
  report["voxel_betti"] = r.smooth ? r.smooth->voxel_betti : rec.voxel_betti;
  report["watertight"] = r.diagnosis.topology.watertight;
  report["counts"] = countsJson(r);
  if (c.input_kind == InputKind::slices || c.input_kind == InputKind::plus_sequence)
    report["segmentation"] = segmentationJson(c, r.inputs.segmentation, r.inputs.elevation_median);
  if (r.inputs.plus) report["plus_sequence"] = plusSequenceJson(*r.inputs.plus);
  report["reconstruction"] = reconstructionJson(r);
  report["materials"] = materialsJson(r);
  // Several materials: the voxels whose label changed so that every label is well-composed
  // (well_composed_labels.h); labels.nrrd holds the changed labels.
  if (!r.meshes.materials.empty())
    report["label_composition"] = {{"voxels_relabelled", r.meshes.label_composition.voxels_relabelled},
                                   {"voxels_added", r.meshes.label_composition.voxels_added}};
  report["arrangement"] = {{"cells", a.cells},
                           {"sub_sections", a.sub_sections.size()},
                           {"trace_points_added", a.trace_points},
                           {"sample_spacing_mm", a.sample_spacing_mm}};
  report["graph"] = graphSummaryJson(r);
  // topology: the confidence for every run (issue 52); the mode and what topology control changed.
  report["topology"] = r.reconstruction.topology ? topologyJson(r) : json{{"mode", "free"}};
  report["topology"]["confidence"] = confidenceJson(r.confidence.confidence);
  if (r.smooth) report["smoothing"] = smoothingJson(r);
  report["topology_repair"] = {{"specks_removed", rec.repair.specks_removed},
                               {"cavities_filled", rec.repair.cavities_filled},
                               {"critical_voxels_added", rec.repair.critical_voxels_added}};
  report["conformity"] = conformityJson(r);
  report["sampling"] = samplingSummaryJson(r.sampling);
  report["timings_s"] = clock.timings;
  report["timings_s"]["total"] = clock.total();
  report["peak_memory_mb"] = clock.memory;
  report["throughput"] = throughputJson(r);
  report["warnings"] = runWarnings(r);
  r.method.addToReport(r, report);
  // What the sampling verdict and the topology confidence mean for this result, in one sentence
  // (the run's last lines and report.html's headline say the same).
  report["in_plain_words"] = verdictSentence(report);
  return report;
}

}  // namespace xsect

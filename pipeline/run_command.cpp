// `xsect run` and `xsect check`: the stages of GUIDE.md wired together, timed, reported.
// load -> segment -> conform -> reconstruct (method 1) -> mesh -> diagnose -> write.
#include <sys/resource.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "geometry/arrangement/cell_connectivity_check.h"
#include "geometry/meshing/conformal_cut.h"
#include "pipeline/smooth_stage.h"
#include "io/level_set_file.h"
#include "geometry/arrangement/connectivity_graph.h"
#include "geometry/core/digital_topology.h"
#include "geometry/meshing/mesh_topology.h"
#include "geometry/core/polygon.h"
#include "geometry/reconstruction/sampled_reconstruction.h"
#include "geometry/arrangement/section_arrangement.h"
#include "geometry/meshing/volume_mesher.h"
#include "geometry/reconstruction/voxel_labels.h"
#include "io/csl_file.h"
#include "io/file_hash.h"
#include "io/input_error.h"
#include "io/text_file.h"
#include "io/label_volume_file.h"
#include "io/mesh_io.h"
#include "io/run_config.h"
#include "io/slices_file.h"
#include "io/staged_output.h"
#include "pipeline/commands.h"
#include "pipeline/conform_stage.h"
#include "pipeline/library_versions.h"
#include "pipeline/load_sections.h"
#include "pipeline/machine_memory.h"
#include "pipeline/progress.h"
#include "pipeline/voxel_size_choice.h"

namespace xsect {
namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace {

double peakMemoryMb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_maxrss) / 1024.0;
}

class StageClock {
 public:
  void end(const std::string& stage) {
    const auto now = std::chrono::steady_clock::now();
    timings[stage] = std::chrono::duration<double>(now - last_).count();
    memory[stage] = peakMemoryMb();
    last_ = now;
  }
  json timings = json::object(), memory = json::object();

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

struct Inputs {
  RunConfig config;
  std::vector<CuttingPlane> planes;
  std::vector<std::string> input_files;  // hashed into the manifest
  std::vector<std::string> warnings;
  int slices = 0;
  double threshold = 0;  // grey threshold applied (slices input)
  std::vector<std::vector<Section>> labelled;  // segmentation labels: per plane, per label
  json conformity;          // stage 3's summary (report.json "conformity")
  json conformity_details;  // conformity.json
};

/// Stages load + segment + conform.
Inputs loadInputs(const RunOptions& o, StageClock& clock, Progress& progress) {
  Inputs in;
  progress.stage("load");
  in.config = readRunConfig(o.config, o.overrides);
  in.warnings = in.config.warnings;
  const RunConfig& c = in.config;
  in.input_files.push_back(c.path);
  in.input_files.push_back(c.input_path);
  std::vector<SliceRecord> slices;
  if (c.input_kind == InputKind::slices) {
    slices = mergeRepeatedSlices(readSlicesFile(c.input_path, &in.warnings), &in.warnings);
    for (const auto& s : slices) {
      in.input_files.push_back(s.image_resolved);
      if (s.fov_resolved) in.input_files.push_back(*s.fov_resolved);
    }
  } else if (c.input_kind == InputKind::csl) {
    in.planes = readCslFile(c.input_path, &in.warnings);
  } else {
    throw InputError(c.path, std::string("input.") + nameOf(kInputKinds, c.input_kind),
                     "this input kind is not available in this version (slices | csl)");
  }
  clock.end("load");
  progress.stage("segment");
  if (c.input_kind == InputKind::slices)
    in.planes = sectionsFromSlices(slices, c.input_path, c.segmentation, &in.warnings, &in.threshold,
                                   &in.labelled);
  in.slices = int(in.planes.size());
  clock.end("segment");
  progress.stage("conform");
  ConformStage conform = conformStage(c.conformity, std::move(in.planes), std::move(in.labelled));
  in.planes = std::move(conform.planes);
  in.labelled = std::move(conform.labelled);
  in.conformity = std::move(conform.summary);
  in.conformity_details = std::move(conform.details);
  in.warnings.insert(in.warnings.end(), conform.warnings.begin(), conform.warnings.end());
  clock.end("conform");
  progress.note(conform.stderr_summary);
  return in;
}

json vec(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

/// report.json: a solid's connectivity against the graph, cell by cell.
json cellsJson(const CellConnectivityCheck& c) {
  return {{"cells_compared", c.cells_compared},
          {"cells_unresolved", c.cells_unresolved},
          {"cells_differing", c.cells_differing},
          {"pairs_joined_by_graph_only", c.pairs_joined_by_graph_only},
          {"pairs_joined_by_solid_only", c.pairs_joined_by_voxels_only},
          {"differing_cells", c.differing_cells}};
}

/// The grid the reconstruction will use; configuration problems become InputError.
ReconstructionLayout layoutOf(const std::vector<CuttingPlane>& planes, const RunConfig& c) {
  try {
    return reconstructionLayout(planes, reconstructionParams(c));
  } catch (const std::invalid_argument& e) {
    throw InputError(c.path, "reconstruction.voxel_size_mm", e.what());
  }
}

/// Refuses, before allocating, a grid that would not fit in this machine's memory.
void checkMemory(const RunConfig& c, const ReconstructionLayout& L) {
  const double need = double(L.grid.count()) * kReconstructionBytesPerVoxel;
  const double have = physicalMemoryBytes();
  if (have > 0 && need > 0.8 * have)
    throw InputError(c.path, "reconstruction.voxel_size_mm",
                     "a grid of " + std::to_string(L.grid.count()) + " voxels needs about " +
                         std::to_string(int(need / 1e9)) + " GB, more than this machine has (" +
                         std::to_string(int(have / 1e9)) + " GB): increase the voxel size");
}

/// Resolves the voxel size (auto) and checks it against the sections' widths; a too coarse explicit
/// size is a warning printed even with --quiet.
VoxelSizeReport resolveVoxelSize(Inputs& in, bool quiet) {
  VoxelSizeReport r = chooseVoxelSize(in.config, in.planes);
  if (!r.warning.empty()) {
    in.warnings.insert(in.warnings.begin(), r.warning);
    std::cerr << "WARNING: " << r.warning << "\n";
  }
  if (!quiet && r.automatic)
    std::cerr << "voxel size " << r.voxel_mm << " mm (auto, limited by " << voxelSizeLimitName(r.choice.limited_by)
              << "; " << r.choice.voxels << " voxels)\n";
  return r;
}

json voxelSizeJson(const VoxelSizeReport& r) {
  return {{"voxel_size_mm", r.voxel_mm},
          {"auto", r.automatic},
          {"limited_by", r.automatic ? json(voxelSizeLimitName(r.choice.limited_by)) : json("configuration")},
          {"bounds_diagonal_mm", r.automatic ? json(r.choice.bounds_diagonal_mm) : json(nullptr)},
          {"median_pixel_mm", r.automatic ? json(r.choice.median_pixel_mm) : json(nullptr)},
          {"voxel_budget", r.automatic ? json(r.choice.voxel_budget) : json(nullptr)},
          {"median_section_width_mm", r.median_section_width_mm},
          {"min_section_width_mm", r.min_section_width_mm},
          {"sections_narrower_than_two_voxels", r.sections_narrower_than_two_voxels}};
}

/// The mesh written must bound the solid report.json describes (issue 14): a difference is a
/// defect of this program, an error (exit 1, nothing written), never a warning.
void requireMeshBoundsSolid(const MeshTopology& mesh, const Betti& solid, const std::string& what) {
  if (solid[0] == 0 || mesh.betti[0] == 0)
    throw std::runtime_error(what + " is empty although the sections are not (the solid has " +
                             std::to_string(solid[0]) + " components): nothing written");
  if (mesh.watertight && mesh.betti == solid) return;
  const auto betti = [](const Betti& b) {
    return "(" + std::to_string(b[0]) + ", " + std::to_string(b[1]) + ", " + std::to_string(b[2]) + ")";
  };
  throw std::runtime_error(what + " has Betti numbers " + betti(mesh.betti) +
                           (mesh.watertight ? "" : " and is not watertight") + " while the voxel solid it was made from has " +
                           betti(solid) + "; nothing written (a defect of xsect: please report it with the configuration)");
}

}  // namespace

int runCommand(const RunOptions& o) {
  Progress progress(o.quiet);
  StageClock clock;
  Inputs in = loadInputs(o, clock, progress);
  const RunConfig& c = in.config;
  const fs::path outDir = o.out.empty() ? fs::path(c.output_dir) : fs::absolute(o.out);

  int sections = 0, planesWithSections = 0;
  for (const auto& p : in.planes) {
    sections += int(p.sections.size());
    planesWithSections += !p.sections.empty();
  }
  if (sections == 0)
    throw InputError(c.input_path, "", "no section found in any slice (check segmentation settings)");
  const VoxelSizeReport voxelSize = resolveVoxelSize(in, o.quiet);

  progress.stage("reconstruct");
  const ReconstructionParams rp = reconstructionParams(c);
  checkMemory(c, layoutOf(in.planes, c));
  SampledReconstruction rec;
  try {
    rec = reconstructOnGrid(in.planes, rp, [&](double f) { progress.update(f); });
  } catch (const std::invalid_argument& e) {
    throw InputError(c.path, "reconstruction", e.what());
  }
  clock.end("reconstruct");
  if (rec.voxels_inside == 0) {
    // An automatic size the budget forced so coarse that nothing is left: the configuration must
    // change (exit 2); otherwise exit 1 with the size to use (issue 14).
    if (voxelSize.automatic && voxelSize.choice.limited_by == VoxelSizeLimit::voxel_budget)
      throw InputError(c.path, "reconstruction.voxel_budget", emptySolidMessage(voxelSize, sections));
    throw std::runtime_error(emptySolidMessage(voxelSize, sections));
  }
  in.warnings.push_back("open ends closed by 6 virtual empty planes at " +
                        std::to_string(rec.end_margin_mm) + " mm beyond the sections' bounds" +
                        (rec.end_margin_auto ? " (automatic margin)" : ""));
  if (planesWithSections == 1) {
    // One plane (a single slice, or every slice at one pose, merged in stage 3) says nothing about
    // the object across it: method 1 extends its section to the end planes on both sides.
    const auto holder = std::find_if(in.planes.begin(), in.planes.end(),
                                     [](const CuttingPlane& p) { return !p.sections.empty(); });
    in.warnings.push_back("only one plane holds sections (slice " + std::to_string(holder->slice) +
                          "): the shape across it is unknown, and the result is its sections extended " +
                          std::to_string(rec.end_margin_mm) + " mm to the end planes on each side");
  }

  // Stage 4 (arrange) and the connectivity graphs: they need the rasters and the end planes the
  // reconstruction made, so they run after it.
  progress.stage("arrange");
  std::vector<CuttingPlane> allPlanes = in.planes;
  allPlanes.insert(allPlanes.end(), rec.end_planes.begin(), rec.end_planes.end());
  const std::vector<SectionDistanceField>& allFields = rec.fields;  // real planes', then end planes'
  double sectionArea = 0;
  for (const auto& p : in.planes)
    for (const auto& s : p.sections) sectionArea += xsect::sectionArea(s);
  // Lattice of section points: the voxel size, coarser when it would exceed 250 000 points.
  const double spacing = std::max(c.voxel_size_mm, std::sqrt(sectionArea / 250000.0));
  const SectionArrangement arrangement = arrangeSections(allPlanes, spacing);
  SectionVoronoiParams vp;
  vp.slab_mm = rp.slab_voxels * rp.voxel_mm;
  const bool method2 = rp.method == ReconstructionMethod::section_voronoi;
  const ConnectivityGraphs graphs = connectivityGraphs(allPlanes, allFields, arrangement, vp, method2);
  const std::vector<GraphEdge>& methodEdges = method2 ? graphs.g_prime : graphs.g;
  const GraphVoxelCheck graphCheck =
      compareWithVoxels(methodEdges, in.planes, arrangement, rec.fields, rec.inside, rec.field.grid);
  // The same, cell by cell (thesis: R_C's components are the classes of S_C the lifts join).
  const CellConnectivityCheck cellCheck =
      compareCellsWithVoxels(methodEdges, allPlanes, arrangement, rec.fields, rec.inside, rec.field.grid);
  bool gInGPrime = true;
  for (const GraphEdge& e : graphs.g)
    gInGPrime = gInGPrime && std::binary_search(graphs.g_prime.begin(), graphs.g_prime.end(), e);
  if (!graphCheck.same_partition)
    in.warnings.push_back("the connectivity graph and the voxel solid group the sections differently (" +
                          std::to_string(graphCheck.pairs_joined_by_graph_only) + " pairs joined by the graph only, " +
                          std::to_string(graphCheck.pairs_joined_by_voxels_only) + " by the voxels only, " +
                          std::to_string(graphCheck.sections_unlocated) + " sections not located)");
  clock.end("arrange");

  // Stage 6: the smooth surface (optional).
  const bool smoothing = c.smoothing_method != SmoothingMethod::none;
  SmoothStage smooth;
  if (smoothing) {
    progress.stage("smooth");
    smooth = smoothStage(c, in.planes, rec, arrangement, methodEdges, graphCheck, cellCheck,
                         [&](double f) { progress.update(f); });
    if (c.smoothing_method == SmoothingMethod::shepard && !smooth.shepard_keeps_connectivity)
      in.warnings.push_back("Shepard's surface joins the sections differently from the method's graph (" +
                            std::to_string(smooth.shepard_check.pairs_joined_by_graph_only) +
                            " pairs joined by the graph only, " +
                            std::to_string(smooth.shepard_check.pairs_joined_by_voxels_only) +
                            " by the surface only" +
                            (smooth.shepard_check.same_partition
                                 ? "; " +
                                       std::to_string(std::count_if(
                                           smooth.refined_cells.begin(), smooth.refined_cells.end(),
                                           [](const CellRefinement& r) { return !r.accepted; })) +
                                       " cells where it differs from the graph more than the method's solid "
                                       "does, on the grid and on finer lattices)"
                                 : std::string(")")) +
                            (smooth.fell_back ? ": the surface written is the level-set smoothing of the "
                                                "method's solid, which keeps the method's connectivity"
                                              : ""));
    clock.end("smooth");
  }

  progress.stage("mesh");
  TriangleMesh methodMesh = meshZeroLevel(rec.field);
  const ConformalCutStats methodCut = c.conformal_mesh
                                          ? cutAlongSections(methodMesh, in.planes, rec.fields, c.voxel_size_mm)
                                          : ConformalCutStats{};
  TriangleMesh mesh = smoothing ? smooth.surface.mesh : methodMesh;
  const ConformalCutStats cutStats =
      !smoothing ? methodCut
                 : c.conformal_mesh ? cutAlongSections(mesh, in.planes, rec.fields, c.voxel_size_mm)
                                    : ConformalCutStats{};

  // Several materials: each voxel takes the label of the section its lift comes from; one mesh
  // per label (written when there are at least two) beside the union's.
  bool anyLabelled = false;  // segmentation labels gave per-label sections
  for (const auto& l : in.labelled) anyLabelled = anyLabelled || !l.empty();
  const std::vector<std::vector<Section>> ownSections;  // empty: the planes' own sections
  const auto& labelled = anyLabelled ? in.labelled : ownSections;
  const std::vector<std::uint16_t> voxelLabel =
      voxelLabels(rec.inside, rec.section_plane, in.planes, labelled, rec.field.grid);
  std::vector<std::uint16_t> labelValues;
  for (std::size_t p = 0; p < in.planes.size(); ++p)
    for (const auto& s : anyLabelled ? in.labelled[p] : in.planes[p].sections)
      labelValues.push_back(std::uint16_t(s.label));
  std::sort(labelValues.begin(), labelValues.end());
  labelValues.erase(std::unique(labelValues.begin(), labelValues.end()), labelValues.end());
  struct Material {
    std::uint16_t label;
    TriangleMesh mesh;
    std::int64_t voxels = 0;
    int critical_voxels_added = 0;
    Betti voxel_betti{0, 0, 0};
    MeshTopology topology;  ///< of `mesh`, computed once in the diagnose stage
  };
  std::vector<Material> materials;
  if (labelValues.size() >= 2)
    for (const std::uint16_t L : labelValues) {
      Material m;
      m.label = L;
      std::vector<std::uint8_t> in_L(voxelLabel.size());
      for (std::size_t q = 0; q < in_L.size(); ++q) {
        in_L[q] = voxelLabel[q] == L;
        m.voxels += in_L[q];
      }
      if (m.voxels == 0) {  // a label too small for the grid (a few pixels in one slice)
        in.warnings.push_back("label " + std::to_string(L) + " has sections but no voxel at " +
                              std::to_string(c.voxel_size_mm) + " mm: no mesh for it");
        continue;
      }
      // Well-composed, so that the mesh bounds the set voxelBetti counts: the mesh of a label
      // may take a voxel of a neighbouring label where the two meet at a vertex or an edge only
      // (counted in critical_voxels_added; labels.nrrd keeps each voxel's own label).
      m.critical_voxels_added = makeWellComposed(in_L, rec.field.grid);
      ScalarField f = labelField(rec.field, voxelLabel, L, float(0.05 * c.voxel_size_mm));
      imposeSolid(f, in_L, float(0.05 * c.voxel_size_mm));
      m.voxel_betti = voxelBetti(in_L, rec.field.grid);
      m.mesh = meshZeroLevel(f);
      materials.push_back(std::move(m));
    }
  if (labelValues.size() > 64)
    in.warnings.push_back(std::to_string(labelValues.size()) +
                          " materials (segmentation.method: labels takes every pixel value as a "
                          "label; is the image a grey image?)");
  clock.end("mesh");

  progress.stage("diagnose");
  const MeshTopology topo = meshTopology(mesh);
  const Betti smoothVoxelBetti = smoothing ? smooth.voxel_betti : Betti{0, 0, 0};
  requireMeshBoundsSolid(topo, smoothing ? smoothVoxelBetti : rec.voxel_betti,
                         smoothing ? std::string("the smoothed mesh (") + nameOf(kSmoothingMethods, smooth.method) + ")" : std::string("the mesh"));
  const MeshTopology methodTopo = smoothing ? meshTopology(methodMesh) : topo;
  if (smoothing) requireMeshBoundsSolid(methodTopo, rec.voxel_betti, "the unsmoothed mesh");
  for (Material& m : materials) {
    m.topology = meshTopology(m.mesh);
    requireMeshBoundsSolid(m.topology, m.voxel_betti, "the mesh of label " + std::to_string(m.label));
  }
  clock.end("diagnose");

  progress.stage("write");
  StagedOutput out(outDir);
  for (const auto& fmt : c.mesh_formats) writeMesh(out.file("mesh." + fmt).string(), mesh);
  if (smoothing) {
    for (const auto& fmt : c.mesh_formats)
      writeMesh(out.file("mesh_unsmoothed." + fmt).string(), methodMesh);
    writeLevelSetVdb(out.file("level_set.vdb").string(), smooth.surface.level_set);
  }
  for (const Material& m : materials)
    for (const auto& fmt : c.mesh_formats)
      writeMesh(out.file("mesh_label_" + std::to_string(m.label) + "." + fmt).string(), m.mesh);
  writeLabelVolumeNrrd(out.file("labels.nrrd").string(), rec.field.grid, voxelLabel);

  // graph.json and graph.dot: the sections (nodes) and the edges of G (method 1) and, for
  // method 2, G' (thesis Def. 30), each with the cell of the arrangement where the lifts meet.
  json nodes = json::array();
  std::vector<int> firstId(in.planes.size() + 1, 0);
  int id = 0;
  for (std::size_t pi = 0; pi < in.planes.size(); ++pi) {
    const auto& p = in.planes[pi];
    firstId[pi] = id;
    for (std::size_t s = 0; s < p.sections.size(); ++s) {
      const Section& sec = p.sections[s];
      nodes.push_back({{"id", id++}, {"slice", p.slice}, {"section", s}, {"label", sec.label},
                       {"area_mm2", xsect::sectionArea(sec)},
                       {"centroid_mm", vec(p.plane.toWorld(sectionCentroid(sec)))}});
    }
  }
  json edges = json::array();
  std::string dot = "graph sections {\n  node [shape=ellipse];\n";
  for (std::size_t pi = 0; pi < in.planes.size(); ++pi)
    for (std::size_t s = 0; s < in.planes[pi].sections.size(); ++s)
      dot += "  n" + std::to_string(firstId[pi] + int(s)) + " [label=\"" +
             std::to_string(in.planes[pi].slice) + ":" + std::to_string(s) + "\"];\n";
  const auto addEdges = [&](const std::vector<GraphEdge>& es, const char* method, const char* style) {
    for (const GraphEdge& e : es) {
      const int a = firstId[std::size_t(e.plane_a)] + e.section_a,
                b = firstId[std::size_t(e.plane_b)] + e.section_b;
      edges.push_back({{"a", a}, {"b", b}, {"cell", e.cell}, {"method", method}});
      dot += "  n" + std::to_string(a) + " -- n" + std::to_string(b) + " [" + style +
             ", tooltip=\"cell " + std::to_string(e.cell) + "\"];\n";
    }
  };
  addEdges(graphs.g, "nearest_plane", "style=dashed");
  if (method2) addEdges(graphs.g_prime, "section_voronoi", "style=solid");
  dot += "}\n";
  json graph = {{"method", nameOf(kReconstructionMethods, c.reconstruction_method)},
                {"cells", arrangement.cells},
                {"sample_spacing_mm", arrangement.sample_spacing_mm},
                {"nodes", nodes},
                {"edges", edges}};
  writeTextFile(out.file("graph.json").string(), graph.dump(2) + "\n");
  writeTextFile(out.file("graph.dot").string(), dot);
  writeTextFile(out.file("conformity.json").string(), in.conformity_details.dump(2) + "\n");

  const double total = [&] {
    double t = 0;
    for (auto& [k, v] : clock.timings.items()) t += v.get<double>();
    return t;
  }();
  json report;
  report["xsect_version"] = XSECT_VERSION;
  report["betti"] = topo.betti;
  report["voxel_betti"] = rec.voxel_betti;
  report["watertight"] = topo.watertight;
  report["counts"] = {{"slices", in.slices}, {"slices_used", in.planes.size()},
                      {"planes_with_sections", planesWithSections},
                      {"sections", sections}, {"end_planes", rec.end_planes.size()},
                      {"cells", arrangement.cells}, {"sub_sections", arrangement.sub_sections.size()},
                      {"voxels", rec.field.grid.count()},
                      {"voxels_inside", rec.voxels_inside},
                      {"mesh_vertices", mesh.vertices.size()},
                      {"mesh_triangles", mesh.triangles.size()}};
  if (c.input_kind == InputKind::slices)
    report["segmentation"] = {{"method", nameOf(kSegmentationMethods, c.segmentation.method)}, {"threshold_used", in.threshold}};
  report["reconstruction"] = {{"method", nameOf(kReconstructionMethods, c.reconstruction_method)},
                              {"voxel_size_mm", c.voxel_size_mm},
                              {"voxel_size", voxelSizeJson(voxelSize)},
                              {"grid_origin_mm", vec(rec.field.grid.origin)},
                              {"grid_dims", rec.field.grid.dims},
                              {"end_margin_mm", rec.end_margin_mm},
                              {"end_margin_auto", rec.end_margin_auto},
                              {"max_lift_mm", rec.max_lift_mm},
                              {"exact_face_tests", rec.exact_face_tests},
                              {"search_restarts", rec.search_restarts},
                              {"volume_mm3", topo.volume_mm3}};
  json mats = json::array();
  for (const Material& m : materials) {
    const MeshTopology& t = m.topology;
    mats.push_back({{"label", m.label}, {"betti", t.betti}, {"voxel_betti", m.voxel_betti},
                    {"watertight", t.watertight}, {"voxels", m.voxels},
                    {"critical_voxels_added", m.critical_voxels_added}, {"volume_mm3", t.volume_mm3},
                    {"mesh_triangles", m.mesh.triangles.size()}});
  }
  report["materials"] = mats;
  report["arrangement"] = {{"cells", arrangement.cells},
                           {"sub_sections", arrangement.sub_sections.size()},
                           {"trace_points_added", arrangement.trace_points},
                           {"sample_spacing_mm", arrangement.sample_spacing_mm}};
  report["graph"] = {{"edges_g", graphs.g.size()},
                     {"edges_g_prime", method2 ? json(graphs.g_prime.size()) : json(nullptr)},
                     {"g_subset_of_g_prime", method2 ? json(gInGPrime) : json(nullptr)},
                     {"components", graphCheck.graph_components},
                     {"voxel_components_with_sections", graphCheck.voxel_components},
                     {"same_partition_as_voxels", graphCheck.same_partition},
                     {"pairs_joined_by_graph_only", graphCheck.pairs_joined_by_graph_only},
                     {"pairs_joined_by_voxels_only", graphCheck.pairs_joined_by_voxels_only},
                     {"sections_not_located", graphCheck.sections_unlocated},
                     {"per_cell", cellsJson(cellCheck)}};
  if (smoothing) {
    const MeshTopology& mt = methodTopo;
    const bool shepard = c.smoothing_method == SmoothingMethod::shepard;
    const auto check = [](const GraphVoxelCheck& g, const CellConnectivityCheck& cells) {
      return json{{"same_partition_as_graph", g.same_partition},
                  {"components", g.voxel_components},
                  {"pairs_joined_by_graph_only", g.pairs_joined_by_graph_only},
                  {"pairs_joined_by_surface_only", g.pairs_joined_by_voxels_only},
                  {"sections_not_located", g.sections_unlocated},
                  {"per_cell", cellsJson(cells)}};
    };
    const auto refined = [](const std::vector<CellRefinement>& cells) {
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
    };
    report["smoothing"] = {{"method", nameOf(kSmoothingMethods, c.smoothing_method)},
                           {"surface_from", nameOf(kSmoothingMethods, smooth.method)},
                           {"exponent", std::isinf(smooth.exponent) ? json("inf") : json(smooth.exponent)},
                           {"cap_mm", smooth.cap_mm},
                           {"cap_auto", smooth.cap_auto},
                           {"empty_plane_value_mm", smooth.empty_value_mm},
                           {"adaptivity", c.smoothing_adaptivity},
                           {"grid_dims", smooth.field.grid.dims},
                           {"grid_origin_mm", vec(smooth.field.grid.origin)},
                           {"evaluate_s", smooth.evaluate_s},
                           {"voxels_per_s", smooth.evaluate_s > 0 ? double(smooth.field.grid.count()) / smooth.evaluate_s : 0.0},
                           {"mean_visible_planes", smooth.mean_visible_planes},
                           {"max_visible_planes", smooth.max_visible_planes},
                           {"end_plane_weights", shepard ? json(smooth.end_plane_weights) : json(nullptr)},
                           {"contour_pinning", shepard ? json{{"samples", smooth.pinning.samples},
                                                              {"samples_pinned", smooth.pinning.samples_pinned},
                                                              {"samples_outside", smooth.pinning.samples_outside},
                                                              {"samples_crowded", smooth.pinning.samples_crowded},
                                                              {"voxels_pinned", smooth.pinning.voxels_pinned},
                                                              {"worst_before_mm", smooth.pinning.worst_before_mm}}
                                                       : json(nullptr)},
                           {"voxel_betti", smoothVoxelBetti},
                           {"repair", {{"specks_removed", smooth.repair.specks_removed},
                                       {"cavities_filled", smooth.repair.cavities_filled},
                                       {"critical_voxels_added", smooth.repair.critical_voxels_added}}},
                           {"adaptivity_dropped", smooth.adaptivity_dropped},
                           {"level_set_active_voxels", smooth.surface.level_set.coords.size()},
                           {"level_set_half_width_mm", smooth.surface.level_set.background},
                           {"shepard_connectivity", shepard ? check(smooth.shepard_check, smooth.shepard_cells) : json(nullptr)},
                           {"shepard_refined_cells", shepard ? refined(smooth.refined_cells) : json(nullptr)},
                           {"shepard_keeps_connectivity", shepard ? json(smooth.shepard_keeps_connectivity) : json(nullptr)},
                           {"fell_back_to_level_set", smooth.fell_back},
                           {"level_set_iterations", smooth.iterations_applied},
                           {"connectivity", check(smooth.final_check, smooth.final_cells)},
                           {"unsmoothed", {{"betti", mt.betti}, {"watertight", mt.watertight},
                                           {"volume_mm3", mt.volume_mm3},
                                           {"mesh_triangles", methodMesh.triangles.size()}}}};
  }
  report["topology_repair"] = {{"specks_removed", rec.repair.specks_removed},
                               {"cavities_filled", rec.repair.cavities_filled},
                               {"critical_voxels_added", rec.repair.critical_voxels_added}};
  report["conformity"] = in.conformity;
  report["conformity"].update(json{{"conformal_mesh", c.conformal_mesh},
                          {"planes_cut", cutStats.planes_cut},
                          {"cut_vertices", cutStats.vertices_added},
                          {"cut_vertices_on_contour", cutStats.vertices_snapped},
                          {"cut_vertices_short_of_contour", cutStats.vertices_shortened},
                          {"cut_vertices_off_contour", cutStats.vertices_unsnapped},
                          {"cut_max_move_mm", cutStats.max_move_mm}});
  report["timings_s"] = clock.timings;
  report["timings_s"]["total"] = total;
  report["peak_memory_mb"] = clock.memory;
  report["throughput"] = {{"reconstruct_voxels_per_s",
                           rec.evaluate_seconds > 0 ? double(rec.field.grid.count()) / rec.evaluate_seconds : 0.0},
                          {"evaluate_s", rec.evaluate_seconds},
                          {"method1_evaluate_s", rp.method == ReconstructionMethod::nearest_plane
                                                     ? json(rec.evaluate_seconds) : json(nullptr)},
                          {"method2_evaluate_s", rp.method == ReconstructionMethod::section_voronoi
                                                     ? json(rec.evaluate_seconds) : json(nullptr)}};
  report["warnings"] = in.warnings;
  writeTextFile(out.file("report.json").string(), report.dump(2) + "\n");

  json manifest;
  manifest["config_path"] = c.path;
  manifest["config_resolved"] = c.resolved_yaml;
  manifest["config_sha256"] = sha256Hex(c.resolved_yaml);
  manifest["overrides"] = o.overrides;
  json files = json::array();
  for (const auto& f : in.input_files) files.push_back({{"path", f}, {"sha256", sha256File(f)}});
  manifest["inputs"] = files;
  manifest["libraries"] = libraryVersions();
  manifest["threads"] = tbb::this_task_arena::max_concurrency();
  json outputs = json::array();
  for (const auto& e : fs::directory_iterator(out.dir()))
    outputs.push_back(e.path().filename().string());
  std::sort(outputs.begin(), outputs.end());
  manifest["outputs"] = outputs;
  writeTextFile(out.file("manifest.json").string(), manifest.dump(2) + "\n");
  out.commit();
  progress.finish();
  for (const auto& w : in.warnings) progress.note("warning: " + w);
  if (!o.quiet)
    std::cerr << "betti " << topo.betti[0] << " " << topo.betti[1] << " " << topo.betti[2]
              << "; outputs in " << outDir.string() << "\n";
  return 0;
}

int checkCommand(const RunOptions& o) {
  Progress progress(o.quiet);
  StageClock clock;
  Inputs in = loadInputs(o, clock, progress);
  progress.finish();
  int sections = 0;
  for (const auto& p : in.planes) sections += int(p.sections.size());
  json r;
  r["config"] = in.config.path;
  r["valid"] = true;
  r["counts"] = {{"slices", in.slices}, {"sections", sections}};
  r["conformity"] = in.conformity;
  if (sections > 0) {
    r["voxel_size"] = voxelSizeJson(resolveVoxelSize(in, true));
    const ReconstructionLayout L = layoutOf(in.planes, in.config);
    r["sections_bounds_mm"] = {vec(L.sections_min), vec(L.sections_max)};
    r["end_margin_mm"] = L.end_margin_mm;
    r["grid_dims"] = L.grid.dims;
    r["estimated_voxels"] = L.grid.count();
    r["estimated_memory_mb"] = double(L.grid.count()) * kReconstructionBytesPerVoxel / 1e6;
  } else {
    in.warnings.push_back("no section found in any slice");
  }
  r["warnings"] = in.warnings;
  std::cout << r.dump(2) << "\n";
  return 0;
}

}  // namespace xsect

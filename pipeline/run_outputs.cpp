// The output folder of `xsect run` (see run_outputs.h); report.json is built in run_report.cpp.
#include "pipeline/json_values.h"
#include "pipeline/run_outputs.h"

#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include <algorithm>

#include "geometry/core/polygon.h"
#include "geometry/core/section_ids.h"
#include "io/append_int.h"
#include "io/file_hash.h"
#include "io/json_edge_lists.h"
#include "io/label_volume_file.h"
#include "io/level_set_file.h"
#include "io/mesh_io.h"
#include "io/scalar_volume_file.h"
#include "io/slices_file.h"
#include "io/staged_output.h"
#include "io/text_file.h"
#include "pipeline/library_versions.h"
#include "pipeline/output_manifest.h"
#include "report/run/run_report_page.h"

namespace xsect {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace {

/// The graphs' edges as (flat section id a, id b, cell, method, Graphviz style), G, then G' (methods
/// 2 and 3), then G'' (method 3).
template <typename Visit>
void forEachEdge(const RunResults& r, const Visit& visit) {
  const SectionIds ids = r.scene_stage.scene.ids();  // the real planes' sections
  const auto visitAll = [&](const std::vector<GraphEdge>& es, const char* method, const char* style) {
    for (const GraphEdge& e : es)
      visit(ids.of(e.plane_a, e.section_a), ids.of(e.plane_b, e.section_b), e.cell, method, style);
  };
  const ArrangeStage& a = r.arrangement;
  // The run's method's graph as its solid realises it (less the joins reconstruction.topology cut).
  const std::vector<GraphEdge>& joins = r.reconstruction.joins(a.methodEdges());
  const auto graphOf = [&](const std::vector<GraphEdge>& es) -> const std::vector<GraphEdge>& {
    return &es == &a.methodEdges() ? joins : es;
  };
  visitAll(graphOf(a.graphs.g), "nearest_plane", "style=dashed");
  if (a.with_g_prime) visitAll(graphOf(a.graphs.g_prime), "section_voronoi", "style=solid");
  if (a.with_g_double_prime) visitAll(graphOf(a.graphs.g_double_prime), "delaunay", "style=bold");
}

std::string manifestText(const RunInputs& in, const RunOptions& o, const fs::path& dir) {
  const RunConfig& c = in.config;
  json manifest = manifestHead("run", in.input_files);
  manifest["config_path"] = c.path;
  manifest["config_resolved"] = c.resolved_yaml;
  manifest["config_sha256"] = sha256Hex(c.resolved_yaml);
  manifest["overrides"] = o.overrides;
  manifest["libraries"] = libraryVersions();
  manifest["threads"] = tbb::this_task_arena::max_concurrency();
  return outputManifestText(std::move(manifest), dir);
}

}  // namespace

SectionGraph sectionGraph(const RunResults& r) {
  SectionGraph graph;
  int id = 0;
  for (const CuttingPlane& p : r.inputs.planes)
    for (std::size_t s = 0; s < p.sections.size(); ++s) {
      const Section& sec = p.sections[s];
      graph.nodes.push_back({{"id", id++}, {"slice", p.slice}, {"section", s}, {"label", sec.label},
                             {"area_mm2", sectionArea(sec)},
                             {"centroid_mm", vecJson(p.plane.toWorld(sectionCentroid(sec)))}});
    }
  graph.method = nameOf(kReconstructionMethods, r.method.id());
  forEachEdge(r, [&](int a, int b, int cell, const char* method, const char*) {
    if (graph.method == method) graph.edges.push_back({a, b, cell});
  });
  return graph;
}

std::string graphJsonText(const RunResults& r, const json& nodes) {
  json graph = {{"method", nameOf(kReconstructionMethods, r.method.id())},
                {"cells", r.arrangement.arrangement.cells},
                {"sample_spacing_mm", r.arrangement.arrangement.sample_spacing_mm},
                {"nodes", nodes},
                {"edges", json::array()}};
  std::vector<std::pair<std::string, std::vector<EdgeObject>>> lists(1);
  lists[0].first = "edges";
  forEachEdge(r, [&](int a, int b, int cell, const char* method, const char*) {
    lists[0].second.push_back({a, b, cell, method});
  });
  if (const std::vector<GraphEdge>* joins = r.method.joinsRealised(r.reconstruction)) {  // method 3: by R''
    const std::string key = std::string(nameOf(kReconstructionMethods, r.method.id())) + "_connections";
    graph[key] = json::array();
    const SectionIds ids = r.scene_stage.scene.ids();
    lists.push_back({key, {}});
    for (const GraphEdge& e : *joins)
      lists.back().second.push_back({ids.of(e.plane_a, e.section_a), ids.of(e.plane_b, e.section_b), e.cell, nullptr});
  }
  return jsonWithEdgeLists(graph, lists);
}

std::string graphDot(const RunResults& r) {
  std::string dot = "graph sections {\n  node [shape=ellipse];\n";
  int id = 0;
  for (const CuttingPlane& p : r.inputs.planes)
    for (std::size_t s = 0; s < p.sections.size(); ++s)
      dot += "  n" + std::to_string(id++) + " [label=\"" + std::to_string(p.slice) + ":" + std::to_string(s) + "\"];\n";
  // Appended in place, room reserved (method 3 on multiaxial-3x40 lists 490 000 edges: 18 MB).
  std::size_t edges = 0;
  forEachEdge(r, [&](int, int, int, const char*, const char*) { ++edges; });
  dot.reserve(dot.size() + 64 * edges + 4);
  forEachEdge(r, [&](int a, int b, int cell, const char*, const char* style) {
    dot += "  n";
    appendInt(dot, a);
    dot += " -- n";
    appendInt(dot, b);
    dot += " [";
    dot += style;
    dot += ", tooltip=\"cell ";
    appendInt(dot, cell);
    dot += "\"];\n";
  });
  dot += "}\n";
  return dot;
}

std::vector<std::string> runWarnings(const RunResults& r) {
  std::vector<std::string> w = warningsThroughScene(r.inputs, r.scene_stage);
  w.insert(w.end(), r.reconstruction.warnings.begin(), r.reconstruction.warnings.end());
  if (r.smooth) w.insert(w.end(), r.smooth->warnings.begin(), r.smooth->warnings.end());
  w.insert(w.end(), r.meshes.warnings.begin(), r.meshes.warnings.end());
  return w;
}

json writeRunOutputs(const RunResults& r, const RunOptions& o, const StageClock& clock) {
  const RunConfig& c = r.inputs.config;
  const fs::path& outDir = r.inputs.output_dir;
  StagedOutput out(outDir, r.inputs.output_guard);
  // Independent groups of files written at once (each file's bytes depend on the results
  // only); the manifest, which lists the folder, last.
  const auto meshes = [&] {
    for (const auto& fmt : c.mesh_formats) writeMesh(out.file("mesh." + fmt).string(), r.meshes.mesh);
    if (r.smooth) {
      for (const auto& fmt : c.mesh_formats)
        writeMesh(out.file("mesh_unsmoothed." + fmt).string(), r.meshes.method_mesh);
      writeLevelSetVdb(out.file("level_set.vdb").string(), r.smooth->surface.level_set);
    }
    for (const Material& m : r.meshes.materials)
      for (const auto& fmt : c.mesh_formats)
        writeMesh(out.file("mesh_label_" + std::to_string(m.label) + "." + fmt).string(), m.mesh);
  };
  const BlockGrid<std::uint16_t>& labels = r.meshes.voxel_label;
  const auto volumes = [&] {
    writeLabelVolumeNrrd(out.file("labels.nrrd").string(), labels.grid(),
                         [&](int j, int k, std::uint16_t* row) { labels.readRow(j, k, row); });
    const GridSpec& g = labels.grid();
    writeScalarVolumeNrrd(
        out.file("sampling.nrrd").string(), g,
        [&](int j, int k, float* row) { samplingRatioRow(r.sampling, g, j, k, row); },
        "xsect sampling: per voxel, h_C / critical reach of its cell (thesis Def. 23; < 1 passes), -1 unknown");
  };
  const SectionGraph graph = sectionGraph(r);
  json report;
  // The graph's two files on their own: with method 3 they list G, G', G'' and the connections of
  // R'' (multiaxial-3x40: 42 MB and 18 MB; the writing took 0.6 s with them in one group, 0.4 s so).
  const auto graphJson = [&] { writeTextFile(out.file("graph.json").string(), graphJsonText(r, graph.nodes)); };
  const auto graphDotFile = [&] { writeTextFile(out.file("graph.dot").string(), graphDot(r)); };
  const auto documents = [&] {
    const json conformity = conformityDetailsJson(c.conformity, r.inputs.conformity);
    writeTextFile(out.file("conformity.json").string(), conformity.dump(2) + "\n");
    writeTextFile(out.file("sampling.json").string(), samplingDetailsJson(r.sampling).dump(1) + "\n");
    if (!r.inputs.slice_records.empty() && !r.inputs.conformity.pose_changes.empty()) {
      // The input's slices with the poses the run used (smoothed, corrected), images relative to
      // the output folder so that the file can be run from there.
      std::vector<SliceRecord> corrected = r.inputs.slice_records;
      const fs::path outAbs = fs::absolute(outDir).lexically_normal();
      const auto fromOut = [&](const std::string& p) { return fs::path(p).lexically_normal().lexically_relative(outAbs).string(); };
      for (SliceRecord& s : corrected) {
        s.image = fromOut(s.image_resolved);
        if (s.fov_resolved) s.fov = fromOut(*s.fov_resolved);
      }
      for (const PoseChange& p : r.inputs.conformity.pose_changes)
        corrected[std::size_t(p.slice)].image_to_world = p.transform * corrected[std::size_t(p.slice)].image_to_world;
      writeSlicesFile(out.file("corrected_slices.yaml").string(), corrected);
    }
    if (!r.sampling.advice_poses.empty()) {
      std::vector<std::string> notes;
      for (const AdvisedSlice& a : r.sampling.advice)
        notes.push_back("splits cell " + std::to_string(a.cell) + "; worst " + (a.ratio ? "ratio " : "height (mm) ") +
                        jsonNumber(a.worst_before) + " -> " + jsonNumber(a.worst_after));
      writePosesFile(out.file("advice.yaml").string(), r.sampling.advice_poses,
                     "xsect advice: slices to add, best first (image_to_world in the input's frame, pixels of " +
                         jsonNumber(r.sampling.advice_pixel_mm) + " mm)",
                     notes);
    }
    report = reportJson(r, clock);
    writeTextFile(out.file("report.json").string(), report.dump(2) + "\n");
    writeTextFile(out.file("report.html").string(), reportPageHtml(runReportPage(r, report, conformity, graph)));
  };
  tbb::parallel_invoke(meshes, volumes, graphJson, graphDotFile, documents);
  writeTextFile(out.file(kManifestName).string(), manifestText(r.inputs, o, out.dir()));
  out.commit();
  return report;
}

}  // namespace xsect

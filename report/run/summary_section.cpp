// report.html's figures from report.json (see summary_section.h).
#include "report/run/summary_section.h"

#include "report/page/report_page.h"
#include "report/run/page_text.h"

namespace xsect {

using json = nlohmann::ordered_json;

namespace {

std::string row(const std::string& name, const std::string& valueHtml) {
  return "<tr><th>" + htmlEscape(name) + "</th><td>" + valueHtml + "</td></tr>\n";
}

std::string mm(const json& v) { return v.is_null() ? "–" : cellText(v) + " mm"; }

}  // namespace

std::string headlineHtml(const json& report) {
  const std::string verdict = field(report, {"sampling", "verdict"}).is_string()
                                  ? field(report, {"sampling", "verdict"}).get<std::string>()
                                  : "undetermined";
  return "sampling verdict <span id=\"verdict\" class=\"verdict-" + htmlEscape(verdict) + "\">" + htmlEscape(verdict) +
         "</span> · Betti numbers <span id=\"betti\">" + cellText(field(report, {"betti"})) +
         "</span> · topology confidence <span id=\"confidence\">" +
         htmlEscape(field(report, {"topology", "confidence", "level"}).is_string()
                        ? field(report, {"topology", "confidence", "level"}).get<std::string>()
                        : std::string("not computed")) +
         "</span> · mesh of <span id=\"mesh-triangles\">" + cellText(field(report, {"counts", "mesh_triangles"})) +
         "</span> triangles from <span id=\"slices-used\">" + cellText(field(report, {"counts", "slices_used"})) +
         "</span> slices";
}

std::string summaryHtml(const json& report, const std::string& samplingLine) {
  const json& counts = field(report, {"counts"});
  const json& rec = field(report, {"reconstruction"});
  std::string t = "<table>\n";
  t += row("slices", cellText(field(counts, {"slices_used"})) + " used of " + cellText(field(counts, {"slices"})) + " read; " +
           cellText(field(counts, {"planes_with_sections"})) + " hold " + cellText(field(counts, {"sections"})) + " sections");
  // The arrangement's cells (the sampling diagnosis reads each) and those bounded by sections (the
  // ones a method joins sections in): two counts, each named, so that the sampling row's agree.
  const json& allCells = field(report, {"sampling", "cells", "total"});
  t += row("reconstruction", cellText(field(rec, {"method"})) + " on " + cellText(field(rec, {"planes"})) + " planes, voxel " +
                                 mm(field(rec, {"voxel_size_mm"})) + ", " +
                                 (allCells.is_number() ? cellText(allCells) + " cells of the arrangement, " +
                                                             cellText(field(counts, {"cells"})) + " of them bounded by sections"
                                                       : cellText(field(counts, {"cells"})) + " cells bounded by sections"));
  const json& delaunay = field(rec, {"delaunay"});
  if (delaunay.is_object())  // method 3: R'' is a union of tetrahedra, its mesh ∂R''
    t += row("method 3", cellText(field(delaunay, {"d3"})) + " tetrahedra kept of " +
                             cellText(field(delaunay, {"section_vertices"})) + " section-vertices (" +
                             cellText(field(delaunay, {"branching_points"})) + " branching points) in " +
                             cellText(field(delaunay, {"cells"})) + " cells, " +
                             cellText(field(delaunay, {"tetrahedra_components"})) + " component(s); R″ joins " +
                             cellText(field(delaunay, {"connections"})) + " section pairs, G″ has " +
                             cellText(field(delaunay, {"edges_g_double_prime"})) + " edges");
  if (const json& c = field(report, {"topology", "confidence", "text"}); c.is_string())
    t += row("topology confidence", htmlEscape(c.get<std::string>()) +
                                        (field(report, {"topology", "mode"}) == "free" &&
                                                 field(report, {"topology", "confidence", "level"}) != "high"
                                             ? " (if you know the object's topology, give it as reconstruction.topology)"
                                             : ""));
  t += row("solid", "Betti numbers " + cellText(field(report, {"betti"})) + " (voxels: " +
                        cellText(field(report, {"voxel_betti"})) + "), " +
                        (field(report, {"watertight"}) == json(true) ? "watertight" : "<b>not watertight</b>") + ", " +
                        cellText(field(counts, {"mesh_triangles"})) + " triangles");
  const json& sampling = field(report, {"sampling"});
  std::string conditions;
  for (const auto& [name, state] : field(sampling, {"conditions"}).items())
    conditions += (conditions.empty() ? "" : "; ") + htmlEscape(name) + ": " + cellText(state);
  const json& cells = field(sampling, {"cells"});
  t += row("sampling", "<b>" + cellText(field(sampling, {"verdict"})) + "</b> (" + conditions + "); of the " +
                           cellText(field(cells, {"total"})) + " cells, " + cellText(field(cells, {"satisfied"})) +
                           " satisfied, " + cellText(field(cells, {"violated"})) + " violated, " +
                           cellText(field(cells, {"undetermined"})) + " undetermined<br><span class=\"hint\">" +
                           htmlEscape(samplingLine) + "</span>");
  std::string guarantees;
  for (const auto& g : field(sampling, {"guarantees"})) guarantees += (guarantees.empty() ? "" : "; ") + cellText(g);
  if (!guarantees.empty()) t += row("guarantees", guarantees);
  const json& conf = field(report, {"conformity"});
  const bool measured = field(conf, {"pairs_measured"}).is_number() && field(conf, {"pairs_measured"}).get<double>() > 0;
  std::string c = measured ? cellText(field(conf, {"pairs_measured"})) + " pairs of slices compared; disagreement median " +
                                 mm(field(conf, {"before", "median_mismatch_mm"})) + ", max " +
                                 mm(field(conf, {"before", "max_mismatch_mm"}))
                           : std::string("no pair of slices crosses where both hold sections: nothing to compare");
  if (!field(conf, {"after"}).is_null())
    c += "; after enforcement median " + mm(field(conf, {"after", "median_mismatch_mm"})) + ", max " +
         mm(field(conf, {"after", "max_mismatch_mm"}));
  if (!field(conf, {"pose_correction"}).is_null())
    c += "; pose correction (" + cellText(field(conf, {"pose_correction", "kind"})) + "): gaps at crossings " +
         mm(field(conf, {"pose_correction", "gap_rms_before_mm"})) + " → " +
         mm(field(conf, {"pose_correction", "gap_rms_after_mm"})) + " RMS";
  const json& flagged = field(conf, {"flagged_slices"});
  const json& dropped = field(conf, {"dropped_slices"});
  if (flagged.is_array() && !flagged.empty()) c += "; flagged slices " + cellText(flagged);
  if (dropped.is_array() && !dropped.empty()) c += "; dropped " + cellText(dropped);
  t += row("conformity", c);
  const json& graph = field(report, {"graph"});
  t += row("connectivity", cellText(field(graph, {"components"})) + " component(s) in the graph; " +
                               (field(graph, {"same_partition_as_voxels"}) == json(true)
                                    ? "the solid groups the sections the same way"
                                    : "<b>the solid groups the sections differently</b>"));
  return t + "</table>\n";
}

std::string timingsHtml(const json& report) {
  const json& timings = field(report, {"timings_s"});
  const json& memory = field(report, {"peak_memory_mb"});
  std::string t = "<table>\n<tr><th>stage</th><th>wall time (s)</th><th>peak memory (MB)</th></tr>\n";
  for (const auto& [stage, seconds] : timings.items())
    t += "<tr><td>" + htmlEscape(stage) + "</td><td class=\"num\">" + cellText(seconds) + "</td><td class=\"num\">" +
         cellText(field(memory, {stage.c_str()})) + "</td></tr>\n";
  return t + "</table>\n<p class=\"hint\">Writing the outputs (this page too) comes after these figures.</p>\n";
}

}  // namespace xsect

// The changes topology control made, as a table (see topology_changes.h).
#include "report/run/topology_changes.h"

#include "report/run/page_text.h"

namespace xsect {

using json = nlohmann::ordered_json;

namespace {

/// The chosen solid's tunnels and cavities with their sizes and places (report.json
/// topology.features), or why they were not computed.
std::string featuresHtml(const json& t) {
  if (!t.contains("features")) return "";
  if (t["features"].is_null())
    return "<p>Tunnels and cavities not sized: the solid's box holds " + cellText(t["features_voxels"]) +
           " voxels, more than the persistence computation takes.</p>\n";
  if (t["features"].empty()) return "<p>The solid chosen has no tunnel and no cavity.</p>\n";
  std::string h = "<p>Tunnels and cavities of the solid chosen, by size (the least erosion or growth that "
                  "removes one: near the voxel size, a spurious one):</p>\n<table>\n<tr><th>kind</th><th>size (mm)"
                  "</th><th>born at (mm)</th><th>dies at (mm)</th><th>cells</th></tr>\n";
  for (const json& f : t["features"])
    h += "<tr><td>" + cellText(f["kind"]) + "</td><td class=\"num\">" + cellText(f["size_mm"]) + "</td><td>" +
         cellText(f["born_at_mm"]) + "</td><td>" + cellText(f["dies_at_mm"]) + "</td><td>" + cellText(f["cells"]) +
         "</td></tr>\n";
  return h + "</table>\n";
}

}  // namespace

std::string topologyChangesHtml(const json& report) {
  const json& t = field(report, {"topology"});
  if (!t.is_object() || !t.contains("changes")) return "";  // free: only the confidence (the summary shows it)
  std::string h = "<p>reconstruction.topology: " + cellText(t["mode"]) +
                  (t["target"].is_null() ? std::string() : " [" + cellText(t["target"]) + "]") +
                  "; Betti numbers of the method's solid " + cellText(t["betti_before"]) + ", of the solid chosen " +
                  cellText(t["betti_after"]) + " (" + cellText(t["joins"]) + " joins made by the method, " +
                  cellText(t["joins_forced"]) + " of them forced, " + cellText(t["changes_tried"]) +
                  " changes tried).</p>\n";
  h += featuresHtml(t);
  if (t["changes"].empty()) return h + "<p>No cell changed.</p>\n";
  h += "<table>\n<tr><th>change</th><th>sections</th><th>cell</th><th>centre (mm)</th><th>voxels</th>"
       "<th>width (mm)</th><th>Betti after</th></tr>\n";
  for (const json& c : t["changes"])
    h += "<tr><td>" + cellText(c["change"]) + "</td><td>" + cellText(c["sections"]) + "</td><td class=\"num\">" +
         cellText(c["cell"]) + "</td><td>" + cellText(c["at_mm"]) + "</td><td class=\"num\">" + cellText(c["voxels"]) +
         "</td><td class=\"num\">" + cellText(c["width_mm"]) + "</td><td>" + cellText(c["betti_after"]) + "</td></tr>\n";
  return h + "</table>\n<p class=\"hint\">Sections are numbered as graph.json's nodes; cells as the arrangement's "
             "(report.json topology.cells_changed).</p>\n";
}

}  // namespace xsect

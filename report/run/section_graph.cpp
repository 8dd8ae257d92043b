// The sections' connectivity graph for report.html (see section_graph.h).
#include "report/run/section_graph.h"

#include <algorithm>
#include <map>
#include <set>
#include <vector>

#include "geometry/core/disjoint_sets.h"
#include "report/charts/graphviz_svg.h"
#include "report/page/report_page.h"
#include "report/run/page_text.h"

namespace xsect {

using json = nlohmann::ordered_json;

namespace {

constexpr const char* kComponentColours[] = {"#a6cee3", "#b2df8a", "#fb9a99", "#fdbf6f", "#cab2d6", "#ffff99",
                                             "#8dd3c7", "#bebada", "#fccde5", "#d9d9d9", "#ccebc5", "#ffed6f"};

/// The graph a method's edges in graph.json form (their `method`), as the page names it.
std::string methodGraphName(const std::string& method) {
  if (method == "section_voronoi") return "graph G′ (method 2)";
  if (method == "delaunay") return "graph G″ (method 3, Def. 44)";
  return "graph G (method 1)";
}

}  // namespace

std::string sectionGraphHtml(const SectionGraph& graph, std::size_t maxNodes, std::size_t maxEdges) {
  const json& nodes = graph.nodes;
  const std::size_t n = nodes.size();
  const std::string& method = graph.method;
  // One entry per pair of sections, with the cells where their lifts meet.
  std::map<std::pair<int, int>, std::set<int>> cellsOfPair;
  for (const SectionGraph::Edge& e : graph.edges) {
    if (e.a == e.b || e.a < 0 || e.b < 0 || std::size_t(e.a) >= n || std::size_t(e.b) >= n) continue;
    cellsOfPair[{std::min(e.a, e.b), std::max(e.a, e.b)}].insert(e.cell);
  }
  DisjointSets sets(n);
  for (const auto& [pair, cells] : cellsOfPair) sets.unite(std::size_t(pair.first), std::size_t(pair.second));
  std::map<std::size_t, int> componentOf;  // representative -> component number, in section order
  std::vector<int> component(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto [it, added] = componentOf.emplace(sets.find(i), int(componentOf.size()));
    component[i] = it->second;
  }
  std::string intro = "<p>" + std::to_string(n) + " sections, " + std::to_string(cellsOfPair.size()) +
                      " pairs joined by the " + methodGraphName(method) +
                      ", " + std::to_string(componentOf.size()) +
                      " connected component(s). A node is <i>slice:section</i>; colours tell the components apart.</p>\n";
  if (n == 0) return intro;
  // Drawn when it can be read: a sweep's chain of sections or a sparse set (at most two pairs per
  // section on average). Denser graphs (a multi-axial torus: 36 sections, 177 pairs) draw as a
  // tangle whatever the layout; their components are listed.
  const bool readable = cellsOfPair.size() <= 2 * n;
  if (n <= maxNodes && cellsOfPair.size() <= maxEdges && readable) {
    std::string dot = "graph sections {\n  graph [layout=neato, start=1, overlap=false, splines=false, outputorder=edgesfirst, "
                      "size=\"10,7\", fontname=\"Helvetica\"];\n  node [shape=ellipse, style=filled, fontsize=9, margin=\"0.03,0.01\", "
                      "width=0.3, height=0.2, fontname=\"Helvetica\"];\n"
                      "  edge [color=\"#7b8494\"];\n";
    for (std::size_t i = 0; i < n; ++i) {
      const json& node = nodes[i];
      dot += "  n" + std::to_string(i) + " [label=\"" + std::to_string(node.value("slice", -1)) + ":" +
             std::to_string(node.value("section", 0)) + "\", fillcolor=\"" +
             kComponentColours[std::size_t(component[i]) % std::size(kComponentColours)] + "\", tooltip=\"component " +
             std::to_string(component[i]) + ", label " + std::to_string(node.value("label", 1)) + ", area " +
             shortNumber(node.value("area_mm2", 0.0)) + " mm²\"];\n";
    }
    for (const auto& [pair, cells] : cellsOfPair)
      dot += "  n" + std::to_string(pair.first) + " -- n" + std::to_string(pair.second) + " [tooltip=\"joined in " +
             std::to_string(cells.size()) + " cell(s)\"" + (cells.size() > 1 ? ", penwidth=1.6" : "") + "];\n";
    dot += "}\n";
    if (const auto svg = graphvizSvg(dot)) return intro + "<div class=\"graph-box\">\n" + *svg + "</div>\n";
    intro += "<p class=\"hint\">Graphviz (dot) did not draw the graph (is the Debian package graphviz installed?): "
             "the components are listed instead.</p>\n";
  } else {
    intro += "<p class=\"hint\">Too many sections or pairs to draw readably: the components are listed (graph.json and "
             "graph.dot hold the whole graph; <code>dot -Tsvg graph.dot</code> draws it).</p>\n";
  }
  // The fallback: each component with its size and slices, largest first.
  std::vector<std::vector<std::size_t>> members(componentOf.size());
  for (std::size_t i = 0; i < n; ++i) members[std::size_t(component[i])].push_back(i);
  std::vector<std::size_t> order(members.size());
  for (std::size_t c = 0; c < order.size(); ++c) order[c] = c;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return members[a].size() > members[b].size(); });
  std::string html = "<div class=\"graph-fallback\"><table>\n<tr><th>component</th><th>sections</th><th>slices</th></tr>\n";
  const std::size_t shown = std::min<std::size_t>(order.size(), 40);
  for (std::size_t q = 0; q < shown; ++q) {
    const std::vector<std::size_t>& m = members[order[q]];
    int lo = 1 << 30, hi = -1;
    for (const std::size_t i : m) {
      lo = std::min(lo, nodes[i].value("slice", -1));
      hi = std::max(hi, nodes[i].value("slice", -1));
    }
    html += "<tr><td><span class=\"legend-swatch\" style=\"background:" +
            std::string(kComponentColours[order[q] % std::size(kComponentColours)]) + "\"></span>" +
            std::to_string(order[q]) + "</td><td class=\"num\">" + std::to_string(m.size()) + "</td><td>" +
            std::to_string(lo) + (hi > lo ? " – " + std::to_string(hi) : "") + "</td></tr>\n";
  }
  if (shown < order.size())
    html += "<tr><td colspan=\"3\" class=\"hint\">and " + std::to_string(order.size() - shown) + " more</td></tr>\n";
  return intro + html + "</table></div>\n";
}

}  // namespace xsect

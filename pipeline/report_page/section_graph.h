// report.html's connectivity graph (issue 21): the sections as nodes, joined where the method's
// graph joins them (G for method 1, G' ⊇ G for method 2; thesis Defs. 29-30; graph.json), coloured
// by connected component, drawn by Graphviz into inline SVG; a table of the components instead when
// the graph is too large to read or Graphviz is missing.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

namespace xsect {

/// @param graph      graph.json's content.
/// @param max_nodes  above this many sections the components are listed instead of drawn.
std::string sectionGraphHtml(const nlohmann::ordered_json& graph, std::size_t max_nodes = 250);

}  // namespace xsect

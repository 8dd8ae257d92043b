// report.html's connectivity graph (issue 21): the sections as nodes, joined where the method's
// graph joins them (G for method 1, G' ⊇ G for method 2, G'' ⊇ G' for method 3; thesis Defs. 29-30
// and 44; graph.json), coloured
// by connected component, drawn by Graphviz into inline SVG; a table of the components instead when
// the graph is too large to read or Graphviz is missing.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

namespace xsect {

/// @param graph      graph.json's content.
/// @param max_nodes  above this many sections, or
/// @param max_edges  this many joined pairs, the components are listed instead of drawn: the
///                   choice depends on the graph only, never on how long Graphviz takes (neato
///                   without splines draws 250 nodes and 1,441 pairs in 0.4 s; with splines it took
///                   over 60 s), so that the page is the same on a busy machine.
std::string sectionGraphHtml(const nlohmann::ordered_json& graph, std::size_t max_nodes = 250,
                             std::size_t max_edges = 1500);

}  // namespace xsect

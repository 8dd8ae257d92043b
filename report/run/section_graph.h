// report.html's connectivity graph (issue 21): the sections as nodes, joined where the method's
// graph joins them (G for method 1, G' ⊇ G for method 2, G'' ⊇ G' for method 3; thesis Defs. 29-30
// and 44; graph.json), coloured
// by connected component, drawn by Graphviz into inline SVG; a table of the components instead when
// the graph is too large or too dense to read (more than two joined pairs per section) or Graphviz
// is missing.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace xsect {

/// The graph the page draws: graph.json's nodes, and the method's edges.
struct SectionGraph {
  struct Edge {
    int a = 0, b = 0;  ///< flat section ids (graph.json's node ids)
    int cell = -1;     ///< the cell of the arrangement where they are joined
  };
  nlohmann::ordered_json nodes = nlohmann::ordered_json::array();  ///< graph.json's `nodes`
  std::string method;       ///< graph.json's `method` (a reconstruction method's name)
  std::vector<Edge> edges;  ///< the edges of that method's graph (graph.json's edges of `method`)
};

/// @param graph      the sections and the method's edges.
/// @param max_nodes  above this many sections, or
/// @param max_edges  this many joined pairs, the components are listed instead of drawn: the
///                   choice depends on the graph only, never on how long Graphviz takes (neato
///                   without splines draws 250 nodes and 1,441 pairs in 0.4 s; with splines it took
///                   over 60 s), so that the page is the same on a busy machine.
std::string sectionGraphHtml(const SectionGraph& graph, std::size_t max_nodes = 250, std::size_t max_edges = 1500);

}  // namespace xsect

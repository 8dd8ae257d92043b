// graph.json's edge lists as text (see json_edge_lists.h).
#include "io/json_edge_lists.h"

#include <stdexcept>

namespace xsect {

std::string jsonWithEdgeLists(const nlohmann::ordered_json& doc,
                              const std::vector<std::pair<std::string, std::vector<EdgeObject>>>& lists) {
  for (const auto& [key, edges] : lists)
    if (!doc.contains(key) || !doc.at(key).is_array() || !doc.at(key).empty())
      throw std::invalid_argument("json edge lists: \"" + key + "\" is not an empty top-level array");
  // dump(2) writes a top-level key at 2 spaces, "[]" for an empty array; a non-empty array's
  // objects at 4 spaces, their fields at 6.
  std::string text = doc.dump(2) + "\n";
  for (const auto& [key, edges] : lists) {
    if (edges.empty()) continue;
    std::string items;
    for (const EdgeObject& e : edges) {
      if (!items.empty()) items += ",\n";
      items += "    {\n      \"a\": " + std::to_string(e.a) + ",\n      \"b\": " + std::to_string(e.b) +
               ",\n      \"cell\": " + std::to_string(e.cell);
      if (e.method) items += ",\n      \"method\": \"" + std::string(e.method) + "\"";
      items += "\n    }";
    }
    const std::string empty = "\n  \"" + key + "\": []";
    text.replace(text.find(empty), empty.size(), "\n  \"" + key + "\": [\n" + items + "\n  ]");
  }
  return text;
}

}  // namespace xsect

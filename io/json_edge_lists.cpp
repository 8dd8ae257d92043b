// graph.json's edge lists as text (see json_edge_lists.h).
#include "io/json_edge_lists.h"

#include <algorithm>
#include <stdexcept>

#include "io/append_int.h"

namespace xsect {

std::string jsonWithEdgeLists(const nlohmann::ordered_json& doc,
                              const std::vector<std::pair<std::string, std::vector<EdgeObject>>>& lists) {
  for (const auto& [key, edges] : lists)
    if (!doc.contains(key) || !doc.at(key).is_array() || !doc.at(key).empty())
      throw std::invalid_argument("json edge lists: \"" + key + "\" is not an empty top-level array");
  // dump(2) writes a top-level key at 2 spaces, "[]" for an empty array; a non-empty array's
  // objects at 4 spaces, their fields at 6. The text is assembled once, in place (method 3 on
  // multiaxial-3x40 lists 490 000 edges: 42 MB).
  const std::string base = doc.dump(2) + "\n";
  struct Cut {
    std::size_t at, length;
    const std::string* key;
    const std::vector<EdgeObject>* edges;
  };
  std::vector<Cut> cuts;
  std::size_t size = base.size();
  for (const auto& [key, edges] : lists) {
    if (edges.empty()) continue;
    const std::string empty = "\n  \"" + key + "\": []";
    const std::size_t at = base.find(empty);
    if (at == std::string::npos)
      throw std::invalid_argument("json edge lists: \"" + key + "\" is not written as a top-level key");
    cuts.push_back({at, empty.size(), &key, &edges});
    size += edges.size() * 80;
  }
  std::sort(cuts.begin(), cuts.end(), [](const Cut& l, const Cut& r) { return l.at < r.at; });
  for (std::size_t k = 1; k < cuts.size(); ++k)
    if (cuts[k].at == cuts[k - 1].at)
      throw std::invalid_argument("json edge lists: \"" + *cuts[k].key + "\" is listed twice");
  std::string text;
  text.reserve(size);
  std::size_t from = 0;
  for (const Cut& c : cuts) {
    text.append(base, from, c.at - from);
    text += "\n  \"" + *c.key + "\": [\n";
    for (std::size_t k = 0; k < c.edges->size(); ++k) {
      const EdgeObject& e = (*c.edges)[k];
      if (k > 0) text += ",\n";
      text += "    {\n      \"a\": ";
      appendInt(text, e.a);
      text += ",\n      \"b\": ";
      appendInt(text, e.b);
      text += ",\n      \"cell\": ";
      appendInt(text, e.cell);
      if (e.method) {
        text += ",\n      \"method\": \"";
        text += e.method;
        text += '"';
      }
      text += "\n    }";
    }
    text += "\n  ]";
    from = c.at + c.length;
  }
  text.append(base, from, std::string::npos);
  return text;
}

}  // namespace xsect

// graph.json's edge lists written as text (io/json_edge_lists.h) are the bytes nlohmann's dump(2)
// gives for the same document built as ordered values: random documents with empty and non-empty
// lists, with and without "method", negative cells, lists named in another order than the
// document's; a key that is not an empty top-level array, or is named twice, is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "io/json_edge_lists.h"

using namespace xsect;
using ordered = nlohmann::ordered_json;

TEST(JsonEdgeLists, AreTheBytesOfDumpTwo) {
  std::mt19937 rng(5);
  const char* methods[] = {"nearest_plane", "section_voronoi", "delaunay"};
  for (int trial = 0; trial < 40; ++trial) {
    ordered doc = {{"method", "delaunay"}, {"cells", trial}, {"sample_spacing_mm", 0.1 * trial + 0.05},
                {"nodes", ordered::array()}, {"edges", ordered::array()}};
    for (int n = 0; n < trial % 4; ++n)
      doc["nodes"].push_back({{"id", n}, {"slice", n}, {"centroid_mm", {0.5, -1.25, 3.0}}});
    const bool second = trial % 2 == 1;
    if (second) doc["delaunay_connections"] = ordered::array();
    ordered full = doc;
    std::vector<std::pair<std::string, std::vector<EdgeObject>>> lists{{"edges", {}}};
    if (second) lists.push_back({"delaunay_connections", {}});
    for (auto& [key, edges] : lists) {
      const int count = std::uniform_int_distribution<int>(0, 5)(rng) * (trial % 3 != 0);
      for (int k = 0; k < count; ++k) {
        EdgeObject e{std::uniform_int_distribution<int>(0, 3000)(rng), std::uniform_int_distribution<int>(0, 3000)(rng),
                     std::uniform_int_distribution<int>(-1, 90000)(rng), key == "edges" ? methods[k % 3] : nullptr};
        edges.push_back(e);
        ordered o = {{"a", e.a}, {"b", e.b}, {"cell", e.cell}};
        if (e.method) o["method"] = e.method;
        full[key].push_back(o);
      }
    }
    if (trial % 4 == 3) std::reverse(lists.begin(), lists.end());  // lists named out of the document's order
    EXPECT_EQ(jsonWithEdgeLists(doc, lists), full.dump(2) + "\n") << "trial " << trial;
  }
  const ordered doc = {{"edges", ordered::array({1})}, {"nodes", ordered::array()}};
  EXPECT_THROW(jsonWithEdgeLists(doc, {{"edges", {}}}), std::invalid_argument);
  EXPECT_THROW(jsonWithEdgeLists(doc, {{"missing", {}}}), std::invalid_argument);
  const ordered twice = {{"edges", ordered::array()}};
  EXPECT_THROW(jsonWithEdgeLists(twice, {{"edges", {EdgeObject{1, 2, 3}}}, {"edges", {EdgeObject{4, 5, 6}}}}),
               std::invalid_argument);
}

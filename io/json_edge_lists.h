// graph.json's edge lists as text (pipeline/run_outputs.cpp): the bytes nlohmann's dump(2) writes
// for a document whose top-level keys hold arrays of edge objects {"a", "b", "cell"[, "method"]},
// without a json value per edge. Why: multiaxial-3x40 with method 3 lists 255 000 edges; building
// them as json values and dumping took 0.8 s of the run's 1.4 s of writing, this takes 0.05 s.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

namespace xsect {

struct EdgeObject {
  int a = 0, b = 0, cell = -1;
  const char* method = nullptr;  ///< written as "method" when not null (a static string)
};

/// dump(2) of `doc` (a JSON object) with each listed top-level key's value, an empty array in
/// `doc`, replaced by the objects given for it, plus a final newline.
/// Throws std::invalid_argument when a listed key is not a top-level empty array of `doc`.
std::string jsonWithEdgeLists(const nlohmann::ordered_json& doc,
                              const std::vector<std::pair<std::string, std::vector<EdgeObject>>>& lists);

}  // namespace xsect

// report.html's "Topology control" section (issue 51): what reconstruction.topology asked, the
// Betti numbers before and after, and each change of a cell (a join cut, halved or added: its
// sections, its cell, where, its size), read from report.json's `topology` block.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace xsect {

/// Empty when report.json has no `topology` block (reconstruction.topology free).
std::string topologyChangesHtml(const nlohmann::ordered_json& report);

}  // namespace xsect

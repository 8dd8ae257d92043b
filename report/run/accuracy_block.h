// report.html's accuracy block (issue 21: "`xsect eval` adds its metrics to a report beside the
// mesh when one exists"): eval.json's figures as a table, and the page beside an evaluated mesh
// updated in place.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace xsect {

/// The evaluation's main figures (distances, overlap, topology against the truth's) as HTML.
std::string accuracyHtml(const nlohmann::ordered_json& eval);

/// When `mesh_path` is a run's mesh.<fmt> and its folder holds a report.html of this version,
/// rewrites the page's accuracy block with `eval` (atomically). Returns whether it did.
bool addAccuracyToReportPage(const std::filesystem::path& mesh_path, const nlohmann::ordered_json& eval);

}  // namespace xsect

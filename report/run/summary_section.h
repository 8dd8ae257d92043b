// report.html's figures from report.json (issue 21: "the page is built from the same data as
// report.json"): the headline (verdict, Betti numbers, mesh size, slices used), the summary table,
// and the timings and peak memory per stage.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace xsect {

/// The headline; its figures carry ids (verdict, betti, mesh-triangles, slices-used) for tests.
std::string headlineHtml(const nlohmann::ordered_json& report);

/// The summary: input, reconstruction, topology, sampling (with `sampling_line`, the run's stderr
/// line about it), conformity and the connectivity graph.
std::string summaryHtml(const nlohmann::ordered_json& report, const std::string& sampling_line);

/// The timings (s) and peak memory (MB) of each stage.
std::string timingsHtml(const nlohmann::ordered_json& report);

}  // namespace xsect

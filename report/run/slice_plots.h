// report.html's per-slice plots (issue 21), from conformity.json's rows (stage 3): the slices'
// disagreement with those they cross before and after enforcement, pose corrections with their
// uncertainty and the gaps at the crossings they close, pose changes from smoothing, and the
// flagged and dropped slices marked on each.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace xsect {

/// The plots as inline SVG (report/charts/svg_chart.h), with a short line before each saying what it shows.
/// @param conformity  conformity.json's content.
std::string slicePlotsHtml(const nlohmann::ordered_json& conformity);

}  // namespace xsect

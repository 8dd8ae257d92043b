// report.html of `xsect run` (issue 21): the page's parts built from the run's results and from
// the same JSON the run writes (report.json, conformity.json, graph.json), so that the page and the
// files agree by construction.
#pragma once

#include <nlohmann/json.hpp>

#include "io/report_page/report_page.h"
#include "pipeline/run_outputs.h"

namespace xsect {

/// The page of a run. @param report, conformity, graph  the content of report.json,
/// conformity.json and graph.json.
ReportPage runReportPage(const RunResults& r, const nlohmann::ordered_json& report,
                         const nlohmann::ordered_json& conformity, const nlohmann::ordered_json& graph);

}  // namespace xsect

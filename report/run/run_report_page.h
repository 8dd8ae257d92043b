// report.html of `xsect run` (issue 21): the page's parts built from the run's results and from
// the same JSON the run writes (report.json, conformity.json; graph.json's nodes and the method's
// edges as the writer lists them), so that the page and the files agree by construction.
#pragma once

#include <nlohmann/json.hpp>

#include "report/page/report_page.h"
#include "report/run/section_graph.h"
#include "pipeline/run_outputs.h"

namespace xsect {

/// The page of a run. @param report, conformity  the content of report.json and conformity.json;
/// @param graph  graph.json's nodes and the method's edges (sectionGraph, run_outputs.h).
ReportPage runReportPage(const RunResults& r, const nlohmann::ordered_json& report,
                         const nlohmann::ordered_json& conformity, const SectionGraph& graph);

}  // namespace xsect

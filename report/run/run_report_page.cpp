// report.html of `xsect run` (see run_report_page.h).
#include "report/run/run_report_page.h"

#include <filesystem>

#include "report/run/frame_overlays.h"
#include "report/run/section_graph.h"
#include "report/run/slice_plots.h"
#include "report/run/summary_section.h"
#include "report/run/topology_changes.h"
#include "report/run/view_data.h"
#include "report/run/warning_advice.h"

namespace xsect {

using json = nlohmann::ordered_json;

ReportPage runReportPage(const RunResults& r, const json& report, const json& conformity, const SectionGraph& graph) {
  ReportPage page;
  page.title = "xsect: " + std::filesystem::path(r.inputs.config.path).filename().string() + " (" +
               std::filesystem::path(r.inputs.config.input_path).filename().string() + ")";
  page.headline_html = headlineHtml(report);
  page.view_json = viewDataJson(r).dump();
  page.sections.push_back({"summary", "Summary", summaryHtml(report, samplingLine(r.sampling))});
  page.sections.push_back({"warnings", "Warnings", warningsHtml(runWarnings(r))});
  page.sections.push_back({"slice-plots", "Slices", "<div class=\"plots\">\n" + slicePlotsHtml(conformity) + "</div>"});
  page.sections.push_back({"graph", "How the sections connect", sectionGraphHtml(graph)});
  if (const std::string changes = topologyChangesHtml(report); !changes.empty())
    page.sections.push_back({"topology", "Topology control", changes});
  page.sections.push_back({"frames", "Frames", frameOverlaysHtml(r.inputs)});
  // Timings and memory change from run to run: the one block of the page that does (tests and
  // scripts/output_hashes.py drop what lies between the markers before comparing pages).
  page.sections.push_back({"timings", "Time and memory",
                        "<!--xsect-unrepeatable-begin-->\n" + timingsHtml(report) + "<!--xsect-unrepeatable-end-->"});
  return page;
}

}  // namespace xsect

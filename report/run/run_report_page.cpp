// report.html of `xsect run` (see run_report_page.h).
#include "report/run/run_report_page.h"

#include <filesystem>

#include "geometry/core/reconstruction_method.h"

#include "report/run/frame_overlays.h"
#include "report/run/page_text.h"
#include "report/run/section_graph.h"
#include "report/run/slice_plots.h"
#include "report/run/summary_section.h"
#include "report/run/topology_changes.h"
#include "report/run/view_data.h"
#include "report/run/warning_advice.h"

namespace xsect {

using json = nlohmann::ordered_json;

namespace {

/// What the input is called: its file's name without the extension, or its folder's name when the
/// file's says nothing ("slices.yaml", "config.yaml", "input.csl", "sequence.igs.mha").
std::string inputName(const RunConfig& c) {
  const std::filesystem::path input(c.input_path);
  std::string stem = input.filename().string();
  stem = stem.substr(0, stem.find('.'));
  for (const char* generic : {"slices", "config", "input", "sequence", "recording", "contours", "frames"})
    if (stem == generic) {
      const std::string folder = input.parent_path().filename().string();
      return folder.empty() ? stem : folder;
    }
  return stem;
}

}  // namespace

ReportPage runReportPage(const RunResults& r, const json& report, const json& conformity, const SectionGraph& graph) {
  ReportPage page;
  const RunConfig& c = r.inputs.config;
  page.title = inputName(c) + " — reconstructed by xsect, method " +
               std::to_string(methodNumber(c.reconstruction_method)) + " (" +
               nameOf(kReconstructionMethods, c.reconstruction_method) + ")";
  page.headline_html = headlineHtml(report);
  page.headline_note = field(report, {"in_plain_words"}).is_string() ? field(report, {"in_plain_words"}).get<std::string>() : "";
  page.view_json = viewDataJson(r).dump();
  // Sections with nothing to show are left out (no empty plot, no "nothing here" paragraph).
  const auto add = [&](const char* id, const char* title, const std::string& html) {
    if (!html.empty()) page.sections.push_back({id, title, html});
  };
  add("summary", "Summary", summaryHtml(report, samplingLine(r.sampling)));
  add("warnings", "Warnings", warningsHtml(runWarnings(r)));
  if (const std::string plots = slicePlotsHtml(conformity); !plots.empty())
    add("slice-plots", "Slices", "<div class=\"plots\">\n" + plots + "</div>");
  add("graph", "How the sections connect", sectionGraphHtml(graph));
  add("topology", "Topology control", topologyChangesHtml(report));
  add("frames", "Frames", frameOverlaysHtml(r.inputs));
  // Timings and memory change from run to run: the one block of the page that does (tests and
  // scripts/output_hashes.py drop what lies between the markers before comparing pages).
  page.sections.push_back({"timings", "Time and memory",
                        "<!--xsect-unrepeatable-begin-->\n" + timingsHtml(report) + "<!--xsect-unrepeatable-end-->"});
  return page;
}

}  // namespace xsect

// The accuracy block of report.html (see accuracy_block.h).
#include "report/run/accuracy_block.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "report/page/report_page.h"
#include "io/text_file.h"
#include "report/run/page_text.h"

namespace xsect {

using json = nlohmann::ordered_json;

std::string accuracyHtml(const json& eval) {
  struct Row {
    const char* key;
    const char* name;
    const char* unit;
  };
  static constexpr Row kRows[] = {
      {"hausdorff_mm", "Hausdorff distance", " mm"},
      {"mean_distance_mm", "mean surface distance", " mm"},
      {"mesh_to_truth_max_mm", "mesh to truth, max", " mm"},
      {"truth_to_mesh_max_mm", "truth to mesh, max", " mm"},
      {"dice", "Dice", ""},
      {"iou", "IoU", ""},
      {"betti", "Betti numbers of the mesh", ""},
      {"truth_betti", "Betti numbers of the truth", ""},
      {"watertight", "watertight", ""},
      {"conformity_iou_min", "worst slice IoU against its sections", ""},
  };
  const std::string against = eval.contains("truth") ? "truth " + cellText(eval["truth"])
                                                     : "reference " + cellText(field(eval, {"reference"}));
  std::string html = "<p>xsect eval of " + cellText(field(eval, {"mesh"})) + " against the " + against + ":</p>\n<table id=\"accuracy-table\">\n";
  for (const Row& r : kRows)
    if (eval.contains(r.key) && !eval[r.key].is_null())
      html += "<tr><th>" + std::string(r.name) + "</th><td class=\"num\" data-key=\"" + r.key + "\">" + cellText(eval[r.key]) +
              r.unit + "</td></tr>\n";
  return html + "</table>\n";
}

bool addAccuracyToReportPage(const std::filesystem::path& meshPath, const json& eval) {
  // Only the run's mesh.<fmt> is the page's mesh (not mesh_unsmoothed or a material's).
  if (meshPath.stem() != "mesh") return false;
  const std::filesystem::path page = meshPath.parent_path() / "report.html";
  std::ifstream in(page, std::ios::binary);
  if (!in) return false;
  std::stringstream text;
  text << in.rdbuf();
  std::string updated;
  try {
    updated = withReportPageEval(text.str(), accuracyHtml(eval));
  } catch (const std::invalid_argument&) {
    return false;  // another kind of page
  }
  writeTextFileAtomically(page.string(), updated);
  return true;
}

}  // namespace xsect

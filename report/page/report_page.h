// report.html (issue 21): one self-contained page, working offline from file://, that shows a run
// of `xsect run`: an interactive 3D view of the mesh with the input slices and their contours
// (three.js, inlined), and sections of HTML the pipeline builds (summary, warnings, plots, graph,
// frames, timings). `xsect eval` later fills the page's accuracy block in place.
//
// The page's script (report_page.js) reads the view's data from a JSON block and, once the view has
// drawn, sets on <body>: data-view-ready="1", data-canvas-rect="X Y W H" (CSS pixels),
// data-background="#rrggbb"; data-errors counts script errors (0 when none). Opened as
// report.html#mesh-only, the view starts with the slices and contours hidden.
#pragma once

#include <string>
#include <vector>

namespace xsect {

/// One section of the page: <section id=ID><h2>TITLE</h2>HTML</section>.
struct ReportPageSection {
  std::string id;
  std::string title;
  std::string html;  ///< trusted HTML built by the caller (texts escaped with htmlEscape)
};

struct ReportPage {
  std::string title;                      ///< the document's title (plain text)
  std::string headline_html;              ///< shown under the title
  std::string headline_note;              ///< one plain sentence under the headline (plain text)
  std::string view_json;                  ///< the 3D view's data (report_page.js); empty: no view
  std::vector<ReportPageSection> sections;  ///< below the 3D view, in order
  std::string eval_html;                  ///< the accuracy block (xsect eval); a hint when empty
};

/// Text escaped for HTML element content and attribute values.
std::string htmlEscape(const std::string& text);

/// The page as one HTML document (UTF-8).
std::string reportPageHtml(const ReportPage& page);

/// `html` with its accuracy block replaced by `eval_html`. Throws std::invalid_argument when the
/// text holds no accuracy block (not a page of this version).
std::string withReportPageEval(const std::string& html, const std::string& eval_html);

}  // namespace xsect

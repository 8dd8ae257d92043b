// report.html as text (see report_page.h): the document skeleton with its inlined scripts.
#include "report/page/report_page.h"

#include <stdexcept>

#include "report/page/report_assets.h"

namespace xsect {

namespace {

constexpr const char* kEvalBegin = "<!--xsect-eval-begin-->";
constexpr const char* kEvalEnd = "<!--xsect-eval-end-->";

/// Text that may sit inside <script>: "</" becomes "<\/" (the same string in JSON and in
/// JavaScript string literals; the assets hold no "</script" outside strings).
std::string scriptSafe(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    out += text[i];
    if (text[i] == '<' && i + 1 < text.size() && text[i + 1] == '/') out += '\\';
  }
  return out;
}

std::string sectionHtml(const ReportPageSection& s) {
  return "<section id=\"" + htmlEscape(s.id) + "\">\n<h2>" + htmlEscape(s.title) + "</h2>\n" + s.html + "\n</section>\n";
}

std::string evalBlock(const std::string& evalHtml) {
  return std::string(kEvalBegin) +
         (evalHtml.empty() ? "<p class=\"hint\">No accuracy yet: <code>xsect eval --mesh mesh.ply --truth TRUTH</code> "
                             "(or <code>--reference MESH</code>) adds it to this page.</p>"
                           : evalHtml) +
         kEvalEnd;
}

}  // namespace

std::string htmlEscape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  return out;
}

std::string reportPageHtml(const ReportPage& page) {
  std::string html = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
                     "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>" +
                     htmlEscape(page.title) + "</title>\n<style>\n" + reportAsset("page_style") + "\n</style>\n";
  // The error counter comes first, so that it sees every later script's errors.
  html += "<script>\n(function(){var n=0;function bump(){n++;if(document.body)document.body.setAttribute('data-errors',String(n));}"
          "window.addEventListener('error',bump);window.addEventListener('unhandledrejection',bump);"
          "var e=console.error;console.error=function(){bump();return e.apply(console,arguments);};"
          "window.xsectErrors=function(){return n;};})();\n</script>\n</head>\n<body data-errors=\"0\">\n";
  html += "<header>\n<h1>" + htmlEscape(page.title) + "</h1>\n<p class=\"headline\">" + page.headline_html + "</p>\n" +
          (page.headline_note.empty() ? std::string()
                                      : "<p class=\"meaning\" id=\"verdict-meaning\">" + htmlEscape(page.headline_note) + "</p>\n") +
          "</header>\n<main>\n";
  if (!page.view_json.empty()) {
    html += "<section id=\"view\">\n<h2>Shape and slices</h2>\n"
            "<div class=\"view-controls\">colour <select id=\"view-colour\">"
            "<option value=\"uniform\">uniform</option><option value=\"sampling\">sampling verdict</option>"
            "<option value=\"material\">material</option></select>\n"
            "slices <select id=\"view-slices\"><option value=\"few\">a few</option><option value=\"all\">all</option>"
            "<option value=\"none\">none</option></select>\n"
            "<label><input type=\"checkbox\" id=\"view-contours\" checked> contours</label>\n"
            "<label><input type=\"checkbox\" id=\"view-mesh\" checked> mesh</label>\n"
            "<span id=\"view-legend\"></span></div>\n"
            "<canvas id=\"view-canvas\" width=\"1200\" height=\"600\"></canvas>\n"
            "<p id=\"view-note\" class=\"hint\"></p>\n</section>\n";
  }
  for (const ReportPageSection& s : page.sections) html += sectionHtml(s);
  html += "<section id=\"accuracy\">\n<h2>Accuracy</h2>\n" + evalBlock(page.eval_html) + "\n</section>\n</main>\n";
  if (!page.view_json.empty()) {
    html += "<script type=\"application/json\" id=\"view-data\">" + scriptSafe(page.view_json) + "</script>\n";
    html += "<script>\n" + scriptSafe(reportAsset("three")) + "\n</script>\n";
    html += "<script>\n" + scriptSafe(reportAsset("orbit_controls")) + "\n</script>\n";
    html += "<script>\n" + scriptSafe(reportAsset("page_script")) + "\n</script>\n";
  }
  return html + "</body>\n</html>\n";
}

std::string withReportPageEval(const std::string& html, const std::string& evalHtml) {
  const std::size_t begin = html.find(kEvalBegin);
  const std::size_t end = begin == std::string::npos ? std::string::npos : html.find(kEvalEnd, begin);
  if (end == std::string::npos) throw std::invalid_argument("no accuracy block (not an xsect report page)");
  return html.substr(0, begin) + evalBlock(evalHtml) + html.substr(end + std::string(kEvalEnd).size());
}

}  // namespace xsect

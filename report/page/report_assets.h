// The report page's scripts and style, compiled into the library (report/page/embed_assets.cmake)
// so that report.html is self-contained and works offline: three.js and its OrbitControls from
// Debian's libjs-three, and the page's own script and style sheet (report/page/report_page.js,
// report_page.css).
#pragma once

#include <string>

namespace xsect {

/// The bytes of the asset `name`: "three" (three.min.js), "orbit_controls" (OrbitControls.js),
/// "page_script" (report_page.js), "page_style" (report_page.css). Throws std::invalid_argument
/// for any other name.
std::string reportAsset(const std::string& name);

}  // namespace xsect

// Graphviz's `dot` (Debian graphviz) run on a graph in its DOT language, giving SVG to inline in
// report.html (the sections' connectivity graph, issue 21).
#pragma once

#include <optional>
#include <string>

namespace xsect {

/// The SVG that `dot -Tsvg` draws for `dot_text` (the XML declaration and DOCTYPE removed, so
/// that it can sit inside HTML); std::nullopt when `dot` is not installed, fails, or takes longer
/// than `timeout_s` seconds (the caller shows a fallback).
std::optional<std::string> graphvizSvg(const std::string& dot_text, double timeout_s = 20.0);

}  // namespace xsect

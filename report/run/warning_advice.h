// The run's warnings in plain words, each with what to do about it (report.html, issue 21).
#pragma once

#include <string>
#include <vector>

namespace xsect {

struct WarningAdvice {
  std::string warning;  ///< as the run printed it
  std::string meaning;  ///< what it says, in plain words (empty when the warning says it already)
  std::string action;   ///< what to do about it (empty when nothing needs doing)
};

/// The advice for one warning of `xsect run` (matched on the wording of the stage that emits it).
WarningAdvice warningAdvice(const std::string& warning);

/// The warnings as an HTML list (texts escaped), or a line saying there were none.
std::string warningsHtml(const std::vector<std::string>& warnings);

}  // namespace xsect

// One plain sentence of what a run's sampling verdict and topology confidence mean for its result
// (docs/outputs.md, "The verdict and the confidence, in plain words"): whether the thesis'
// sampling conditions (ch. 1 §2.3, §4.4-4.5; ch. 2 §3) prove the result's topology, and when they
// do not, how far the result's own features are to be trusted and what would settle it. Stored in
// report.json `in_plain_words`, printed at the end of `xsect run`, under report.html's headline and
// by scripts/demo.sh.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace xsect {

/// @param report report.json of the run (sampling, topology.confidence, betti)
std::string verdictSentence(const nlohmann::ordered_json& report);

}  // namespace xsect

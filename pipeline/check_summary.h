// The few lines `xsect check` prints by default (docs/commands.md): whether the configuration is
// valid, what the input holds, the grid, the estimated memory and time, the sampling verdict and
// the warnings. `xsect check --json` prints the whole diagnosis these lines are taken from.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace xsect {

/// @param check        the diagnosis `xsect check --json` prints
/// @param samplingLine the sampling verdict as `xsect run` ends with it ("" without sections)
std::string checkSummary(const nlohmann::ordered_json& check, const std::string& samplingLine);

}  // namespace xsect

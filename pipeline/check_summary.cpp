// `xsect check`'s summary (see check_summary.h).
#include "pipeline/check_summary.h"

#include <cmath>
#include <sstream>

#include "pipeline/json_values.h"

namespace xsect {

namespace {

/// A duration in the unit a reader takes in at a glance.
std::string duration(double seconds) {
  if (seconds < 90) return fixedText(seconds, seconds < 10 ? 1 : 0) + " s";
  if (seconds < 5400) return fixedText(seconds / 60, 0) + " min";
  return fixedText(seconds / 3600, 1) + " h";
}

}  // namespace

std::string checkSummary(const nlohmann::ordered_json& r, const std::string& samplingLine) {
  std::ostringstream s;
  s << r["config"].get<std::string>() << ": valid\n";
  const auto& counts = r["counts"];
  s << "input: " << counts["slices"].get<int>() << " slices, " << counts["sections"].get<int>() << " sections";
  if (r.contains("plus_sequence")) {
    const auto& p = r["plus_sequence"];
    if (p.contains("frames") && p.contains("frames_used"))
      s << " (" << p["frames_used"].get<long>() << " of " << p["frames"].get<long>() << " frames of the recording)";
  }
  s << "\n";
  if (r.contains("grid_dims")) {
    const auto& v = r["voxel_size"];
    const auto& d = r["grid_dims"];
    s << "grid: " << fixedText(v["voxel_size_mm"].get<double>(), 4) << " mm voxels ("
      << (v["auto"].get<bool>() ? "auto, limited by " + v["limited_by"].get<std::string>() : std::string("configured"))
      << "), " << d[0].get<long>() << " x " << d[1].get<long>() << " x " << d[2].get<long>() << "\n";
    s << "estimated: " << fixedText(r["estimated_memory_mb"].get<double>(), 0) << " MB, "
      << duration(r["estimated_seconds"].get<double>()) << "\n";
  }
  if (!samplingLine.empty()) s << samplingLine << "\n";
  const auto& warnings = r["warnings"];
  if (!warnings.empty()) {
    s << "warnings (" << warnings.size() << "):\n";
    for (const auto& w : warnings) s << "  - " << w.get<std::string>() << "\n";
  }
  s << "the whole diagnosis: xsect check " << r["config"].get<std::string>() << " --json\n";
  return s.str();
}

}  // namespace xsect

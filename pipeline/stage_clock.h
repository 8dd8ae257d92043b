// Wall time and peak memory at the end of each stage of `xsect run` (report.json "timings_s",
// "peak_memory_mb"; scripts/bench.sh reads them).
#pragma once

#include <sys/resource.h>

#include <chrono>
#include <nlohmann/json.hpp>
#include <string>

namespace xsect {

/// This process's peak resident memory so far, MB.
inline double peakMemoryMb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_maxrss) / 1024.0;
}

class StageClock {
 public:
  /// Records the time since the previous stage ended (or the clock was made) under `stage`.
  void end(const std::string& stage) {
    const auto now = std::chrono::steady_clock::now();
    timings[stage] = std::chrono::duration<double>(now - last_).count();
    memory[stage] = peakMemoryMb();
    last_ = now;
  }
  /// The sum of the stages' times, s.
  double total() const {
    double t = 0;
    for (auto& [k, v] : timings.items()) t += v.get<double>();
    return t;
  }
  nlohmann::ordered_json timings = nlohmann::ordered_json::object(), memory = nlohmann::ordered_json::object();

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace xsect

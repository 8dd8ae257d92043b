// Progress of the long stages on stderr (issue 21), silenced by --quiet. Every stage ends with one
// line: "[segment] 400 frames in 2.1 s" when it counted its work, "[scene] done in 0.1 s" otherwise.
// On a terminal, a stage that reports how far it is also shows until then a bar rewritten in place,
//   [segment] [#########-----------]  120/400 frames  0:03 left
// ("42%" instead of the counts when only a fraction is known), redrawn at most ten times a second
// and only when its text changes. Elsewhere (logs, CI) nothing is written between those lines.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <mutex>
#include <string>

namespace xsect {

class Progress {
 public:
  /// Writes to stderr; the bar only when stderr is a terminal.
  explicit Progress(bool quiet);
  /// Writes to `out`; the bar when `terminal` says so (tests).
  Progress(bool quiet, bool terminal, std::FILE* out);
  /// Ends the current stage, except while an exception unwinds (the stage did not end): then only
  /// the bar's line is ended, so that the error message starts a line of its own.
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// Ends the current stage and starts `name`, whose work is counted in `unit` ("frames", "pairs",
  /// "blocks"; empty when only fractions are reported).
  void stage(const std::string& name, const std::string& unit = "");
  /// `done` of the stage's `total` units of work are done. Callable from any thread, concurrently
  /// (TBB workers): it never waits, the thread that finds the terminal free redraws. A second pass
  /// over the work just reports from 0 again.
  void update(std::int64_t done, std::int64_t total);
  /// The fraction of the stage's work done, in [0, 1]: the bar shows a percentage. Same threads.
  void update(double fraction);
  /// update(done, total) as a callback, for the `progress` parameters of geometry and stages.
  std::function<void(std::int64_t, std::int64_t)> counter();
  /// Ends the current stage and writes `text` on a line of its own.
  void note(const std::string& text);
  /// Ends the current stage: its line. stage(), note() and finish() are called by the thread that
  /// runs the stages, between parallel loops.
  void finish();
  /// Whether nothing is written (--quiet).
  bool quiet() const { return quiet_; }
  /// Also tells `listener` the name of every stage as it starts, whether quiet or not (the Python
  /// module's progress= callback), from the thread that calls stage().
  void onStage(std::function<void(const std::string&)> listener) { listener_ = std::move(listener); }

 private:
  using Clock = std::chrono::steady_clock;
  void redraw();
  std::string barLine(double elapsed_s) const;

  const bool quiet_, terminal_;
  std::FILE* const out_;
  std::mutex draw_;                         ///< held while a line is composed and written
  bool open_ = false;
  std::string name_, unit_;
  Clock::time_point start_ = Clock::now();
  std::atomic<std::int64_t> done_{0}, total_{0};
  std::atomic<bool> counted_{false};        ///< counts reported (else fractions, or nothing)
  std::atomic<std::int64_t> last_draw_ns_{0};  ///< since start_
  std::string drawn_;                       ///< the bar on screen (empty: none)
  std::function<void(const std::string&)> listener_;
};

}  // namespace xsect

// Progress lines and bars on stderr (see progress.h).
#include "pipeline/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <exception>

namespace xsect {
namespace {

/// At most ten redraws a second: more is flicker on a terminal and lost time on a slow one.
constexpr std::int64_t kRedrawNs = 100'000'000;
constexpr int kBarWidth = 20;
/// The time left is shown once the stage has run this long: an estimate from less is noise.
constexpr double kEstimateAfterS = 0.5;
/// update(fraction) in counts of this many.
constexpr std::int64_t kFractionScale = 1000;

/// "0:03", "12:34", "1:02:03".
std::string clockText(double seconds) {
  const long long s = std::llround(std::max(0.0, seconds));
  char text[32];
  if (s >= 3600)
    std::snprintf(text, sizeof text, "%lld:%02lld:%02lld", s / 3600, s / 60 % 60, s % 60);
  else
    std::snprintf(text, sizeof text, "%lld:%02lld", s / 60, s % 60);
  return text;
}

/// "0.04 s", "2.1 s".
std::string secondsText(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, seconds < 1 ? "%.2f s" : "%.1f s", seconds);
  return text;
}

}  // namespace

Progress::Progress(bool quiet) : Progress(quiet, ::isatty(2) != 0, stderr) {}

Progress::Progress(bool quiet, bool terminal, std::FILE* out) : quiet_(quiet), terminal_(terminal), out_(out) {}

Progress::~Progress() {
  if (std::uncaught_exceptions() == 0) {
    finish();
    return;
  }
  std::lock_guard<std::mutex> lock(draw_);
  if (open_ && !quiet_ && !drawn_.empty()) {
    std::fputs("\n", out_);
    std::fflush(out_);
  }
  open_ = false;
}

void Progress::stage(const std::string& name, const std::string& unit) {
  finish();
  if (listener_) listener_(name);
  std::lock_guard<std::mutex> lock(draw_);
  open_ = true;
  name_ = name;
  unit_ = unit;
  start_ = Clock::now();
  done_ = 0;
  total_ = 0;
  counted_ = false;
  last_draw_ns_ = -kRedrawNs;  // the first update draws at once
  drawn_.clear();
}

void Progress::update(std::int64_t done, std::int64_t total) {
  if (quiet_) return;
  total_.store(total, std::memory_order_relaxed);
  done_.store(done, std::memory_order_relaxed);
  counted_.store(true, std::memory_order_relaxed);
  if (terminal_) redraw();
}

void Progress::update(double fraction) {
  if (quiet_) return;
  total_.store(kFractionScale, std::memory_order_relaxed);
  done_.store(std::llround(std::clamp(fraction, 0.0, 1.0) * kFractionScale), std::memory_order_relaxed);
  counted_.store(false, std::memory_order_relaxed);
  if (terminal_) redraw();
}

std::function<void(std::int64_t, std::int64_t)> Progress::counter() {
  return [this](std::int64_t done, std::int64_t total) { update(done, total); };
}

void Progress::redraw() {
  const auto since = [&] {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - start_).count();
  };
  if (since() - last_draw_ns_.load(std::memory_order_relaxed) < kRedrawNs) return;
  std::unique_lock<std::mutex> lock(draw_, std::try_to_lock);
  if (!lock.owns_lock() || !open_) return;  // another thread is drawing: it shows this update's state or newer
  const std::int64_t now = since();
  if (now - last_draw_ns_.load(std::memory_order_relaxed) < kRedrawNs) return;
  last_draw_ns_.store(now, std::memory_order_relaxed);
  std::string line = barLine(double(now) * 1e-9);
  if (line == drawn_) return;
  std::fputs(("\r" + line + "\033[K").c_str(), out_);
  std::fflush(out_);
  drawn_ = std::move(line);
}

std::string Progress::barLine(double elapsed_s) const {
  const std::int64_t total = std::max<std::int64_t>(0, total_.load(std::memory_order_relaxed));
  const std::int64_t done = std::clamp<std::int64_t>(done_.load(std::memory_order_relaxed), 0, total);
  const double fraction = total > 0 ? double(done) / double(total) : 0.0;
  const int filled = std::min(kBarWidth, int(fraction * kBarWidth));
  std::string line = "[" + name_ + "] [" + std::string(std::size_t(filled), '#') +
                     std::string(std::size_t(kBarWidth - filled), '-') + "]  ";
  char text[96];
  if (counted_.load(std::memory_order_relaxed)) {
    const int width = int(std::to_string(total).size());  // the line keeps its length
    std::snprintf(text, sizeof text, "%*lld/%lld", width, (long long)done, (long long)total);
    line += text;
    if (!unit_.empty()) line += " " + unit_;
  } else {
    std::snprintf(text, sizeof text, "%3d%%", int(total > 0 ? done * 100 / total : 0));
    line += text;
  }
  if (done > 0 && done < total && elapsed_s >= kEstimateAfterS)
    line += "  " + clockText(elapsed_s * double(total - done) / double(done)) + " left";
  return line;
}

void Progress::note(const std::string& text) {
  finish();
  if (quiet_) return;
  std::fprintf(out_, "%s\n", text.c_str());
  std::fflush(out_);
}

void Progress::finish() {
  std::lock_guard<std::mutex> lock(draw_);
  if (!open_) return;
  open_ = false;
  if (quiet_) return;
  const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
  const std::int64_t total = total_.load(std::memory_order_relaxed);
  std::string line = "[" + name_ + "] ";
  if (counted_.load(std::memory_order_relaxed) && total > 0)
    line += std::to_string(total) + (unit_.empty() ? "" : " " + unit_) + " in " + secondsText(elapsed);
  else
    line += "done in " + secondsText(elapsed);
  if (terminal_ && !drawn_.empty()) line = "\r" + line + "\033[K";
  std::fprintf(out_, "%s\n", line.c_str());
  std::fflush(out_);
  drawn_.clear();
}

}  // namespace xsect

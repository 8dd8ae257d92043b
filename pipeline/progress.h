// Progress of long stages on stderr ("[stage] 42%"), silenced by --quiet. On a terminal the
// percentage is rewritten in place; elsewhere (logs, CI) only one line per stage is written.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <string>

namespace xsect {

class Progress {
 public:
  explicit Progress(bool quiet) : quiet_(quiet), tty_(::isatty(2) != 0) {}
  void stage(const std::string& name) {
    finish();
    name_ = name;
    last_ = -1;
    if (!quiet_ && tty_) std::fprintf(stderr, "[%s] ...", name.c_str());
    open_ = true;
  }
  void update(double fraction) {
    const int pct = int(fraction * 100.0);
    if (quiet_ || !tty_ || pct == last_) return;
    last_ = pct;
    std::fprintf(stderr, "\r[%s] %3d%%", name_.c_str(), pct);
  }
  void note(const std::string& text) {
    finish();
    if (!quiet_) std::fprintf(stderr, "%s\n", text.c_str());
  }
  void finish() {
    if (open_ && !quiet_) std::fprintf(stderr, tty_ ? "\r[%s] done\n" : "[%s] done\n", name_.c_str());
    open_ = false;
  }
  ~Progress() { finish(); }

 private:
  bool quiet_, tty_;
  bool open_ = false;
  std::string name_;
  int last_ = -1;
};

}  // namespace xsect

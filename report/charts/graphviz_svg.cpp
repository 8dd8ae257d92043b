// Runs Graphviz's dot (see graphviz_svg.h): the graph written to a temporary file, dot started
// through coreutils' timeout with its output in another, both removed afterwards.
#include "report/charts/graphviz_svg.h"

#include <unistd.h>

#include <cstdio>
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace xsect {

namespace fs = std::filesystem;

namespace {

/// A fresh temporary folder, removed with its content when the object goes.
class TemporaryFolder {
 public:
  TemporaryFolder() {
    std::string pattern = (fs::temp_directory_path() / "xsect-dot-XXXXXX").string();
    if (::mkdtemp(pattern.data())) path_ = pattern;
  }
  ~TemporaryFolder() {
    std::error_code ec;
    if (!path_.empty()) fs::remove_all(path_, ec);
  }
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

std::string shellQuoted(const std::string& s) {
  std::string out = "'";
  for (const char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

std::optional<std::string> graphvizSvg(const std::string& dotText, double timeoutS) {
  const TemporaryFolder folder;
  if (folder.path().empty()) return std::nullopt;
  const fs::path in = folder.path() / "graph.dot", out = folder.path() / "graph.svg";
  {
    std::ofstream f(in, std::ios::binary);
    f << dotText;
    if (!f) return std::nullopt;
  }
  std::ostringstream seconds;
  seconds << std::max(1.0, timeoutS);
  const std::string command = "timeout " + seconds.str() + " dot -Tsvg -o " + shellQuoted(out.string()) + " " +
                              shellQuoted(in.string()) + " >/dev/null 2>&1";
  if (std::system(command.c_str()) != 0) return std::nullopt;
  std::ifstream f(out, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  std::string svg = ss.str();
  const std::size_t start = svg.find("<svg");
  if (start == std::string::npos) return std::nullopt;
  return svg.substr(start);
}

}  // namespace xsect

// Helpers for tests that run the xsect binary: temporary folders, exit codes, captured stdout and stderr.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace xsect::test {

inline std::filesystem::path freshDir(const std::string& tag) {
  std::string tmpl = (std::filesystem::temp_directory_path() / ("xsect-" + tag + "-XXXXXX")).string();
  if (!::mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
  return tmpl;
}

struct CliResult {
  int code = -1;
  std::string err;
  std::string out;
};

/// Runs `xsect ARGS`, stdout and stderr captured; with timeout_s > 0 it is killed after that
/// many seconds (exit code 124, coreutils' timeout).
inline CliResult runXsect(const std::string& args, int timeout_s = 0) {
  const auto folder = freshDir("stderr");
  const std::string cmd = (timeout_s > 0 ? "timeout " + std::to_string(timeout_s) + " " : std::string()) +
                          std::string(XSECT_BIN) + " " + args + " >" + (folder / "out.txt").string() + " 2>" +
                          (folder / "err.txt").string();
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  const auto read = [](const std::filesystem::path& p) {
    std::ifstream f(p);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
  };
  r.err = read(folder / "err.txt");
  r.out = read(folder / "out.txt");
  std::filesystem::remove_all(folder);
  return r;
}

/// The whole file as bytes.
inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void writeFile(const std::filesystem::path& p, const std::string& text) {
  std::filesystem::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

}  // namespace xsect::test

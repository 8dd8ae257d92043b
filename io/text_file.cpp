// Text file writers (see text_file.h).
#include "io/text_file.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace xsect {

namespace fs = std::filesystem;

void writeTextFile(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) throw std::runtime_error("cannot write " + path);
  f << text;
  f.close();
  if (!f) throw std::runtime_error("write failed: " + path);
}

void writeTextFileAtomically(const std::string& path, const std::string& text) {
  const fs::path target = fs::absolute(fs::path(path));
  if (!target.parent_path().empty()) fs::create_directories(target.parent_path());
  const fs::path tmp = target.parent_path() / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()));
  try {
    writeTextFile(tmp.string(), text);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  std::error_code ec;
  fs::rename(tmp, target, ec);
  if (ec) {
    const std::string why = ec.message();
    fs::remove(tmp, ec);
    throw std::runtime_error("cannot move " + tmp.string() + " to " + target.string() + ": " + why);
  }
}

}  // namespace xsect

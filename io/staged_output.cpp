// Staged output folder: write beside, rename into place (see staged_output.h).
#include "io/staged_output.h"

#include <atomic>
#include <chrono>
#include <system_error>
#include <unistd.h>

namespace xsect {
namespace fs = std::filesystem;

StagedOutput::StagedOutput(const fs::path& destination)
    : destination_(fs::absolute(destination).lexically_normal()) {
  if (destination_.filename().empty()) destination_ = destination_.parent_path();
  const fs::path parent = destination_.parent_path();
  fs::create_directories(parent);
  staging_ = parent / ("." + destination_.filename().string() + ".partial-" +
                       std::to_string(::getpid()));
  std::error_code ec;
  fs::remove_all(staging_, ec);
  fs::create_directories(staging_);
}

StagedOutput::~StagedOutput() {
  if (!committed_) {
    std::error_code ec;
    fs::remove_all(staging_, ec);
  }
}

void StagedOutput::commit() {
  std::error_code ec;
  if (fs::exists(destination_)) {
    const fs::path old = destination_.parent_path() /
                         ("." + destination_.filename().string() + ".old-" +
                          std::to_string(::getpid()));
    fs::remove_all(old, ec);
    fs::rename(destination_, old);
    fs::rename(staging_, destination_);
    fs::remove_all(old, ec);
  } else {
    fs::rename(staging_, destination_);
  }
  committed_ = true;
}

}  // namespace xsect

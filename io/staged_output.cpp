// Staged output folder: write beside, rename into place (see staged_output.h).
#include "io/staged_output.h"

#include <stdexcept>
#include <system_error>

namespace xsect {
namespace fs = std::filesystem;

StagedOutput::StagedOutput(const fs::path& destination, OutputGuard guard)
    : destination_(fs::absolute(destination).lexically_normal()), guard_(std::move(guard)) {
  if (destination_.filename().empty()) destination_ = destination_.parent_path();
  checkOutputDestination(destination_, guard_);
  const fs::path parent = destination_.parent_path();
  fs::create_directories(parent);
  removeStaleStaging(destination_);
  staging_ = parent / ("." + destination_.filename().string() + ".partial-" + stagingTag());
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
  if (!fs::exists(staging_ / kManifestName))
    throw std::logic_error("output folder " + destination_.string() + " committed without its " + kManifestName);
  checkOutputDestination(destination_, guard_);
  std::error_code ec;
  if (fs::exists(destination_)) {
    const fs::path old = destination_.parent_path() / ("." + destination_.filename().string() + ".old-" + stagingTag());
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

// An output folder that appears complete or not at all (docs/outputs.md: "never half written"), and only
// where xsect may write one (io/output_destination.h: never over a user's files or inputs).
// Files are written into a hidden staging folder beside the destination; commit() renames it into
// place (replacing an older output folder of xsect of the same name); destruction without
// commit() removes it. Staging folders that killed runs left beside the destination are removed
// when the next one starts.
#pragma once

#include <filesystem>
#include <string>

#include "io/output_destination.h"

namespace xsect {

class StagedOutput {
 public:
  /// Checks the destination against `guard` (InputError when xsect may not replace it), removes
  /// stale staging folders beside it, and creates this one's.
  StagedOutput(const std::filesystem::path& destination, OutputGuard guard);
  ~StagedOutput();
  StagedOutput(const StagedOutput&) = delete;
  StagedOutput& operator=(const StagedOutput&) = delete;

  /// Folder to write into until commit().
  const std::filesystem::path& dir() const { return staging_; }
  std::filesystem::path file(const std::string& name) const { return staging_ / name; }
  const std::filesystem::path& destination() const { return destination_; }
  /// Moves the staging folder to the destination, after checking the destination again (it may
  /// have changed while the files were written). The staging folder must hold its manifest.json.
  void commit();

 private:
  std::filesystem::path destination_, staging_;
  OutputGuard guard_;
  bool committed_ = false;
};

}  // namespace xsect

// An output folder that appears complete or not at all (GUIDE.md: "never half written").
// Files are written into a hidden staging folder beside the destination; commit() renames it into
// place (replacing an older folder of the same name); destruction without commit() removes it.
#pragma once

#include <filesystem>
#include <string>

namespace xsect {

class StagedOutput {
 public:
  explicit StagedOutput(const std::filesystem::path& destination);
  ~StagedOutput();
  StagedOutput(const StagedOutput&) = delete;
  StagedOutput& operator=(const StagedOutput&) = delete;

  /// Folder to write into until commit().
  const std::filesystem::path& dir() const { return staging_; }
  std::filesystem::path file(const std::string& name) const { return staging_ / name; }
  const std::filesystem::path& destination() const { return destination_; }
  /// Moves the staging folder to the destination.
  void commit();

 private:
  std::filesystem::path destination_, staging_;
  bool committed_ = false;
};

}  // namespace xsect

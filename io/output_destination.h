// Where an output folder of xsect may go (issue 48: never destroy a user's files). A destination
// is replaced only when it is absent, an empty folder, or a folder xsect wrote: one whose
// manifest.json says so (`"written_by": "xsect"`, or the manifests of earlier versions, which list
// their `outputs` beside the `libraries` they were built with) and which holds nothing, at any
// depth, that the manifest does not list (or that is not itself an output folder of xsect). Whatever the folder holds, it is refused when it is the current folder or one of
// its ancestors, when it holds one of the command's inputs (the input's own folder, an ancestor of
// it), and when it is a file. A refusal is an InputError naming the key the destination came
// from (`--out`, `output.dir`) and what to do.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace xsect {

/// Name of the marker file every output folder of xsect holds.
inline constexpr const char* kManifestName = "manifest.json";

/// The destination of an output folder, with what it must not touch.
struct OutputGuard {
  std::vector<std::string> inputs;  ///< files the command reads (none may lie in the destination)
  std::string file;                 ///< where the destination was given: a configuration file, or "command line"
  std::string key;                  ///< the key or option that gave it: "output.dir", "--out"
};

/// Throws InputError (guard.file, guard.key) unless `destination` may be replaced (see above).
/// Paths are compared after resolving symbolic links, so a link to the input's folder is refused.
void checkOutputDestination(const std::filesystem::path& destination, const OutputGuard& guard);

/// A single output file (`xsect eval --json`): refused when it is a folder or one of guard.inputs
/// (after resolving links); an existing other file is replaced, atomically.
void checkOutputFile(const std::filesystem::path& file, const OutputGuard& guard);

/// Whether `folder` is an output folder of xsect: its manifest.json is xsect's and every entry of
/// the folder is one the manifest lists (or the manifest itself). Never throws.
bool isXsectOutputFolder(const std::filesystem::path& folder);

/// Removes the staging folders (`.NAME.partial-HOST-PID`, `.NAME.old-HOST-PID`, and the
/// `.NAME.partial-PID` of earlier versions, taken as this host's) that runs of this host left
/// beside `destination` when they were killed: those whose process no longer exists. Folders of
/// live processes and of other hosts (a shared file system) are left alone. When the destination
/// is absent, an `.old-` folder (the previous output, moved aside by a run killed before it put its
/// own in place) is renamed back instead. Never throws.
void removeStaleStaging(const std::filesystem::path& destination);

/// The suffix `HOST-PID` of this process' staging folders.
std::string stagingTag();

}  // namespace xsect

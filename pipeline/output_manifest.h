// manifest.json, the marker of every output folder of xsect (io/output_destination.h): which
// command wrote it, from which inputs (with their SHA-256), and the folder's entries, so that a
// later command may replace the folder and nothing else.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace xsect {

/// {"written_by": "xsect", "command", "xsect_version", "inputs": [{path, sha256}]}: the head of
/// every manifest; the command adds its own keys, then outputManifestText() lists the folder.
nlohmann::ordered_json manifestHead(const std::string& command, const std::vector<std::string>& inputs);

/// The manifest as written: `manifest` with "outputs", the sorted entries of `folder` at every depth
/// (relative paths, '/'-separated: "images/000.png"; the staging folder, written before the
/// manifest), and manifest.json itself.
std::string outputManifestText(nlohmann::ordered_json manifest, const std::filesystem::path& folder);

}  // namespace xsect

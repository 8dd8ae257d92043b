// manifest.json of the output folders (see output_manifest.h).
#include "pipeline/output_manifest.h"

#include <algorithm>

#include "io/file_hash.h"
#include "io/output_destination.h"

namespace xsect {

namespace fs = std::filesystem;

nlohmann::ordered_json manifestHead(const std::string& command, const std::vector<std::string>& inputs) {
  nlohmann::ordered_json m;
  m["written_by"] = "xsect";
  m["command"] = command;
  m["xsect_version"] = XSECT_VERSION;
  nlohmann::ordered_json files = nlohmann::ordered_json::array();
  for (const auto& f : inputs) files.push_back({{"path", f}, {"sha256", sha256File(f)}});
  m["inputs"] = files;
  return m;
}

std::string outputManifestText(nlohmann::ordered_json manifest, const fs::path& folder) {
  std::vector<std::string> names{kManifestName};
  for (const auto& e : fs::recursive_directory_iterator(folder))
    names.push_back(e.path().lexically_relative(folder).generic_string());
  std::sort(names.begin(), names.end());
  names.erase(std::unique(names.begin(), names.end()), names.end());
  manifest["outputs"] = names;
  return manifest.dump(2) + "\n";
}

}  // namespace xsect

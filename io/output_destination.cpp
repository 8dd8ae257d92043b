// Where an output folder of xsect may go (see output_destination.h).
#include "io/output_destination.h"

#include <nlohmann/json.hpp>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <system_error>

#include "io/input_error.h"

namespace xsect {

namespace fs = std::filesystem;

namespace {

/// The absolute, normal path without a trailing separator ("out/", "." name their folder).
fs::path plain(const fs::path& p) {
  std::error_code ec;
  fs::path a = fs::absolute(p, ec).lexically_normal();
  if (!a.has_filename() && a.has_parent_path() && a != a.root_path()) a = a.parent_path();
  return a;
}

/// The path with symbolic links resolved as far as it exists (never throws).
fs::path resolved(const fs::path& p) {
  std::error_code ec;
  fs::path r = fs::weakly_canonical(plain(p), ec);
  if (ec) return plain(p);
  return plain(r);
}

/// Whether `p` is `folder` or lies under it (component by component, both resolved).
bool within(const fs::path& p, const fs::path& folder) {
  auto a = folder.begin(), b = p.begin();
  for (; a != folder.end(); ++a, ++b) {
    if (a->empty()) continue;  // a trailing separator
    if (b == p.end() || *a != *b) return false;
  }
  return true;
}

/// The names an xsect manifest lists as its folder's outputs; false when `manifest` is not one.
bool manifestOutputs(const fs::path& manifest, std::set<std::string>* outputs) {
  std::ifstream f(manifest, std::ios::binary);
  if (!f) return false;
  std::ostringstream s;
  s << f.rdbuf();
  const nlohmann::json m = nlohmann::json::parse(s.str(), nullptr, false);
  if (!m.is_object()) return false;
  const bool marked = m.contains("written_by") && m["written_by"] == "xsect";
  const bool earlier = m.contains("libraries") && m.contains("config_sha256");  // before the marker
  if (!marked && !earlier) return false;
  if (m.contains("outputs") && m["outputs"].is_array())
    for (const auto& o : m["outputs"])
      if (o.is_string()) outputs->insert(o.get<std::string>());
  return true;
}

/// isXsectOutputFolder, with a depth bound on nested output folders (a run's `out` inside the
/// phantom folder it read). Every entry at any depth (relative path, '/'-separated) must be
/// listed, or lie in a nested output folder of xsect.
bool xsectFolder(const fs::path& folder, int depth, std::vector<std::string>* foreign) {
  std::set<std::string> listed;
  std::error_code ec;
  if (!fs::is_directory(folder, ec) || !manifestOutputs(folder / kManifestName, &listed)) return false;
  fs::recursive_directory_iterator it(folder, ec), end;
  for (; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().lexically_relative(folder).generic_string();
    if (name == kManifestName || listed.count(name)) continue;
    if (depth > 0 && it->is_directory(ec) && !it->is_symlink(ec) && xsectFolder(it->path(), depth - 1, nullptr)) {
      it.disable_recursion_pending();
      continue;
    }
    if (!foreign) return false;
    foreign->push_back(name);
    if (it->is_directory(ec)) it.disable_recursion_pending();
  }
  if (ec) return false;
  return !foreign || foreign->empty();
}

std::string hostName() {
  char host[256] = {};
  if (::gethostname(host, sizeof host - 1) != 0) return "host";
  std::string h(host);
  for (char& c : h)
    if (c == '/' || c == '.') c = '_';
  return h.empty() ? "host" : h;
}

bool processAlive(long pid) {
  if (pid <= 0) return true;  // not a process id: leave the folder alone
  return ::kill(pid_t(pid), 0) == 0 || errno == EPERM;
}

[[noreturn]] void refuse(const OutputGuard& g, const fs::path& destination, const std::string& why,
                         const std::string& fix) {
  throw InputError(g.file, g.key, destination.string() + " " + why + ": " + fix);
}

}  // namespace

bool isXsectOutputFolder(const fs::path& folder) { return xsectFolder(folder, 3, nullptr); }

std::string stagingTag() { return hostName() + "-" + std::to_string(::getpid()); }

void checkOutputDestination(const fs::path& destination, const OutputGuard& guard) {
  const fs::path given = plain(destination);
  const fs::path dest = resolved(destination);
  const std::string elsewhere = "name a folder that does not exist yet, e.g. " + given.string() + "_xsect";
  std::error_code ec;
  const fs::file_status link = fs::symlink_status(given, ec);
  if (fs::is_symlink(link))
    refuse(guard, given, "is a symbolic link (to " + dest.string() + ")",
           "xsect would replace the link; " + elsewhere);
  const fs::file_status st = fs::status(dest, ec);
  if (fs::exists(st) && !fs::is_directory(st))
    refuse(guard, given, "is an existing file, not a folder", "xsect writes a folder of outputs; " + elsewhere);
  // The folder it goes in: its nearest existing ancestor must be a folder xsect can write in.
  fs::path above = dest.parent_path();
  while (!above.empty() && !fs::exists(above, ec) && above != above.root_path()) above = above.parent_path();
  if (!above.empty() && !fs::is_directory(above, ec))
    refuse(guard, given, "lies under " + above.string() + ", which is a file", "name a folder elsewhere");
  if (!above.empty() && ::access(above.c_str(), W_OK | X_OK) != 0)
    refuse(guard, given, "cannot be written: " + above.string() + " is not writable", "name a folder you can write in");
  const fs::path cwd = resolved(fs::current_path(ec));
  if (within(cwd, dest))
    refuse(guard, given, dest == cwd ? "is the current folder" : "holds the current folder",
           "xsect replaces its output folder as a whole; " + elsewhere);
  // Inputs exist: an absent destination holds none. Otherwise each input is resolved through its
  // folder, resolved once per folder (a series of 2000 frames lies in one or two), and itself only
  // when it is a link.
  std::map<fs::path, fs::path> folders;
  for (const std::string& input : fs::exists(st) ? guard.inputs : std::vector<std::string>{}) {
    if (input.empty()) continue;
    const fs::path file = plain(input);
    fs::path in;
    if (fs::is_symlink(fs::symlink_status(file, ec))) {
      in = resolved(file);
    } else {
      auto [it, fresh] = folders.emplace(file.parent_path(), fs::path());
      if (fresh) it->second = resolved(file.parent_path());
      in = it->second / file.filename();
    }
    if (within(in, dest))
      refuse(guard, given,
             "holds the input " + in.string() + (in.parent_path() == dest ? " (it is the input's folder)" : ""),
             "xsect replaces its output folder as a whole and never touches its inputs; name a folder that holds no "
             "input, e.g. " + (given / "xsect_out").string());
  }
  if (!fs::is_directory(st) || fs::is_empty(dest, ec)) return;
  std::vector<std::string> foreign;
  if (!fs::exists(dest / kManifestName))
    refuse(guard, given, "is a folder xsect did not write (it has no " + std::string(kManifestName) + ")",
           "xsect only replaces its own output folders; " + elsewhere + ", or empty this one yourself");
  if (!xsectFolder(dest, 3, &foreign)) {
    std::string names;
    for (std::size_t i = 0; i < foreign.size() && i < 3; ++i) names += (i ? ", '" : "'") + foreign[i] + "'";
    if (foreign.size() > 3) names += " and " + std::to_string(foreign.size() - 3) + " more";
    refuse(guard, given,
           foreign.empty() ? "holds a " + std::string(kManifestName) + " that xsect did not write"
                           : "holds files its manifest does not list (" + names + ")",
           "xsect only replaces what it wrote; " + elsewhere + ", or move those files away");
  }
}

void checkOutputFile(const fs::path& file, const OutputGuard& guard) {
  const fs::path given = plain(file), dest = resolved(file);
  std::error_code ec;
  if (fs::is_directory(dest, ec))
    refuse(guard, given, "is a folder", "name the file to write, e.g. " + given.string() + ".json");
  for (const std::string& input : guard.inputs)
    if (!input.empty() && resolved(input) == dest)
      refuse(guard, given, "is one of the inputs", "name another file, e.g. " + given.string() + ".eval.json");
}

void removeStaleStaging(const fs::path& destination) {
  const fs::path dest = plain(destination);
  const std::string name = dest.filename().string();
  if (name.empty()) return;
  const std::string host = hostName();
  std::error_code ec;
  std::vector<fs::path> stale;
  for (fs::directory_iterator it(dest.parent_path(), ec), end; !ec && it != end; it.increment(ec)) {
    const std::string entry = it->path().filename().string();
    for (const std::string kind : {".partial-", ".old-"}) {
      const std::string prefix = "." + name + kind;
      if (entry.size() <= prefix.size() || entry.compare(0, prefix.size(), prefix) != 0) continue;
      const std::string tag = entry.substr(prefix.size());
      const auto dash = tag.rfind('-');
      const std::string who = dash == std::string::npos ? host : tag.substr(0, dash);
      const std::string pid = dash == std::string::npos ? tag : tag.substr(dash + 1);
      if (who != host || pid.empty() || !std::all_of(pid.begin(), pid.end(), ::isdigit) || pid.size() > 9) continue;
      if (!processAlive(std::atol(pid.c_str()))) stale.push_back(it->path());
    }
  }
  // A run killed between its two renames (the old folder moved aside, the new one not yet in
  // place) leaves the destination absent: the previous output is put back, not removed.
  for (const fs::path& p : stale) {
    if (!fs::exists(dest, ec) && p.filename().string().compare(0, name.size() + 6, "." + name + ".old-") == 0 &&
        isXsectOutputFolder(p)) {
      fs::rename(p, dest, ec);
      if (!ec) continue;
    }
    fs::remove_all(p, ec);
  }
}

}  // namespace xsect

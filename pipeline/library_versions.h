// Versions of the libraries linked into xsect, for the manifest.
#pragma once

#include <map>
#include <string>

namespace xsect {
std::map<std::string, std::string> libraryVersions();
}

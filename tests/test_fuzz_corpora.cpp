// Issue 15, item 2: every reader's seed corpus and every crash the fuzzers found, replayed through
// the reader harnesses of tests/fuzz/ in the ordinary build. A reader may accept or refuse each
// input with an InputError; any other exception fails the test (a crash fails the whole binary).
// The valid seeds must be accepted, so that a reader that refuses everything cannot pass.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "tests/fuzz/reader_harnesses.h"

namespace fs = std::filesystem;

namespace {

fs::path corpusFolder(const std::string& harness) {
  return fs::path(XSECT_SOURCE_DIR) / "tests/fuzz/corpus" / harness;
}

std::string fileText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The project's own headers a source includes, as paths relative to the source tree.
std::vector<std::string> projectIncludes(const std::string& source) {
  const fs::path root(XSECT_SOURCE_DIR);
  static const std::regex include(R"re(#include "([^"]+)")re");
  const std::string text = fileText(root / source);
  std::vector<std::string> found;
  for (std::sregex_iterator it(text.begin(), text.end(), include), end; it != end; ++it) {
    const std::string name = (*it)[1];
    for (const fs::path& candidate : {fs::path(name), fs::path(source).parent_path() / name})
      if (fs::exists(root / candidate)) {
        found.push_back(candidate.lexically_normal().generic_string());
        break;
      }
  }
  return found;
}

}  // namespace

TEST(FuzzCorpora, EveryHarnessHasASeedCorpusItAccepts) {
  for (const xsect::fuzz::ReaderHarness& h : xsect::fuzz::readerHarnesses()) {
    SCOPED_TRACE(h.name);
    ASSERT_TRUE(fs::is_directory(corpusFolder(h.name)));
    int accepted = 0, files = 0;
    for (const auto& entry : fs::directory_iterator(corpusFolder(h.name))) {
      std::ifstream in(entry.path(), std::ios::binary);
      const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      SCOPED_TRACE(entry.path().filename().string());
      bool ok = false;
      std::string refusal;
      EXPECT_NO_THROW(ok = xsect::fuzz::readFuzzInput(
                          h, reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), &refusal));
      // A seed must be accepted; an input that once crashed a reader (corrupt, every one so far)
      // must now be refused, with a message (under the sanitizers, scripts/fuzz.sh replays it too).
      const bool crashSeed = entry.path().filename().string().rfind("crash-", 0) == 0;
      if (crashSeed) {
        EXPECT_FALSE(ok) << "a corrupt input the reader accepts";
        EXPECT_FALSE(refusal.empty());
        std::cout << h.name << "/" << entry.path().filename().string() << ": " << refusal << "\n";
      } else {
        EXPECT_TRUE(ok) << "a seed the reader refuses: " << refusal;
      }
      accepted += ok;
      ++files;
    }
    EXPECT_GT(files, 0);
    EXPECT_GT(accepted, 0);
  }
  xsect::fuzz::removeScratchFolder();
}

// The fuzz build (scripts/fuzz.sh, clang with sanitizers) compiles its own list of sources; a
// source added to the library and called by a reader but missing from that list breaks only
// that build, at link time, after the whole test suite has passed. Every header a reader includes
// at any depth whose .cpp exists must be in the list.
TEST(FuzzCorpora, FuzzBuildCompilesEverySourceItsReadersInclude) {
  const fs::path root(XSECT_SOURCE_DIR);
  const std::string cmake = fileText(root / "tests/fuzz/CMakeLists.txt");
  std::smatch match;
  ASSERT_TRUE(std::regex_search(cmake, match, std::regex(R"(set\(XSECT_READER_SOURCES([^)]*)\))")));
  std::set<std::string> listed;
  std::istringstream words(match[1].str());
  for (std::string word; words >> word;)
    if (word.rfind('#', 0) != 0) listed.insert(word);
  ASSERT_GT(listed.size(), 10u);
  listed.insert("tests/fuzz/reader_harnesses.cpp");  // the library's own source, beside the list
  std::vector<std::string> pending(listed.begin(), listed.end());
  std::set<std::string> visited;
  while (!pending.empty()) {
    const std::string source = pending.back();
    pending.pop_back();
    if (!visited.insert(source).second) continue;
    for (const std::string& header : projectIncludes(source)) {
      pending.push_back(header);
      if (header.size() < 2 || header.substr(header.size() - 2) != ".h") continue;
      const std::string implementation = header.substr(0, header.size() - 2) + ".cpp";
      if (!fs::exists(root / implementation)) continue;
      pending.push_back(implementation);
      EXPECT_TRUE(listed.count(implementation))
          << implementation << " (its header is included by " << source
          << ") is missing from XSECT_READER_SOURCES in tests/fuzz/CMakeLists.txt";
    }
  }
  EXPECT_GT(visited.size(), listed.size());
}

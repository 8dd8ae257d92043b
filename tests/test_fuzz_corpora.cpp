// Issue 15, item 2: every reader's seed corpus and every crash the fuzzers found, replayed through
// the reader harnesses of tests/fuzz/ in the ordinary build. A reader may accept or refuse each
// input with an InputError; any other exception fails the test (a crash fails the whole binary).
// The valid seeds must be accepted, so that a reader that refuses everything cannot pass.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>

#include "tests/fuzz/reader_harnesses.h"

namespace fs = std::filesystem;

namespace {

fs::path corpusFolder(const std::string& harness) {
  return fs::path(XSECT_SOURCE_DIR) / "tests/fuzz/corpus" / harness;
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

// Fuzz harnesses for every reader of the input contract (issue 15, item 2): each writes the bytes
// it is given to a scratch file with the reader's extension and calls the reader. An InputError is
// the expected way to refuse bad bytes; any other exception, a crash, a hang or a sanitizer report
// is a defect. Driven by libFuzzer (tests/fuzz/fuzz_main.cpp, scripts/fuzz.sh) and, for the seed
// corpora and every crash found so far, by ctest (tests/test_fuzz_corpora.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace xsect::fuzz {

struct ReaderHarness {
  std::string name;       ///< also the corpus folder: tests/fuzz/corpus/<name>/
  std::string extension;  ///< of the scratch file the reader is given, e.g. ".csl"
  void (*read)(const std::string& path);
};

/// The harnesses, one per reader and format.
std::vector<ReaderHarness> readerHarnesses();

/// The harness called `name`; throws std::invalid_argument if there is none.
ReaderHarness readerHarness(const std::string& name);

/// Writes `data` to this process's scratch file for `harness` and reads it. Returns true when the
/// reader accepted the bytes, false when it refused them with an InputError (whose message goes to
/// `refusal` when given); anything else propagates.
bool readFuzzInput(const ReaderHarness& harness, const std::uint8_t* data, std::size_t size,
                   std::string* refusal = nullptr);

/// Removes this process's scratch folder (the replay test's clean-up; libFuzzer runs leave it).
void removeScratchFolder();

}  // namespace xsect::fuzz

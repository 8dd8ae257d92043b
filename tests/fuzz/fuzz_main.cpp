// libFuzzer entry point for one reader harness, chosen at compile time by XSECT_FUZZ_READER
// (tests/fuzz/CMakeLists.txt builds one executable per harness).
#include <cstddef>
#include <cstdint>

#include "tests/fuzz/reader_harnesses.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const xsect::fuzz::ReaderHarness harness = xsect::fuzz::readerHarness(XSECT_FUZZ_READER);
  xsect::fuzz::readFuzzInput(harness, data, size);
  return 0;
}

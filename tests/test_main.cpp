// The tests' entry point. Each test process works in a scratch folder of its own under the system's
// temporary folder: TMPDIR is set to it, so every folder a test makes (test::freshDir,
// std::filesystem::temp_directory_path) and every xsect it starts fall inside it. The folder is removed
// when every test of the process passed, and kept and named on stderr when one failed, to be looked at.
// (Before, each ctest run left about 400 folders and 1-2 GB behind; 50 GB of them filled the CI
// machine's disk.)
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  std::string scratch = (std::filesystem::temp_directory_path() / "xsect-tests-XXXXXX").string();
  if (!::mkdtemp(scratch.data())) {
    std::perror("xsect_tests: cannot make a scratch folder under the temporary folder");
    return 1;
  }
  ::setenv("TMPDIR", scratch.c_str(), 1);
  const int status = RUN_ALL_TESTS();
  if (status == 0) {
    std::error_code ignored;
    std::filesystem::remove_all(scratch, ignored);
  } else {
    std::fprintf(stderr, "xsect_tests: the failed tests' files are kept in %s\n", scratch.c_str());
  }
  return status;
}

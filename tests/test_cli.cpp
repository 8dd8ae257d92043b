// The tool exists and rejects a missing configuration with exit code 2.
#include <gtest/gtest.h>
#include <cstdlib>
#include <string>

TEST(Cli, MissingConfigIsInputError) {
  const std::string cmd = std::string(XSECT_BIN) + " run /nonexistent/config.yaml --quiet 2>/dev/null";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2);
}

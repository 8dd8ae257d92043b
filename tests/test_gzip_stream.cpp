// Parallel gzip rows (io/gzip_stream.h): one gzip member that zlib inflates to the rows in order,
// over many groups and waves, the same bytes on one thread as on many, and empty input.
#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <zlib.h>

#include <cstring>
#include <random>
#include <sstream>
#include <string>

#include "io/gzip_stream.h"

using namespace xsect;

namespace {

/// Row r: 3000 bytes, runs and noise mixed so that deflate has work of both kinds.
void rowOf(std::size_t r, std::string* bytes) {
  std::mt19937 rng(std::uint32_t(r * 2654435761u));
  bytes->assign(3000, char(r % 7));
  for (std::size_t i = 0; i < bytes->size(); i += 1 + rng() % 40) (*bytes)[i] = char(rng());
}

/// Inflates a whole gzip stream with zlib; fails the test on an error or trailing bytes.
std::string inflateAll(const std::string& gz, int* members) {
  z_stream zs;
  std::memset(&zs, 0, sizeof zs);
  EXPECT_EQ(inflateInit2(&zs, 15 + 16), Z_OK);
  zs.next_in = reinterpret_cast<unsigned char*>(const_cast<char*>(gz.data()));
  zs.avail_in = uInt(gz.size());
  std::string out;
  std::string buf(1 << 16, '\0');
  int rc = Z_OK;
  *members = 0;
  while (rc != Z_STREAM_END) {
    zs.next_out = reinterpret_cast<unsigned char*>(buf.data());
    zs.avail_out = uInt(buf.size());
    rc = inflate(&zs, Z_NO_FLUSH);
    EXPECT_TRUE(rc == Z_OK || rc == Z_STREAM_END) << zs.msg;
    if (rc != Z_OK && rc != Z_STREAM_END) break;
    out.append(buf.data(), buf.size() - zs.avail_out);
  }
  *members = rc == Z_STREAM_END;
  EXPECT_EQ(zs.avail_in, 0u);  // one member, nothing after it (readers such as pynrrd stop there)
  inflateEnd(&zs);
  return out;
}

}  // namespace

TEST(GzipStream, OneMemberHoldingEveryRowInOrderOverManyGroups) {
  const std::size_t rows = 12000;  // 36 MB: about 35 groups of 1 MiB, three waves
  std::string expected;
  for (std::size_t r = 0; r < rows; ++r) {
    std::string b;
    rowOf(r, &b);
    expected += b;
  }
  for (const int level : {1, -1}) {
    std::ostringstream gz;
    writeGzipRows(gz, rows, rowOf, level);
    int members = 0;
    const std::string back = inflateAll(gz.str(), &members);
    EXPECT_EQ(members, 1);
    ASSERT_EQ(back.size(), expected.size());
    EXPECT_TRUE(back == expected) << "level " << level;
    EXPECT_LT(gz.str().size(), expected.size() / 2);
  }
}

TEST(GzipStream, SameBytesOnOneThreadAsOnMany) {
  const auto write = [] {
    std::ostringstream gz;
    writeGzipRows(gz, 2500, rowOf, 1);
    return gz.str();
  };
  const std::string many = write();
  std::string one;
  {
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    one = write();
  }
  EXPECT_TRUE(one == many);
}

TEST(GzipStream, IncompressibleRowsAndTheHeaderZlibWrites) {
  // Random bytes: deflate's stored blocks, the worst case for the room each group is given.
  const auto noise = [](std::size_t r, std::string* bytes) {
    std::mt19937_64 rng(r + 1);
    bytes->resize(70000);
    for (char& c : *bytes) c = char(rng());
  };
  std::string expected;
  for (std::size_t r = 0; r < 40; ++r) {
    std::string b;
    noise(r, &b);
    expected += b;
  }
  for (const int level : {0, 1, 6, 9}) {
    std::ostringstream gz;
    writeGzipRows(gz, 40, noise, level);
    const std::string g = gz.str();
    int members = 0;
    EXPECT_TRUE(inflateAll(g, &members) == expected) << "level " << level;
    EXPECT_EQ(members, 1);
    // ID1 ID2 CM FLG, MTIME 0, XFL as zlib sets it for the level, OS 3.
    ASSERT_GE(g.size(), 18u);
    const unsigned char xfl = level == 9 ? 2 : level <= 1 ? 4 : 0;
    const unsigned char head[10] = {0x1f, 0x8b, 8, 0, 0, 0, 0, 0, xfl, 3};
    EXPECT_EQ(std::memcmp(g.data(), head, 10), 0) << "level " << level;
  }
}

TEST(GzipStream, NoRowsIsAnEmptyMember) {
  std::ostringstream gz;
  writeGzipRows(gz, 0, rowOf);
  int members = 0;
  EXPECT_EQ(inflateAll(gz.str(), &members), "");
  EXPECT_EQ(members, 1);
}

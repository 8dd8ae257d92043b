// Issue 15, item 3: a slice image's size is read from its header and checked before it is decoded.
// The sizes of the seed images (PNG, little- and big-endian TIFF) are read exactly; a header that
// claims more pixels than a slice may have, a truncated header and a file that is neither format are
// refused through `xsect run` with exit 2 naming the slice's field, and nothing is written.
#include <gtest/gtest.h>

#include <filesystem>

#include "cli.h"
#include "io/image_header.h"
#include "io/image_io.h"

namespace fs = std::filesystem;
using namespace xsect;

namespace {

const fs::path kImages = fs::path(XSECT_SOURCE_DIR) / "tests/fuzz/corpus/image";

/// A PNG signature and an IHDR chunk claiming width x height 8-bit grey pixels, and nothing else.
std::string pngHeaderOnly(std::uint32_t width, std::uint32_t height) {
  std::string b = "\x89PNG\r\n\x1a\n";
  auto be32 = [&](std::uint32_t v) {
    for (int k = 3; k >= 0; --k) b.push_back(char((v >> (8 * k)) & 0xff));
  };
  be32(13);
  b += "IHDR";
  be32(width);
  be32(height);
  b += std::string("\x08\x00\x00\x00\x00", 5);
  be32(0);  // CRC, never reached
  return b;
}

}  // namespace

TEST(ImageHeader, SizesOfPngAndTiffInBothByteOrders) {
  const ImageHeader png = readImageHeader((kImages / "grey16.png").string());
  EXPECT_EQ(png.format, "png");
  EXPECT_EQ(png.width, 6u);
  EXPECT_EQ(png.height, 5u);
  EXPECT_EQ(png.bits_per_sample, 16);
  EXPECT_EQ(png.channels, 1);
  const ImageHeader le = readImageHeader((kImages / "grey8.tif").string());
  EXPECT_EQ(le.format, "tiff");
  EXPECT_EQ(le.width, 4u);
  EXPECT_EQ(le.height, 3u);
  EXPECT_EQ(le.bits_per_sample, 8);
  const ImageHeader be = readImageHeader((kImages / "grey16_be.tif").string());
  EXPECT_EQ(be.width, 3u);
  EXPECT_EQ(be.height, 2u);
  EXPECT_EQ(be.bits_per_sample, 16);
  // And the decoder agrees with the header on every seed it accepts.
  for (const char* name : {"grey16.png", "grey8.tif", "grey16_be.tif", "frame8.png"}) {
    const std::string path = (kImages / name).string();
    const cv::Mat m = readGreyImage(path, "test", "image");
    const ImageHeader h = readImageHeader(path);
    EXPECT_EQ(std::uint64_t(m.cols), h.width) << name;
    EXPECT_EQ(std::uint64_t(m.rows), h.height) << name;
  }
}

TEST(ImageHeader, HugeTruncatedAndForeignImagesAreRefusedBeforeDecoding) {
  const fs::path dir = test::freshDir("image_header");
  const std::string good = test::slurp(kImages / "frame8.png");
  struct Case { std::string bytes, says; };
  const std::vector<Case> cases = {
      {pngHeaderOnly(70000, 70000), "70000 x 70000 pixels, more than the 268435456 a slice may have"},
      {good.substr(0, 20), "truncated header"},
      {"GIF89a" + std::string(40, '\0'), "neither a PNG nor a TIFF image"},
      {pngHeaderOnly(0, 12), "the header gives no size"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.says);
    test::writeFile(dir / "bad.png", c.bytes);
    test::writeFile(dir / "frame.png", good);
    test::writeFile(dir / "slices.yaml",
                    "slices:\n"
                    "  - image: frame.png\n    image_to_world: [[0.5, 0, 0, 0], [0, 0.5, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n"
                    "  - image: bad.png\n    image_to_world: [[0.5, 0, 0, 0], [0, 0.5, 0, 0], [0, 0, 1, 2], [0, 0, 0, 1]]\n");
    test::writeFile(dir / "config.yaml", "input:\n  slices: slices.yaml\n");
    const auto r = test::runXsect("run " + (dir / "config.yaml").string() + " --out " + (dir / "out").string() +
                                  " --quiet");
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("slices[1].image"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out"));
  }
  fs::remove_all(dir);
}

// Level sets as OpenVDB files (io/level_set_file.h): exact round trip of an analytic sphere band,
// byte-identical files across writes and TBB thread counts (the header's UUID replaced by a content
// tag), signed flood fill of the inactive region, the box of files without xsect's metadata, and
// InputError naming the file for each kind of malformed file. Malformed VDB files are made by
// patching bytes of a written file, so the test needs no OpenVDB headers.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli.h"
#include "io/input_error.h"
#include "io/level_set_file.h"

using namespace xsect;
namespace fs = std::filesystem;

namespace {

constexpr double kVoxel = 0.4;              // mm
const Vec3 kOrigin(-3.25, 1.5, 2.0);        // centre of voxel (0,0,0), mm
const Vec3 kCentreIndex(9.3, 8.6, 9.1);     // sphere centre, index units
constexpr double kRadius = 5 * kVoxel;      // mm
constexpr float kBackground = 3 * kVoxel;   // band half-width, mm

Vec3 sphereCentre() { return kOrigin + kVoxel * kCentreIndex; }

/// Voxels within 3 voxels of a sphere of radius 5 voxels, value |x - c| - r (mm), in (k, j, i)
/// order, on a 20 x 19 x 21 grid the band does not fill (so dims must be stored, not guessed).
NarrowBandLevelSet sphereBand() {
  NarrowBandLevelSet ls;
  ls.grid.origin = kOrigin;
  ls.grid.voxel = kVoxel;
  ls.grid.dims = {20, 19, 21};
  ls.background = kBackground;
  for (int k = 0; k < ls.grid.dims[2]; ++k)
    for (int j = 0; j < ls.grid.dims[1]; ++j)
      for (int i = 0; i < ls.grid.dims[0]; ++i) {
        const double d = (ls.grid.centre(i, j, k) - sphereCentre()).norm() - kRadius;
        if (std::abs(d) > 3 * kVoxel) continue;
        ls.coords.push_back({i, j, k});
        ls.values.push_back(float(d));
      }
  return ls;
}

void writeBytes(const fs::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary | std::ios::trunc)
      .write(bytes.data(), std::streamsize(bytes.size()));
}

/// `bytes` with the first occurrence of `from` replaced by `to` (same length).
std::string patched(std::string bytes, const std::string& from, const std::string& to) {
  EXPECT_EQ(from.size(), to.size());
  const std::size_t at = bytes.find(from);
  EXPECT_NE(at, std::string::npos) << "pattern not found";
  if (at != std::string::npos) bytes.replace(at, from.size(), to);
  return bytes;
}

std::string doubles(const std::vector<double>& v) {
  std::string s(v.size() * sizeof(double), '\0');
  std::memcpy(s.data(), v.data(), s.size());
  return s;
}

/// Field of the InputError that reading `path` raises; "" if none. Also checks what() names the file.
std::string failingField(const fs::path& path, const std::string& gridName = "level_set") {
  try {
    readLevelSetVdb(path.string(), gridName);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    EXPECT_EQ(e.file(), path.string());
    return e.field();
  }
  return "";
}

class LevelSetFile : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::freshDir("lsfile"); }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

}  // namespace

TEST_F(LevelSetFile, RoundTripIsExact) {
  const NarrowBandLevelSet in = sphereBand();
  ASSERT_GT(in.coords.size(), 1000u);
  const fs::path p = dir_ / "sphere.vdb";
  writeLevelSetVdb(p.string(), in);
  const NarrowBandLevelSet out = readLevelSetVdb(p.string());
  EXPECT_EQ(out.grid.origin, in.grid.origin);
  EXPECT_EQ(out.grid.voxel, in.grid.voxel);
  EXPECT_EQ(out.grid.dims, in.grid.dims);
  EXPECT_EQ(out.background, in.background);
  EXPECT_EQ(out.coords, in.coords);
  EXPECT_EQ(out.values, in.values);
  // No temporary file left beside the result.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

TEST_F(LevelSetFile, CustomGridNameRoundTrips) {
  const NarrowBandLevelSet in = sphereBand();
  const fs::path p = dir_ / "named.vdb";
  writeLevelSetVdb(p.string(), in, "surface");
  EXPECT_EQ(readLevelSetVdb(p.string(), "surface").values, in.values);
  EXPECT_EQ(failingField(p), "grid");  // default name "level_set" is absent
}

TEST_F(LevelSetFile, WritingTwiceGivesIdenticalBytes) {
  const NarrowBandLevelSet ls = sphereBand();
  const fs::path a = dir_ / "a.vdb", b = dir_ / "b.vdb", c = dir_ / "c.vdb";
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    writeLevelSetVdb(a.string(), ls);
  }
  writeLevelSetVdb(b.string(), ls);
  {
    tbb::global_control four(tbb::global_control::max_allowed_parallelism, 4);
    writeLevelSetVdb(c.string(), ls);
  }
  NarrowBandLevelSet reversed = ls;  // the order of the voxels does not matter either
  std::reverse(reversed.coords.begin(), reversed.coords.end());
  std::reverse(reversed.values.begin(), reversed.values.end());
  const fs::path d = dir_ / "d.vdb";
  writeLevelSetVdb(d.string(), reversed);
  const std::string bytesA = test::slurp(a);
  ASSERT_GT(bytesA.size(), 57u);
  EXPECT_EQ(bytesA, test::slurp(b));
  EXPECT_EQ(bytesA, test::slurp(c));
  EXPECT_EQ(bytesA, test::slurp(d));
  // The header's tag (bytes 21..56) is UUID-shaped, version 8 (content-derived), and changes with
  // the contents.
  const std::string tag = bytesA.substr(21, 36);
  EXPECT_TRUE(std::regex_match(tag, std::regex("[0-9a-f]{8}-[0-9a-f]{4}-8[0-9a-f]{3}-[89ab][0-9a-f]{3}-[0-9a-f]{12}")))
      << tag;
  NarrowBandLevelSet other = ls;
  other.values[0] += 0.01f;
  writeLevelSetVdb(b.string(), other);
  EXPECT_NE(test::slurp(b).substr(21, 36), tag);
  // And OpenVDB still reads the patched file.
  EXPECT_EQ(readLevelSetVdb(a.string()).values, ls.values);
}

TEST_F(LevelSetFile, InactiveVoxelsAreSignedByFloodFill) {
  const NarrowBandLevelSet ls = sphereBand();
  const fs::path p = dir_ / "sphere.vdb";
  writeLevelSetVdb(p.string(), ls);
  EXPECT_EQ(levelSetValueAt(p.string(), sphereCentre()), -kBackground);
  EXPECT_EQ(levelSetValueAt(p.string(), sphereCentre() + Vec3(40, -30, 25)), kBackground);
  EXPECT_EQ(levelSetValueAt(p.string(), Vec3(1e12, 0, 0)), kBackground);
  // At an active voxel (and a point nearer to it than to any other voxel): its stored value.
  const std::size_t n = ls.coords.size() / 3;
  const auto& c = ls.coords[n];
  const Vec3 near = ls.grid.centre(c[0], c[1], c[2]) + Vec3(0.15, -0.1, 0.19);
  EXPECT_EQ(levelSetValueAt(p.string(), near), ls.values[n]);
  EXPECT_THROW(levelSetValueAt(p.string(), Vec3(NAN, 0, 0)), std::invalid_argument);
  EXPECT_THROW(levelSetValueAt((dir_ / "missing.vdb").string(), Vec3::Zero()), InputError);
}

TEST_F(LevelSetFile, FileWithoutDimsMetadataUsesActiveBox) {
  // A file as another tool would write it: hide xsect's dims metadata by renaming the key.
  NarrowBandLevelSet ls = sphereBand();
  const fs::path p = dir_ / "sphere.vdb";
  writeLevelSetVdb(p.string(), ls);
  writeBytes(p, patched(test::slurp(p), "xsect_grid_dims", "xsect_grid_dimz"));
  NarrowBandLevelSet out = readLevelSetVdb(p.string());
  int maxIndex[3] = {0, 0, 0};
  for (const auto& c : ls.coords)
    for (int a = 0; a < 3; ++a) maxIndex[a] = std::max(maxIndex[a], c[a]);
  EXPECT_EQ(out.grid.dims, (std::array<int, 3>{maxIndex[0] + 1, maxIndex[1] + 1, maxIndex[2] + 1}));
  EXPECT_EQ(out.grid.origin, ls.grid.origin);
  EXPECT_EQ(out.coords, ls.coords);

  // Negative indices along x: the origin moves to the lowest index, coords shift with it.
  for (auto& c : ls.coords) c[0] -= 4;
  writeLevelSetVdb(p.string(), ls);
  writeBytes(p, patched(test::slurp(p), "xsect_grid_dims", "xsect_grid_dimz"));
  out = readLevelSetVdb(p.string());
  int minX = 0;
  for (const auto& c : ls.coords) minX = std::min(minX, c[0]);
  ASSERT_LT(minX, 0);
  EXPECT_NEAR((out.grid.origin - (ls.grid.origin + Vec3(minX * kVoxel, 0, 0))).norm(), 0.0, 1e-12);
  EXPECT_EQ(out.coords.front()[0] + minX, ls.coords.front()[0]);
  EXPECT_EQ(out.values, ls.values);
}

TEST_F(LevelSetFile, MalformedFilesRaiseInputErrorNamingTheFile) {
  const fs::path good = dir_ / "good.vdb";
  writeLevelSetVdb(good.string(), sphereBand());
  const std::string bytes = test::slurp(good);
  const fs::path bad = dir_ / "bad.vdb";

  EXPECT_EQ(failingField(dir_ / "missing.vdb"), "file");
  EXPECT_EQ(failingField(dir_), "file");  // a folder
  writeBytes(bad, "");
  EXPECT_EQ(failingField(bad), "file");
  writeBytes(bad, "solid cube\nfacet normal 0 0 1\n" + std::string(300, '\x7f'));
  EXPECT_EQ(failingField(bad), "file");
  for (const std::size_t size : {std::size_t(4), std::size_t(30), std::size_t(60), std::size_t(120),
                                 bytes.size() / 3, bytes.size() / 2, bytes.size() - 100,
                                 bytes.size() - 1}) {
    writeBytes(bad, bytes.substr(0, size));
    EXPECT_EQ(failingField(bad), "file") << "truncated to " << size << " of " << bytes.size();
  }
  // Corruptions that made OpenVDB allocate gigabytes before failing: a newer format version, a
  // fixed-size metadata value with a wrong stated size, a string claiming 1.8 GB.
  std::string newer = bytes;
  newer[8] = char(0xe1);  // file format version 225
  writeBytes(bad, newer);
  EXPECT_EQ(failingField(bad), "file");
  writeBytes(bad, patched(bytes, std::string("vec3i\x0c\0\0\0", 9), std::string("vec3i\x0d\0\0\0", 9)));
  EXPECT_EQ(failingField(bad), "file");
  writeBytes(bad, patched(bytes, std::string("string\x02\0\0\0mm", 12), std::string("string\x02\0\0\x70mm", 12)));
  EXPECT_EQ(failingField(bad), "file");

  EXPECT_EQ(failingField(good, "density"), "grid");
  // An int32 grid (same value size, so the rest of the file still parses).
  writeBytes(bad, patched(bytes, "Tree_float_5_4_3", "Tree_int32_5_4_3"));
  EXPECT_EQ(failingField(bad), "grid");
  // Grid class "staggered" instead of "level set" (same length, length-prefixed string).
  writeBytes(bad, patched(bytes, std::string("\x09\0\0\0level set", 13), std::string("\x09\0\0\0staggered", 13)));
  EXPECT_EQ(failingField(bad), "grid class");
  // Transform: the serialised translation and scale, with the y scale doubled.
  const std::vector<double> tx = {kOrigin.x(), kOrigin.y(), kOrigin.z(), kVoxel, kVoxel, kVoxel};
  writeBytes(bad, patched(bytes, doubles(tx), doubles({tx[0], tx[1], tx[2], kVoxel, 2 * kVoxel, kVoxel})));
  EXPECT_EQ(failingField(bad), "transform");
  writeBytes(bad, patched(bytes, doubles(tx), doubles({tx[0], tx[1], tx[2], -kVoxel, -kVoxel, -kVoxel})));
  EXPECT_EQ(failingField(bad), "transform");
}

TEST_F(LevelSetFile, WriterRejectsInvalidInput) {
  const std::string p = (dir_ / "x.vdb").string();
  const NarrowBandLevelSet good = sphereBand();
  auto rejects = [&](NarrowBandLevelSet ls) {
    EXPECT_THROW(writeLevelSetVdb(p, ls), std::invalid_argument);
  };
  NarrowBandLevelSet ls = good;
  ls.values.pop_back();
  rejects(ls);
  ls = good;
  ls.background = 0.0f;
  rejects(ls);
  ls.background = INFINITY;
  rejects(ls);
  ls = good;
  ls.values[7] = NAN;
  rejects(ls);
  ls = good;
  ls.grid.voxel = 0.0;
  rejects(ls);
  ls = good;
  ls.coords[5] = ls.coords[4];
  rejects(ls);
  EXPECT_FALSE(fs::exists(p));
  EXPECT_THROW(writeLevelSetVdb((dir_ / "no" / "such" / "dir.vdb").string(), good), std::runtime_error);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 0);
}

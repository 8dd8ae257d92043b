// Label volumes as NRRD (io/label_volume_file.h): exact round trip, the header fields 3D Slicer
// reads (geometry, LPS, segment metadata), reproducible bytes, and InputError naming the field
// for each kind of malformed file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli.h"
#include "io/input_error.h"
#include "io/label_volume_file.h"

using namespace xsect;
namespace fs = std::filesystem;

namespace {

GridSpec testGrid() {
  GridSpec g;
  g.origin = Vec3(-12.345, 0.1, 3.5);
  g.voxel = 0.37;
  g.dims = {7, 5, 3};
  return g;
}

std::vector<std::uint16_t> testLabels(const GridSpec& g) {
  std::vector<std::uint16_t> l(std::size_t(g.count()), 0);
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i)
        if (i >= 2 && j >= 1) l[std::size_t(g.index(i, j, k))] = std::uint16_t(1 + (i + j + k) % 2);
  l[std::size_t(g.index(6, 4, 2))] = 65535;
  l[std::size_t(g.index(0, 0, 1))] = 300;
  return l;
}

void writeBytes(const fs::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));
}

std::string headerOf(const std::string& file) { return file.substr(0, file.find("\n\n") + 2); }
std::string dataOf(const std::string& file) { return file.substr(file.find("\n\n") + 2); }

/// The file with the header line starting with `prefix` replaced by `line` ("" = removed).
std::string withLine(const std::string& file, const std::string& prefix, const std::string& line) {
  std::string h = headerOf(file);
  const std::size_t at = h.find("\n" + prefix);
  EXPECT_NE(at, std::string::npos) << prefix;
  const std::size_t end = h.find('\n', at + 1);
  h.replace(at + 1, end - at, line.empty() ? "" : line + "\n");
  return h + dataOf(file);
}

/// Field named by the InputError that reading `bytes` raises ("" if none is raised).
std::string failingField(const fs::path& dir, const std::string& bytes) {
  const fs::path p = dir / "bad.nrrd";
  writeBytes(p, bytes);
  try {
    readLabelVolumeNrrd(p.string());
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), p.string());
    return e.field();
  }
  return "";
}

}  // namespace

TEST(LabelVolumeFile, RoundTripIsExact) {
  const fs::path dir = test::freshDir("labelvol");
  const GridSpec g = testGrid();
  const auto labels = testLabels(g);
  writeLabelVolumeNrrd((dir / "a.seg.nrrd").string(), g, labels);
  const LabelVolume v = readLabelVolumeNrrd((dir / "a.seg.nrrd").string());
  EXPECT_EQ(v.grid.dims, g.dims);
  EXPECT_EQ(v.grid.voxel, g.voxel);
  EXPECT_EQ(v.grid.origin, g.origin);
  EXPECT_EQ(v.labels, labels);
  fs::remove_all(dir);
}

TEST(LabelVolumeFile, HeaderCarriesTheGridInLpsAndTheSegments) {
  const fs::path dir = test::freshDir("labelvol");
  const GridSpec g = testGrid();
  std::vector<std::uint16_t> labels(std::size_t(g.count()), 0);
  labels[std::size_t(g.index(5, 1, 2))] = 4;  // one voxel: its extent pins the index order
  writeLabelVolumeNrrd((dir / "a.nrrd").string(), g, labels);
  const std::string file = test::slurp(dir / "a.nrrd");
  const std::string h = headerOf(file);
  EXPECT_EQ(h.rfind("NRRD0004\n", 0), 0u);
  for (const char* line : {"\ntype: unsigned short\n", "\ndimension: 3\n",
                           "\nspace: left-posterior-superior\n", "\nsizes: 7 5 3\n",
                           "\nspace directions: (0.37,0,0) (0,0.37,0) (0,0,0.37)\n",
                           "\nspace origin: (-12.345,0.1,3.5)\n", "\nencoding: gzip\n",
                           "\nendian: little\n", "\nSegment0_LabelValue:=4\n",
                           "\nSegment0_Extent:=5 5 1 1 2 2\n", "\nSegment0_Layer:=0\n",
                           "\nSegment0_Name:=label 4\n"})
    EXPECT_NE(h.find(line), std::string::npos) << line;
  EXPECT_EQ(h.find("Segment1_"), std::string::npos);
  EXPECT_NE(h.find("LPS"), std::string::npos);  // the comment says which frame
  const std::string data = dataOf(file);
  ASSERT_GE(data.size(), 2u);
  EXPECT_EQ((unsigned char)data[0], 0x1f);  // gzip magic
  EXPECT_EQ((unsigned char)data[1], 0x8b);
  fs::remove_all(dir);
}

TEST(LabelVolumeFile, BytesAreReproducible) {
  const fs::path dir = test::freshDir("labelvol");
  const GridSpec g = testGrid();
  const auto labels = testLabels(g);
  writeLabelVolumeNrrd((dir / "a.nrrd").string(), g, labels);
  writeLabelVolumeNrrd((dir / "b.nrrd").string(), g, labels);
  EXPECT_EQ(test::slurp(dir / "a.nrrd"), test::slurp(dir / "b.nrrd"));
  // a larger volume goes through several compression chunks: still exact and reproducible
  GridSpec big;
  big.dims = {64, 50, 40};
  big.voxel = 0.25;
  std::vector<std::uint16_t> many(std::size_t(big.count()));
  for (std::size_t n = 0; n < many.size(); ++n) many[n] = std::uint16_t((n * 2654435761u) >> 20);
  writeLabelVolumeNrrd((dir / "c.nrrd").string(), big, many);
  writeLabelVolumeNrrd((dir / "d.nrrd").string(), big, many);
  EXPECT_EQ(test::slurp(dir / "c.nrrd"), test::slurp(dir / "d.nrrd"));
  EXPECT_EQ(readLabelVolumeNrrd((dir / "c.nrrd").string()).labels, many);
  fs::remove_all(dir);
}

TEST(LabelVolumeFile, WriterRejectsLabelsThatDoNotFitTheGrid) {
  const GridSpec g = testGrid();
  std::vector<std::uint16_t> labels(std::size_t(g.count()) - 1, 0);
  EXPECT_THROW(writeLabelVolumeNrrd("/nonexistent/x.nrrd", g, labels), std::invalid_argument);
  GridSpec flat = g;
  flat.voxel = 0;
  EXPECT_THROW(writeLabelVolumeNrrd("/nonexistent/x.nrrd", flat, testLabels(g)), std::invalid_argument);
}

TEST(LabelVolumeFile, ReadsRawBigEndianFiles) {
  const fs::path dir = test::freshDir("labelvol");
  std::string f =
      "NRRD0005\n# hand written\ntype: uint16\ndimension: 3\nspace: LPS\nsizes: 2 1 1\n"
      "space directions: (0.5, 0, 0) (0, 0.5, 0) (0, 0, 0.5)\nendian: big\nencoding: raw\n"
      "space origin: (1, 2, 3)\nkinds: domain domain domain\nSegment0_Name:=x\n\n";
  f += std::string("\x01\x02\x00\x07", 4);
  writeBytes(dir / "raw.nrrd", f);
  const LabelVolume v = readLabelVolumeNrrd((dir / "raw.nrrd").string());
  EXPECT_EQ(v.labels, (std::vector<std::uint16_t>{0x0102, 0x0007}));
  EXPECT_EQ(v.grid.voxel, 0.5);
  EXPECT_EQ(v.grid.origin, Vec3(1, 2, 3));
  EXPECT_EQ(failingField(dir, f.substr(0, f.size() - 1)), "data");  // truncated raw data
  EXPECT_EQ(failingField(dir, f + "xx"), "sizes");                  // more data than sizes
  fs::remove_all(dir);
}

TEST(LabelVolumeFile, MalformedFilesNameTheField) {
  const fs::path dir = test::freshDir("labelvol");
  const GridSpec g = testGrid();
  writeLabelVolumeNrrd((dir / "good.nrrd").string(), g, testLabels(g));
  const std::string good = test::slurp(dir / "good.nrrd");
  ASSERT_EQ(failingField(dir, good), "");

  EXPECT_EQ(failingField(dir, "P3\n" + good), "magic");
  EXPECT_EQ(failingField(dir, ""), "magic");
  EXPECT_EQ(failingField(dir, withLine(good, "type:", "")), "type");
  EXPECT_EQ(failingField(dir, withLine(good, "type:", "type: float")), "type");
  EXPECT_EQ(failingField(dir, withLine(good, "dimension:", "dimension: 4")), "dimension");
  EXPECT_EQ(failingField(dir, withLine(good, "sizes:", "")), "sizes");
  EXPECT_EQ(failingField(dir, withLine(good, "sizes:", "sizes: 7 5")), "sizes");
  EXPECT_EQ(failingField(dir, withLine(good, "sizes:", "sizes: 7 5 -3")), "sizes");
  EXPECT_EQ(failingField(dir, withLine(good, "sizes:", "sizes: 7 5 4")), "sizes");  // too few voxels
  EXPECT_EQ(failingField(dir, withLine(good, "sizes:", "sizes: 7 5 2")), "sizes");  // too many
  EXPECT_EQ(failingField(dir, withLine(good, "encoding:", "")), "encoding");
  EXPECT_EQ(failingField(dir, withLine(good, "encoding:", "encoding: bzip2")), "encoding");
  EXPECT_EQ(failingField(dir, withLine(good, "endian:", "")), "endian");
  EXPECT_EQ(failingField(dir, withLine(good, "space:", "")), "space");
  EXPECT_EQ(failingField(dir, withLine(good, "space:", "space: right-anterior-superior")), "space");
  EXPECT_EQ(failingField(dir, withLine(good, "space directions:", "")), "space directions");
  EXPECT_EQ(failingField(dir, withLine(good, "space directions:",
                                       "space directions: (0,0.37,0) (0.37,0,0) (0,0,0.37)")),
            "space directions");
  EXPECT_EQ(failingField(dir, withLine(good, "space directions:",
                                       "space directions: (0.37,0,0) (0,0.37,0) (0,0,0.5)")),
            "space directions");
  EXPECT_EQ(failingField(dir, withLine(good, "space directions:",
                                       "space directions: (0.37,0,0) (0,0.37,0)")),
            "space directions");
  EXPECT_EQ(failingField(dir, withLine(good, "space origin:", "")), "space origin");
  EXPECT_EQ(failingField(dir, withLine(good, "space origin:", "space origin: (1,2)")), "space origin");
  EXPECT_EQ(failingField(dir, withLine(good, "space origin:", "space origin: (1,nan,2)")), "space origin");
  EXPECT_EQ(failingField(dir, withLine(good, "space units:", "space units: \"cm\" \"cm\" \"cm\"")),
            "space units");
  EXPECT_EQ(failingField(dir, withLine(good, "kinds:", "data file: other.raw.gz")), "data file");
  EXPECT_EQ(failingField(dir, withLine(good, "kinds:", "sizes: 1 1 1")), "sizes");  // given twice
  // header without its blank line; bad gzip; truncated gzip
  EXPECT_EQ(failingField(dir, headerOf(good).substr(0, headerOf(good).size() - 1)), "header");
  std::string corrupt = good;
  const std::size_t d = headerOf(good).size();
  for (std::size_t k = d + 12; k < corrupt.size() - 8; k += 3) corrupt[k] = char(corrupt[k] ^ 0x5a);
  EXPECT_EQ(failingField(dir, corrupt), "data");
  EXPECT_EQ(failingField(dir, headerOf(good) + "not gzip at all"), "data");
  EXPECT_EQ(failingField(dir, good.substr(0, d + (good.size() - d) / 2)), "data");
  EXPECT_EQ(failingField(dir, good.substr(0, good.size() - 4)), "data");  // trailer cut
  EXPECT_EQ(failingField(dir, headerOf(good)), "data");                   // no data at all
  // a missing file is an InputError too
  EXPECT_THROW(readLabelVolumeNrrd((dir / "absent.nrrd").string()), InputError);
  fs::remove_all(dir);
}

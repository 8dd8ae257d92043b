// Mesh files: round trips through PLY, STL and OBJ, byte determinism, the ASCII readers, and
// malformed or truncated files of each format raising InputError that names the file.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/input_error.h"
#include "io/mesh_io.h"
#include "cli.h"
#include "mesh_fixtures.h"

namespace fs = std::filesystem;
using namespace xsect;

namespace {

fs::path tempDir() { return xsect::test::freshDir("mesh-io"); }

using xsect::test::slurp;

void spit(const fs::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary);
  out << bytes;
}

/// A mesh whose coordinates are not exactly representable in short decimals.
TriangleMesh sampleMesh() {
  TriangleMesh m = test::icosphere(3.7, 1, Vec3(0.1, -2.3, 1e-3));
  return m;
}

/// Compares meshes exactly, allowing a renumbering of vertices (STL welding).
void expectSameMesh(const TriangleMesh& a, const TriangleMesh& b) {
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  for (std::size_t t = 0; t < a.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(a.vertices[a.triangles[t][k]], b.vertices[b.triangles[t][k]])
          << "triangle " << t << " corner " << k;
}

/// Expects InputError from readMesh naming the file.
void expectInputError(const fs::path& p) {
  try {
    readMesh(p.string());
    ADD_FAILURE() << "no InputError for " << p;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), p.string());
    EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(MeshIo, RoundTripEachFormatExactly) {
  const fs::path d = tempDir();
  const TriangleMesh m = sampleMesh();
  for (const char* ext : {"ply", "stl", "obj"}) {
    const fs::path p = d / (std::string("m.") + ext);
    writeMesh(p.string(), m);
    const TriangleMesh r = readMesh(p.string());
    SCOPED_TRACE(ext);
    expectSameMesh(m, r);
    // STL welding recovers the shared vertices: same vertex count as the original.
    EXPECT_EQ(r.vertices.size(), m.vertices.size());
  }
  fs::remove_all(d);
}

TEST(MeshIo, OutputIsByteDeterministicAndWellFormed) {
  const fs::path d = tempDir();
  const TriangleMesh m = sampleMesh();
  for (const char* ext : {"ply", "stl", "obj"}) {
    const fs::path a = d / (std::string("a.") + ext), b = d / (std::string("b.") + ext);
    writeMesh(a.string(), m);
    writeMesh(b.string(), m);
    EXPECT_EQ(slurp(a), slurp(b)) << ext;
  }
  const std::string ply = slurp(d / "a.ply");
  EXPECT_EQ(ply.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);
  const std::string header_end = "end_header\n";
  const auto body = ply.find(header_end) + header_end.size();
  EXPECT_EQ(ply.size() - body, 12 * m.vertices.size() + 13 * m.triangles.size());
  EXPECT_EQ(slurp(d / "a.stl").size(), 84 + 50 * m.triangles.size());
  fs::remove_all(d);
}

TEST(MeshIo, ReadsAsciiPlyWithQuadsAndExtraProperties) {
  const fs::path d = tempDir();
  const fs::path p = d / "quad.ply";
  spit(p,
       "ply\nformat ascii 1.0\ncomment a unit square and a triangle\n"
       "element vertex 5\nproperty double x\nproperty double y\nproperty double z\n"
       "property uchar red\n"
       "element face 2\nproperty list uchar uint vertex_indices\nend_header\n"
       "0 0 0 9\n1 0 0 9\n1 1 0 9\n0 1 0 9\n0.5 0.5 2 9\n4 0 1 2 3\n3 0 1 4\n");
  const TriangleMesh m = readMesh(p.string());
  ASSERT_EQ(m.vertices.size(), 5u);
  ASSERT_EQ(m.triangles.size(), 3u);  // the quad fan-triangulated
  EXPECT_EQ(m.triangles[0], (std::array<std::uint32_t, 3>{0, 1, 2}));
  EXPECT_EQ(m.triangles[1], (std::array<std::uint32_t, 3>{0, 2, 3}));
  EXPECT_FLOAT_EQ(m.vertices[4].z(), 2.0f);
  fs::remove_all(d);
}

TEST(MeshIo, ReadsBigEndianPly) {
  const fs::path d = tempDir();
  const fs::path p = d / "be.ply";
  std::string s = "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\n"
                  "property float y\nproperty float z\nelement face 1\n"
                  "property list uchar int vertex_indices\nend_header\n";
  auto putBE = [&](std::uint32_t v) {
    for (int i = 3; i >= 0; --i) s.push_back(char((v >> (8 * i)) & 0xFF));
  };
  const float coords[9] = {0, 0, 0, 1.5f, 0, 0, 0, 2.5f, 0};
  for (float f : coords) {
    std::uint32_t bits;
    std::memcpy(&bits, &f, 4);
    putBE(bits);
  }
  s.push_back(char(3));
  for (std::uint32_t i : {0u, 1u, 2u}) putBE(i);
  spit(p, s);
  const TriangleMesh m = readMesh(p.string());
  ASSERT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(m.vertices[1].x(), 1.5f);
  EXPECT_EQ(m.vertices[2].y(), 2.5f);
  EXPECT_EQ(m.triangles[0], (std::array<std::uint32_t, 3>{0, 1, 2}));
  fs::remove_all(d);
}

TEST(MeshIo, ReadsAsciiStlAndWeldsVertices) {
  const fs::path d = tempDir();
  const fs::path p = d / "two.stl";
  spit(p,
       "solid two triangles\n"
       " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 1 1 0\n"
       "  endloop\n endfacet\n"
       " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 1 0\n   vertex -0 1 0\n"
       "  endloop\n endfacet\nendsolid two triangles\n");
  const TriangleMesh m = readMesh(p.string());
  EXPECT_EQ(m.vertices.size(), 4u);  // 6 corners, 2 shared
  ASSERT_EQ(m.triangles.size(), 2u);
  EXPECT_EQ(m.triangles[1][0], m.triangles[0][0]);
  EXPECT_EQ(m.triangles[1][1], m.triangles[0][2]);
  fs::remove_all(d);
}

TEST(MeshIo, ReadsObjPolygonsSlashFormsAndNegativeIndices) {
  const fs::path d = tempDir();
  const fs::path p = d / "poly.obj";
  spit(p,
       "# comment\nmtllib x.mtl\no thing\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
       "f 1/1/1 2/1/1 3/1/1 4/1/1\nv 0 0 5\nf -5//1 -4//1 -1//1\ns off\n");
  const TriangleMesh m = readMesh(p.string());
  ASSERT_EQ(m.vertices.size(), 5u);
  ASSERT_EQ(m.triangles.size(), 3u);
  EXPECT_EQ(m.triangles[1], (std::array<std::uint32_t, 3>{0, 2, 3}));
  EXPECT_EQ(m.triangles[2], (std::array<std::uint32_t, 3>{0, 1, 4}));
  fs::remove_all(d);
}

TEST(MeshIo, MalformedPlyIsInputError) {
  const fs::path d = tempDir();
  const TriangleMesh m = sampleMesh();
  const fs::path good = d / "good.ply";
  writeMesh(good.string(), m);
  const std::string bytes = slurp(good);

  spit(d / "truncated.ply", bytes.substr(0, bytes.size() - 7));
  expectInputError(d / "truncated.ply");
  spit(d / "noheader.ply", bytes.substr(0, 40));
  expectInputError(d / "noheader.ply");
  spit(d / "magic.ply", "plx\n" + bytes.substr(4));
  expectInputError(d / "magic.ply");
  spit(d / "index.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
       "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
       "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
  expectInputError(d / "index.ply");
  spit(d / "word.ply",
       "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
       "property float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n"
       "0 zero 0\n");
  try {
    readMesh((d / "word.ply").string());
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 10);  // line of the bad number
  }
  expectInputError(d / "missing.ply");
  fs::remove_all(d);
}

TEST(MeshIo, MalformedStlIsInputError) {
  const fs::path d = tempDir();
  const fs::path good = d / "good.stl";
  writeMesh(good.string(), sampleMesh());
  const std::string bytes = slurp(good);
  spit(d / "truncated.stl", bytes.substr(0, bytes.size() - 10));
  expectInputError(d / "truncated.stl");
  spit(d / "short.stl", bytes.substr(0, 50));
  expectInputError(d / "short.stl");
  spit(d / "ascii.stl",
       "solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n"
       "  endloop\n endfacet\nendsolid x\n");
  expectInputError(d / "ascii.stl");
  spit(d / "unended.stl",
       "solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n"
       "   vertex 0 1 0\n  endloop\n endfacet\n");
  expectInputError(d / "unended.stl");
  fs::remove_all(d);
}

TEST(MeshIo, MalformedObjIsInputError) {
  const fs::path d = tempDir();
  spit(d / "range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
  expectInputError(d / "range.obj");
  spit(d / "zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
  expectInputError(d / "zero.obj");
  spit(d / "number.obj", "v 0 0 0\nv 1 x 0\n");
  try {
    readMesh((d / "number.obj").string());
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.file(), (d / "number.obj").string());
  }
  spit(d / "short.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n");
  expectInputError(d / "short.obj");
  // Truncated in the middle of a vertex line.
  spit(d / "truncated.obj", "v 0 0 0\nv 1 0 0\nv 0 1");
  expectInputError(d / "truncated.obj");
  fs::remove_all(d);
}

TEST(MeshIo, UnknownExtensionIsInputError) {
  EXPECT_THROW(readMesh("/tmp/x.off"), InputError);
  EXPECT_THROW(writeMesh("/tmp/x.vtk", sampleMesh()), InputError);
}

// OpenVDB level-set files (see level_set_file.h). The writer builds a FloatGrid from the active
// voxels, flood-fills the signs of the inactive region, prunes, lets openvdb::io::File write it
// under a temporary name, replaces the random UUID in the header with a content-derived tag and
// renames the file into place. The reader parses the file from memory with stream exceptions on
// (OpenVDB does not check its reads; see readNamedGrid), checks the grid's type, class, background
// and transform, and lists its active voxels in (k, j, i) order.
#include "io/level_set_file.h"

#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tools/SignedFloodFill.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <utility>

#include <unistd.h>

#include "io/file_hash.h"
#include "io/input_error.h"

namespace xsect {

namespace {

namespace fs = std::filesystem;

// ---- the header's unique tag ------------------------------------------------------------------

/// OpenVDB's header: magic (int64 0x56444220, "VDB "), file format version (uint32), library
/// major and minor version (uint32 each), has-grid-offsets flag (char), then the UUID as 36
/// characters of text (boost::uuids::to_string). Measured: the only bytes that differ between two
/// writes of the same grid.
constexpr std::size_t kUuidOffset = 8 + 4 + 4 + 4 + 1;
constexpr std::size_t kUuidLength = 36;
constexpr std::int64_t kVdbMagic = 0x56444220;

bool looksLikeUuid(const std::string& s) {
  if (s.size() != kUuidLength) return false;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const bool dash = i == 8 || i == 13 || i == 18 || i == 23;
    if (dash ? s[i] != '-' : !std::isxdigit(static_cast<unsigned char>(s[i]))) return false;
  }
  return true;
}

/// A UUID-shaped tag from SHA-256 of the file with its UUID field zeroed: version nibble 8
/// ("custom", RFC 9562), variant bits 10. Identical contents give identical tags.
std::string contentTag(std::string bytes) {
  bytes.replace(kUuidOffset, kUuidLength, kUuidLength, '0');
  std::string hex = sha256Hex(bytes).substr(0, 32);
  hex[12] = '8';
  const int v = std::stoi(hex.substr(16, 1), nullptr, 16);
  hex[16] = "89ab"[v & 3];
  return hex.substr(0, 8) + "-" + hex.substr(8, 4) + "-" + hex.substr(12, 4) + "-" +
         hex.substr(16, 4) + "-" + hex.substr(20, 12);
}

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot read back the written file");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Overwrites the random UUID of the VDB file at `path` with contentTag(file).
void replaceUuidWithContentTag(const std::string& path) {
  const std::string bytes = readAll(path);
  std::int64_t magic = 0;
  if (bytes.size() >= sizeof magic) std::memcpy(&magic, bytes.data(), sizeof magic);
  if (bytes.size() < kUuidOffset + kUuidLength || magic != kVdbMagic ||
      !looksLikeUuid(bytes.substr(kUuidOffset, kUuidLength)))
    throw std::runtime_error(path + ": unexpected OpenVDB header layout (no UUID at byte " +
                             std::to_string(kUuidOffset) + "); cannot make the file reproducible");
  const std::string tag = contentTag(bytes);
  std::fstream f(path, std::ios::binary | std::ios::in | std::ios::out);
  f.seekp(std::streamoff(kUuidOffset));
  f.write(tag.data(), std::streamsize(tag.size()));
  f.close();
  if (!f) throw std::runtime_error(path + ": cannot rewrite the file header");
}

// ---- writing ----------------------------------------------------------------------------------

void checkWritable(const NarrowBandLevelSet& ls) {
  const GridSpec& g = ls.grid;
  if (ls.coords.size() != ls.values.size())
    throw std::invalid_argument("level set: " + std::to_string(ls.coords.size()) + " coords but " +
                                std::to_string(ls.values.size()) + " values");
  if (!(ls.background > 0.0f) || !std::isfinite(ls.background))
    throw std::invalid_argument("level set: background (band half-width, mm) must be positive "
                                "and finite, got " + std::to_string(ls.background));
  if (!(g.voxel > 0.0) || !std::isfinite(g.voxel))
    throw std::invalid_argument("level set: voxel size (mm) must be positive and finite");
  if (!g.origin.allFinite()) throw std::invalid_argument("level set: grid origin must be finite");
  if (g.dims[0] < 0 || g.dims[1] < 0 || g.dims[2] < 0)
    throw std::invalid_argument("level set: grid dims must not be negative");
  for (std::size_t n = 0; n < ls.values.size(); ++n)
    if (!std::isfinite(ls.values[n]))
      throw std::invalid_argument("level set: value " + std::to_string(n) + " is not finite");
}

/// The grid of the file comment: active voxels set, inactive signs flood-filled, pruned.
openvdb::FloatGrid::Ptr buildGrid(const NarrowBandLevelSet& ls, const std::string& gridName) {
  const GridSpec& g = ls.grid;
  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(ls.background);
  grid->setTransform(openvdb::math::Transform::createLinearTransform(g.voxel));
  grid->transform().postTranslate(openvdb::Vec3d(g.origin.x(), g.origin.y(), g.origin.z()));
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  grid->setName(gridName);
  grid->setSaveFloatAsHalf(false);  // distances keep full float precision: exact round trip

  auto acc = grid->getAccessor();
  for (std::size_t n = 0; n < ls.coords.size(); ++n) {
    const auto& c = ls.coords[n];
    const openvdb::Coord ijk(c[0], c[1], c[2]);
    if (acc.isValueOn(ijk))
      throw std::invalid_argument("level set: voxel (" + std::to_string(c[0]) + ", " +
                                  std::to_string(c[1]) + ", " + std::to_string(c[2]) +
                                  ") is listed twice");
    acc.setValueOn(ijk, ls.values[n]);
  }
  // Inactive voxels enclosed by the band become -background (inside), as level-set consumers
  // (meshing, CSG, ray marching, pyopenvdb users) assume; then collapse uniform nodes to tiles.
  openvdb::tools::signedFloodFill(grid->tree());
  openvdb::tools::pruneLevelSet(grid->tree());

  grid->insertMeta("xsect_units", openvdb::StringMetadata("mm"));
  grid->insertMeta("creator", openvdb::StringMetadata(std::string("xsect ") + XSECT_VERSION));
  grid->insertMeta("xsect_frame",
                   openvdb::StringMetadata("xsect world frame (mm): the frame of the input slices' "
                                           "poses and of xsect's meshes; distances negative inside"));
  grid->insertMeta("xsect_grid_dims",
                   openvdb::Vec3IMetadata(openvdb::Vec3i(g.dims[0], g.dims[1], g.dims[2])));
  return grid;
}

/// A fresh name next to `path` (same folder, so the final rename stays on one file system).
std::string temporarySibling(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  return path + ".partial-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
}

void writeGridFile(const std::string& path, const openvdb::FloatGrid::Ptr& grid) {
  openvdb::io::File file(path);
  // Active-mask compression only: OpenVDB never zips level-set grids (Archive::setGridCompression
  // drops COMPRESS_ZIP for them), and its default Blosc, which would save ~10% here, is an optional
  // dependency that some OpenVDB builds (and so some readers) lack.
  file.setCompression(openvdb::io::COMPRESS_ACTIVE_MASK);
  openvdb::GridCPtrVec grids{grid};
  try {
    file.write(grids);
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": cannot write OpenVDB file: " + e.what());
  }
  file.close();
}

// ---- reading ----------------------------------------------------------------------------------

/// Above this many active voxels (16 bytes each once listed) the file is refused rather than
/// exhausting memory: a narrow band of a 2048^3 grid stays well below it.
constexpr openvdb::Index64 kMaxActiveVoxels = openvdb::Index64(1) << 28;
/// Active tiles (uniform active blocks, which level-set tools do not make: a band keeps its
/// voxels in leaves) are expanded voxel by voxel, up to this many voxels (512 leaf-sized tiles): a
/// few bytes of a corrupt file can otherwise claim billions. The fuzzer (scripts/fuzz.sh) found a
/// 25 kB file whose corrupt tiles claimed 10 million voxels under the former limit of 2^24: 3 s
/// to read, 65 s under AddressSanitizer (tests/fuzz/corpus/vdb/crash-active-tiles-10M-voxels).
constexpr openvdb::Index64 kMaxActiveTileVoxels = openvdb::Index64(1) << 18;

/// A read-only stream buffer over bytes in memory (with seeking, which OpenVDB may use).
class MemoryBuffer : public std::streambuf {
 public:
  explicit MemoryBuffer(std::string& bytes) {
    char* b = bytes.data();
    setg(b, b, b + bytes.size());
  }

 protected:
  pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode) override {
    const off_type base = dir == std::ios_base::beg ? 0
                          : dir == std::ios_base::cur ? gptr() - eback()
                                                      : egptr() - eback();
    return seekpos(pos_type(base + off), std::ios_base::in);
  }
  pos_type seekpos(pos_type pos, std::ios_base::openmode) override {
    if (off_type(pos) < 0 || off_type(pos) > egptr() - eback()) return pos_type(off_type(-1));
    setg(eback(), eback() + off_type(pos), egptr());
    return pos;
  }
};

/// Bounds-checked little-endian reads over the file's bytes; InputError "file" past the end.
class Cursor {
 public:
  Cursor(const std::string& path, const std::string& bytes) : path_(path), bytes_(bytes) {}
  std::size_t pos() const { return pos_; }
  std::size_t remaining() const { return bytes_.size() - pos_; }
  void seek(std::int64_t pos, const char* what) {
    if (pos < std::int64_t(pos_) || std::uint64_t(pos) > bytes_.size())
      fail(std::string(what) + " points outside the file");
    pos_ = std::size_t(pos);
  }
  void skip(std::uint64_t n, const char* what) {
    if (n > remaining()) fail(std::string(what) + " runs past the end of the file");
    pos_ += std::size_t(n);
  }
  template <typename T>
  T read(const char* what) {
    T v;
    if (sizeof v > remaining()) fail(std::string(what) + " runs past the end of the file");
    std::memcpy(&v, bytes_.data() + pos_, sizeof v);
    pos_ += sizeof v;
    return v;
  }
  /// io::readString's layout: uint32 length, then the characters.
  std::string string(const char* what) {
    const auto n = read<std::uint32_t>(what);
    if (n > remaining()) fail(std::string(what) + " runs past the end of the file");
    std::string s = bytes_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(path_, "file", "corrupt or truncated OpenVDB file: " + what + " (byte " +
                                        std::to_string(pos_) + " of " + std::to_string(bytes_.size()) + ")");
  }

 private:
  const std::string& path_;
  const std::string& bytes_;
  std::size_t pos_ = 0;
};

/// The type name of OpenVDB's delayed-load metadata (per-leaf masks and compressed sizes, only
/// used to load leaves lazily from a memory-mapped file), and a name of the same length that no
/// reader registers.
const std::string kDelayedLoadType = "__delayedload";
const std::string kIgnoredType = "xsect_ignored";

/// MetaMap::readMeta's layout: uint32 count, then per entry name, type name, uint32 value size
/// and the value. OpenVDB reads a value of a registered fixed-size type (vec3i, double, ...) by its
/// type's size, not the stated one, so the two must agree or every later read is shifted
/// (measured: 1.7 GB allocated for a flipped size byte). Appends to `delayedLoad` where each
/// delayed-load type name starts.
void checkMetaMap(Cursor& c, std::vector<std::size_t>& delayedLoad) {
  const auto count = c.read<std::uint32_t>("metadata count");
  for (std::uint32_t n = 0; n < count; ++n) {
    c.string("metadata name");
    const std::size_t typeAt = c.pos() + 4;
    const std::string type = c.string("metadata type");
    const auto size = c.read<std::uint32_t>("metadata value size");
    if (type == kDelayedLoadType) {
      delayedLoad.push_back(typeAt);
    } else if (type != openvdb::StringMetadata::staticTypeName() &&
               openvdb::Metadata::isRegisteredType(type) &&
               size != openvdb::Metadata::createMetadata(type)->size()) {
      c.fail("metadata of type " + type + " with a value of " + std::to_string(size) + " bytes");
    }
    c.skip(size, "metadata value");
  }
}

/// Checks, before OpenVDB parses the file, every length and offset that OpenVDB would trust for an
/// allocation ahead of reading: the header, the file's metadata, each grid's descriptor, offsets,
/// metadata and transform type name. Measured without it (random byte flips in a 21 kB file):
/// single corrupt bytes made OpenVDB zero-fill strings of up to 4 GB before failing, and a
/// corrupt version number (an old layout) 800 MB. The tree is left to OpenVDB: its buffers have
/// fixed sizes, and its reads are bounded by the stream. Versions before 222 (OpenVDB 1.0, 2013)
/// are refused, and so are newer versions than this OpenVDB writes (it only warns about them,
/// then misreads: a flipped version byte cost 3 GB).
///
/// Returns where delayed-load metadata type names start. OpenVDB parses that metadata's value
/// without holding it to its stated size (a corrupt inner length desynchronises every later read,
/// measured: 1.7 GB allocated) and Blosc-decompresses it; the reader does not load lazily, so
/// it renames the type (neutraliseDelayedLoadMetadata) and OpenVDB keeps the value as opaque
/// bytes of the stated size.
std::vector<std::size_t> checkEnvelope(const std::string& path, const std::string& bytes) {
  std::vector<std::size_t> delayedLoad;
  Cursor c(path, bytes);
  if (bytes.size() < sizeof kVdbMagic || c.read<std::int64_t>("header") != kVdbMagic)
    throw InputError(path, "file", "not an OpenVDB file (no \"VDB\" magic number)");
  const auto version = c.read<std::uint32_t>("header");
  if (version < openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION)
    throw InputError(path, "file", "OpenVDB file format version " + std::to_string(version) +
                                       " predates OpenVDB 1.0 (version 222); re-save it with a "
                                       "current OpenVDB");
  if (version > openvdb::OPENVDB_FILE_VERSION)  // OpenVDB only warns, then misreads
    throw InputError(path, "file", "OpenVDB file format version " + std::to_string(version) +
                                       " is newer than this build reads (" +
                                       std::to_string(openvdb::OPENVDB_FILE_VERSION) + ")");
  c.skip(4 + 4, "header");  // library version
  const bool hasOffsets = c.read<char>("header") != 0;
  c.skip(kUuidLength, "header");
  checkMetaMap(c, delayedLoad);
  const auto gridCount = c.read<std::int32_t>("grid count");
  if (gridCount < 0) c.fail("negative grid count");
  for (std::int32_t g = 0; g < gridCount; ++g) {
    c.string("grid name");
    c.string("grid type");
    c.string("grid instance parent");
    const auto gridPos = c.read<std::int64_t>("grid offsets");
    const auto blockPos = c.read<std::int64_t>("grid offsets");
    const auto endPos = c.read<std::int64_t>("grid offsets");
    if (hasOffsets) {
      if (blockPos < gridPos || endPos < blockPos) c.fail("grid offsets out of order");
      c.seek(gridPos, "grid offset");
    }
    // Blosc and ZIP blocks state their sizes, and OpenVDB allocates what they state before
    // reading them (measured: a 25 kB file with a corrupt Blosc size asked for 28 GB). xsect
    // writes active-mask compression only (writeLevelSetVdb), so those codecs are refused.
    const auto compression = c.read<std::uint32_t>("grid compression");
    if (compression & (openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_BLOSC))
      throw InputError(path, "file",
                       "a ZIP- or Blosc-compressed grid is not read (a corrupt block size would make "
                       "OpenVDB allocate it unchecked): save it with active-mask compression only, as "
                       "xsect writes its level sets");
    checkMetaMap(c, delayedLoad);
    c.string("transform type");
    if (!hasOffsets) break;  // the next grid starts after this one's tree: left to OpenVDB
    if (c.pos() > std::uint64_t(blockPos)) c.fail("grid metadata overlaps the grid's data");
    c.seek(endPos, "grid end offset");
  }
  return delayedLoad;
}

void neutraliseDelayedLoadMetadata(std::string& bytes, const std::vector<std::size_t>& typeNames) {
  for (const std::size_t at : typeNames) bytes.replace(at, kIgnoredType.size(), kIgnoredType);
}

std::string gridNames(const openvdb::GridPtrVec& grids) {
  std::string names;
  for (const auto& g : grids) names += (names.empty() ? "'" : ", '") + g->getName() + "'";
  return names.empty() ? "none" : names;
}

/// Reads every grid of the file and returns the one named `gridName`.
/// OpenVDB's readers do not check their reads: a truncated file yields zeros or stale bytes and
/// is accepted (measured: files cut anywhere past the header read "successfully", some with fewer
/// voxels). So the bytes are parsed through io::Stream from memory, with stream exceptions on:
/// any read past the end throws, and becomes InputError "file".
openvdb::GridBase::Ptr readNamedGrid(const std::string& path, const std::string& gridName) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw InputError(path, "file", "no such file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "file", "cannot be opened");
  std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw InputError(path, "file", "cannot be read");
  neutraliseDelayedLoadMetadata(bytes, checkEnvelope(path, bytes));
  MemoryBuffer buffer(bytes);
  std::istream is(&buffer);
  is.exceptions(std::ios::failbit | std::ios::badbit);
  openvdb::GridPtrVecPtr grids;
  try {
    openvdb::io::Stream stream(is, /*delayLoad=*/false);
    grids = stream.getGrids();
  } catch (const std::exception& e) {
    // (OpenVDB leaks the node it was reading when a read throws, ~250 kB: harmless for a
    // command that then exits with code 2, worth knowing for a long-lived caller.)
    const bool shortRead = dynamic_cast<const std::ios_base::failure*>(&e) != nullptr;
    throw InputError(path, "file", shortRead ? "corrupt or truncated OpenVDB file (a read ran past "
                                               "the end of its " + std::to_string(bytes.size()) +
                                               " bytes)"
                                             : std::string("not a readable OpenVDB file (") +
                                                   e.what() + ")");
  }
  if (!grids) throw InputError(path, "file", "not a readable OpenVDB file");
  for (const auto& g : *grids)
    if (g && g->getName() == gridName) return g;
  throw InputError(path, "grid", "no grid named '" + gridName + "' (grids: " + gridNames(*grids) + ")");
}

/// Origin (centre of index (0,0,0), mm) and voxel edge (mm) of an axis-aligned uniform transform.
std::pair<Vec3, double> axisAlignedFrame(const std::string& path, const openvdb::math::Transform& xf) {
  if (!xf.isLinear())
    throw InputError(path, "transform", "not linear (" + xf.mapType() + "); xsect grids are regular");
  openvdb::Mat4d m;  // row vectors: world = index * M
  try {
    m = xf.baseMap()->getAffineMap()->getConstMat4();
  } catch (const std::exception& e) {  // e.g. ArithmeticError: a singular scale
    throw InputError(path, "transform", std::string("invalid (") + e.what() + ")");
  }
  const double s = m[0][0];
  if (!(s > 0.0) || !std::isfinite(s))
    throw InputError(path, "transform", "voxel size must be positive and finite");
  const double tol = 1e-9 * s;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (std::abs(m[r][c] - (r == c ? s : 0.0)) > tol)
        throw InputError(path, "transform",
                         "not an axis-aligned uniform scale (" + xf.mapType() +
                             "); xsect grids have cubic voxels along x, y, z");
  const Vec3 origin(m[3][0], m[3][1], m[3][2]);
  if (!origin.allFinite()) throw InputError(path, "transform", "translation is not finite");
  return {origin, s};
}

/// The float level-set grid `gridName` of `path`, checked (InputError otherwise).
openvdb::FloatGrid::Ptr loadLevelSetGrid(const std::string& path, const std::string& gridName) {
  openvdb::initialize();  // idempotent
  const openvdb::GridBase::Ptr base = readNamedGrid(path, gridName);
  openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
  if (!grid)
    throw InputError(path, "grid", "grid '" + gridName + "' holds " + base->valueType() +
                                       " values (" + base->type() + "), not float");
  if (grid->getGridClass() != openvdb::GRID_LEVEL_SET)
    throw InputError(path, "grid class",
                     "'" + openvdb::GridBase::gridClassToString(grid->getGridClass()) +
                         "', not a level set");
  const float bg = grid->background();
  if (!(bg > 0.0f) || !std::isfinite(bg))
    throw InputError(path, "background", "must be positive and finite, got " + std::to_string(bg));
  axisAlignedFrame(path, grid->transform());  // validates
  return grid;
}

using Voxel = std::pair<std::array<int, 3>, float>;

/// Every active voxel (active tiles expanded), sorted by (k, j, i).
std::vector<Voxel> activeVoxels(const std::string& path, const openvdb::FloatGrid& grid) {
  const openvdb::Index64 count = grid.activeVoxelCount();
  if (count > kMaxActiveVoxels)
    throw InputError(path, "grid", std::to_string(count) + " active voxels, more than the " +
                                       std::to_string(kMaxActiveVoxels) + " xsect reads");
  const openvdb::Index64 inTiles = count - grid.tree().activeLeafVoxelCount();
  if (inTiles > kMaxActiveTileVoxels)
    throw InputError(path, "grid", "active tiles cover " + std::to_string(inTiles) +
                                       " voxels (more than " + std::to_string(kMaxActiveTileVoxels) +
                                       "); a narrow band keeps its voxels in leaves");
  std::vector<Voxel> voxels;
  voxels.reserve(std::size_t(count));
  for (auto it = grid.cbeginValueOn(); it; ++it) {
    if (!std::isfinite(*it))
      throw InputError(path, "values", "non-finite distance at an active voxel");
    openvdb::CoordBBox box;
    it.getBoundingBox(box);  // one voxel, or a tile's extent
    for (auto c = box.begin(); c; ++c) voxels.push_back({{(*c)[0], (*c)[1], (*c)[2]}, *it});
  }
  std::sort(voxels.begin(), voxels.end(), [](const Voxel& a, const Voxel& b) {
    return std::tie(a.first[2], a.first[1], a.first[0]) < std::tie(b.first[2], b.first[1], b.first[0]);
  });
  return voxels;
}

/// GridSpec::dims from the writer's "xsect_grid_dims" metadata; false when the file has none.
bool storedDims(const std::string& path, const openvdb::FloatGrid& grid, std::array<int, 3>& dims) {
  const openvdb::Metadata::ConstPtr meta = grid["xsect_grid_dims"];
  if (!meta) return false;
  const auto v = openvdb::DynamicPtrCast<const openvdb::Vec3IMetadata>(meta);
  if (!v) throw InputError(path, "xsect_grid_dims", "must be a vec3i, not " + meta->typeName());
  const openvdb::Vec3i d = v->value();
  if (d[0] < 0 || d[1] < 0 || d[2] < 0)
    throw InputError(path, "xsect_grid_dims", "must not be negative");
  dims = {d[0], d[1], d[2]};
  return true;
}

/// For files without "xsect_grid_dims": the box from index min(0, lowest active index) to the
/// highest active index, per axis; returns the shift (the new index 0) and sets dims.
std::array<int, 3> boxOfActiveVoxels(const std::string& path, const std::vector<Voxel>& voxels,
                                     std::array<int, 3>& dims) {
  std::array<int, 3> shift{0, 0, 0};
  dims = {0, 0, 0};
  if (voxels.empty()) return shift;
  std::array<std::int64_t, 3> lo{0, 0, 0}, hi{std::numeric_limits<std::int64_t>::min(),
                                             std::numeric_limits<std::int64_t>::min(),
                                             std::numeric_limits<std::int64_t>::min()};
  for (const Voxel& v : voxels)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min<std::int64_t>(lo[a], v.first[a]);
      hi[a] = std::max<std::int64_t>(hi[a], v.first[a]);
    }
  for (int a = 0; a < 3; ++a) {
    const std::int64_t extent = hi[a] - lo[a] + 1;
    if (extent > std::numeric_limits<int>::max())
      throw InputError(path, "grid", "active voxels span more than 2^31 voxels");
    shift[a] = int(lo[a]);
    dims[a] = int(extent);
  }
  return shift;
}

}  // namespace

void writeLevelSetVdb(const std::string& path, const NarrowBandLevelSet& ls,
                      const std::string& gridName) {
  checkWritable(ls);
  openvdb::initialize();  // idempotent
  const openvdb::FloatGrid::Ptr grid = buildGrid(ls, gridName);
  const std::string partial = temporarySibling(path);
  try {
    writeGridFile(partial, grid);
    replaceUuidWithContentTag(partial);
    std::error_code ec;
    fs::rename(partial, path, ec);
    if (ec) throw std::runtime_error(path + ": cannot move the written file into place: " + ec.message());
  } catch (...) {
    std::error_code ignored;
    fs::remove(partial, ignored);
    throw;
  }
}

NarrowBandLevelSet readLevelSetVdb(const std::string& path, const std::string& gridName) {
  const openvdb::FloatGrid::Ptr grid = loadLevelSetGrid(path, gridName);
  const auto [origin, voxel] = axisAlignedFrame(path, grid->transform());
  std::vector<Voxel> voxels = activeVoxels(path, *grid);

  NarrowBandLevelSet ls;
  ls.background = grid->background();
  ls.grid.voxel = voxel;
  ls.grid.origin = origin;
  if (!storedDims(path, *grid, ls.grid.dims)) {
    const std::array<int, 3> shift = boxOfActiveVoxels(path, voxels, ls.grid.dims);
    ls.grid.origin = origin + voxel * Vec3(shift[0], shift[1], shift[2]);
    for (Voxel& v : voxels)
      for (int a = 0; a < 3; ++a) v.first[a] -= shift[a];
  }
  ls.coords.reserve(voxels.size());
  ls.values.reserve(voxels.size());
  for (const Voxel& v : voxels) {
    ls.coords.push_back(v.first);
    ls.values.push_back(v.second);
  }
  return ls;
}

float levelSetValueAt(const std::string& path, const Vec3& worldPoint, const std::string& gridName) {
  if (!worldPoint.allFinite()) throw std::invalid_argument("levelSetValueAt: point is not finite");
  const openvdb::FloatGrid::Ptr grid = loadLevelSetGrid(path, gridName);
  const openvdb::Vec3d index =
      grid->transform().worldToIndex(openvdb::Vec3d(worldPoint.x(), worldPoint.y(), worldPoint.z()));
  // Beyond OpenVDB's coordinate range nothing is stored: the point is far outside.
  constexpr double kLimit = double(1 << 30);
  if (std::abs(index[0]) > kLimit || std::abs(index[1]) > kLimit || std::abs(index[2]) > kLimit)
    return grid->background();
  return grid->tree().getValue(openvdb::Coord::round(index));
}

}  // namespace xsect

// The reader harnesses (see reader_harnesses.h).
#include "tests/fuzz/reader_harnesses.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "io/contour_file.h"
#include "io/csl_file.h"
#include "io/image_io.h"
#include "io/input_error.h"
#include "io/label_volume_file.h"
#include "io/level_set_file.h"
#include "io/mesh_io.h"
#include "io/meta_image.h"
#include "io/phantom_spec.h"
#include "io/plus_device_set.h"
#include "io/run_config.h"
#include "io/slices_file.h"
#include "io/truth_file.h"

namespace xsect::fuzz {
namespace {

namespace fs = std::filesystem;

void readCsl(const std::string& path) {
  std::vector<std::string> warnings;
  readCslFile(path, &warnings);
}
void readSlices(const std::string& path) {
  std::vector<std::string> warnings;
  readSlicesFile(path, &warnings);
}
void readPoses(const std::string& path) { readPosesFile(path); }
void readConfig(const std::string& path) { readRunConfig(path); }
void readAnyMesh(const std::string& path) { readMesh(path); }
void readNrrd(const std::string& path) { readLabelVolumeNrrd(path); }
void readTruth(const std::string& path) { readTruthFile(path); }
void readPhantom(const std::string& path) { readPhantomSpec(path); }
void readVdb(const std::string& path) { readLevelSetVdb(path); }
void readImage(const std::string& path) { readGreyImage(path, "fuzz input", "image"); }
void readContour(const std::string& path) { readContourFile(path); }
/// A MetaImage sequence: the header and its frames (frames of at most 4 MB: a mutated DimSize
/// may ask for more than the fuzzer's memory, which the run's own memory check would refuse).
void readMetaImage(const std::string& path) {
  const MetaImageHeader h = readMetaImageHeader(path);
  if (h.frameBytes() > (std::int64_t(1) << 22)) return;
  MetaImageFrames frames(h);
  for (int i = 0; i < h.frames && i < 64; ++i) frames.next();
}
void readDeviceSet(const std::string& path) {
  const PlusDeviceSet d = readPlusDeviceSet(path);
  plusFieldOfView(d, 64, 48);
  chainTransform(d.transforms, "Image", "Reference");
}

// This process's scratch folder. It holds (empty) frame.png, mask.png and slices.yaml so that the
// slice lists and configurations naming them get past the check that their files exist and reach
// the rest of the reader.
fs::path scratchFolder() {
  const fs::path dir = fs::temp_directory_path() / ("xsect-fuzz-" + std::to_string(::getpid()));
  if (!fs::exists(dir / "frame.png")) {
    fs::create_directories(dir);
    std::ofstream(dir / "frame.png").put('\0');
    std::ofstream(dir / "mask.png").put('\0');
    std::ofstream(dir / "slices.yaml").put('\n');
  }
  return dir;
}

}  // namespace

std::vector<ReaderHarness> readerHarnesses() {
  return {
      {"csl", ".csl", readCsl},           {"slices", ".yaml", readSlices},
      {"config", ".yaml", readConfig},    {"mesh_ply", ".ply", readAnyMesh},
      {"mesh_stl", ".stl", readAnyMesh},  {"mesh_obj", ".obj", readAnyMesh},
      {"nrrd", ".nrrd", readNrrd},        {"truth", ".yaml", readTruth},
      {"phantom", ".yaml", readPhantom},  {"vdb", ".vdb", readVdb},
      {"image", ".png", readImage},       {"poses", ".yaml", readPoses},
      {"contour", ".contour", readContour}, {"plus_mha", ".mha", readMetaImage},
      {"plus_xml", ".xml", readDeviceSet},
  };
}

ReaderHarness readerHarness(const std::string& name) {
  for (const ReaderHarness& h : readerHarnesses())
    if (h.name == name) return h;
  throw std::invalid_argument("no reader harness called " + name);
}

void removeScratchFolder() {
  std::error_code ignored;
  fs::remove_all(scratchFolder(), ignored);
}

bool readFuzzInput(const ReaderHarness& harness, const std::uint8_t* data, std::size_t size,
                   std::string* refusal) {
  const fs::path path = scratchFolder() / ("input-" + harness.name + harness.extension);
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    if (!out) throw std::runtime_error("cannot write the fuzz scratch file " + path.string());
  }
  try {
    harness.read(path.string());
    return true;
  } catch (const InputError& e) {
    if (refusal) *refusal = e.what();
    return false;
  }
}

}  // namespace xsect::fuzz

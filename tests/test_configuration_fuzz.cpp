// Issue 48's configuration fuzzer: random settings within and beyond their ranges (numbers from
// 1e-9 to 1e300, negative, not numbers, unknown names, duplicated blocks), random poses (other
// units, a slice moved kilometres away, degenerate matrices), frames stored at another bit depth,
// and random destinations in a sandbox holding the inputs (the input folder, ".", an ancestor, an
// input file, a user's folder, a link, earlier outputs, fresh folders). Every run must end within
// a minute with exit 0, 1 or 2; the inputs stay byte-identical; a refused destination gets exit 2;
// the destination is afterwards a complete output folder of xsect (exit 0) or as it was before;
// no staging folder is left. Two shards of 60 configurations (CI); XSECT_CONFIG_FUZZ_CONFIGS sets
// the count per shard and XSECT_CONFIG_FUZZ_SEED the first seed (scripts/fuzz.sh runs more).
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <yaml-cpp/yaml.h>

#include <map>
#include <random>

#include "cli.h"
#include "io/file_hash.h"
#include "io/output_destination.h"
#include "phantom_runs.h"

namespace fs = std::filesystem;
using namespace xsect;

namespace {

std::uint64_t envNumber(const char* name, std::uint64_t fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::strtoull(v, nullptr, 10) : fallback;
}

/// Every file and link under `dir` with its content's hash ("" for folders), relative paths.
std::map<std::string, std::string> tree(const fs::path& dir) {
  std::map<std::string, std::string> t;
  if (!fs::exists(dir)) return t;
  if (!fs::is_directory(dir)) return {{".", sha256File(dir.string())}};
  for (auto it = fs::recursive_directory_iterator(dir); it != fs::recursive_directory_iterator(); ++it) {
    const std::string rel = fs::relative(it->path(), dir).string();
    if (it->is_symlink()) {
      t[rel] = "link:" + fs::read_symlink(it->path()).string();
      it.disable_recursion_pending();
    } else {
      t[rel] = it->is_regular_file() ? sha256File(it->path().string()) : "";
    }
  }
  return t;
}

/// The settings drawn from, each with values within and beyond its range.
const std::vector<std::pair<std::string, std::vector<std::string>>> kSettings = {
    {"segmentation.method", {"threshold", "otsu", "labels", "bogus"}},
    {"segmentation.threshold", {"0", "64", "128", "250", "-1e9", "1e12", "abc"}},
    {"segmentation.sigma_px", {"0", "1.5", "4", "1e3", "1e9", "-1"}},
    {"segmentation.open_radius_px", {"0", "1", "3", "200", "1e9", "1e30", "-2"}},
    {"segmentation.close_radius_px", {"0", "2", "6", "500", "1e9", "2.5"}},
    {"segmentation.min_area_mm2", {"0", "0.5", "20", "1e4", "1e300", "-3"}},
    {"segmentation.simplify_mm", {"0", "0.1", "5", "1e6"}},
    {"conformity.enforce", {"true", "false", "maybe"}},
    {"conformity.pose_correction", {"none", "translation", "rigid"}},
    {"conformity.band_mm", {"0.01", "2", "1e6", "0"}},
    {"conformity.max_correction_mm", {"1e-9", "5", "1e9"}},
    {"reconstruction.method", {"nearest_plane", "section_voronoi", "delaunay", "poisson"}},
    {"reconstruction.voxel_size_mm", {"auto", "1e-9", "0.01", "0.05", "0.3", "5", "1e9", "-1"}},
    {"reconstruction.voxel_budget", {"1000", "4000000", "2000000000", "1e30"}},
    {"reconstruction.end_margin_mm", {"auto", "1e-6", "2", "1e6"}},
    {"reconstruction.planes", {"whole", "observed"}},
    {"smoothing.method", {"none", "shepard", "level_set"}},
    {"smoothing.iterations", {"0", "8", "1000"}},
    {"sampling.reach_mm", {"0.001", "2", "1e9"}},
    {"sampling.advice_count", {"0", "3", "100000"}},
    {"output.mesh", {"[ply]", "[stl, obj]", "bogus"}},
    {"run.max_seconds", {"1e-3", "5", "0"}},
};

/// The destinations drawn from (S: the sandbox, I = S/in: the inputs' folder).
enum class Destination { fresh, input_folder, dot, ancestor, input_file, user_folder, images, nested, inside_input,
                         earlier_output, config_default, link };
constexpr int kDestinations = 12;
bool refused(Destination d) {
  return d == Destination::input_folder || d == Destination::dot || d == Destination::ancestor ||
         d == Destination::input_file || d == Destination::user_folder || d == Destination::images ||
         d == Destination::link;
}

struct Sandbox {
  fs::path root, in, out, cwd;
  std::string args;  ///< the command's arguments
  std::string what;  ///< for failure messages
  bool clean = true;  ///< inputs and settings unchanged: only the destination can be refused
  Destination dest = Destination::fresh;
};

void setKey(YAML::Node root, const std::string& dotted, const std::string& value) {
  const auto dot = dotted.find('.');
  root[dotted.substr(0, dot)][dotted.substr(dot + 1)] = YAML::Load(value);
}

/// The sandbox of configuration `seed`, the phantom in `phantom` copied into S/in and mutated.
Sandbox draw(std::uint64_t seed, const fs::path& phantom) {
  std::mt19937_64 rng(seed);
  const auto pick = [&](std::size_t n) { return std::size_t(rng() % n); };
  Sandbox s;
  s.root = test::freshDir("config-fuzz");
  s.in = s.root / "in";
  fs::copy(phantom, s.in, fs::copy_options::recursive);
  std::ostringstream what;
  what << "seed " << seed << ":";

  // Settings.
  YAML::Node config = YAML::LoadFile((s.in / "config.yaml").string());
  config["run"]["max_seconds"] = 20;
  const std::size_t settings = pick(5);
  s.clean = settings == 0;
  for (std::size_t k = 0; k < settings; ++k) {
    const auto& [key, values] = kSettings[pick(kSettings.size())];
    const std::string& v = values[pick(values.size())];
    setKey(config, key, v);
    what << " " << key << "=" << v;
  }
  std::string text = YAML::Dump(config) + "\n";
  if (pick(12) == 0) {
    text += "reconstruction:\n  method: delaunay\n";
    what << " (reconstruction twice)";
    s.clean = false;
  }
  if (pick(12) == 0) {
    text += "segmentaton:\n  threshold: 3\n";
    what << " (unknown key)";
    s.clean = false;
  }
  test::writeFile(s.in / "config.yaml", text);

  // Poses.
  YAML::Node slices = YAML::LoadFile((s.in / "slices.yaml").string());
  const std::size_t n = slices["slices"].size();
  const std::size_t poses = pick(8);
  s.clean = s.clean && poses > 3;
  switch (poses) {
    case 0: case 1: {
      const double factor = std::vector<double>{1e-3, 1e3, 1e-6}[pick(3)];
      for (YAML::Node sl : slices["slices"])
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 4; ++c) sl["image_to_world"][r][c] = sl["image_to_world"][r][c].as<double>() * factor;
      what << " poses x" << factor;
      break;
    }
    case 2: {
      const double far = std::vector<double>{1e6, 1e11, 1e13}[pick(3)];
      slices["slices"][pick(n)]["image_to_world"][1][3] = far;
      what << " a slice moved to " << far;
      break;
    }
    case 3: {
      YAML::Node m = slices["slices"][pick(n)]["image_to_world"];
      const int kind = int(pick(3));
      for (int r = 0; r < 3; ++r) {
        if (kind == 0) m[r][0] = 0.0;                          // zero pixel spacing
        if (kind == 1) m[r][1] = m[r][0].as<double>() * 2.0;   // parallel pixel axes
        if (kind == 2) m[r][2] = 1e300;                        // the ignored column, huge
      }
      what << " degenerate pose " << kind;
      break;
    }
    default:
      break;
  }
  std::ofstream(s.in / "slices.yaml") << YAML::Dump(slices) << "\n";

  // Bit depths: some frames stored at 16 bits (full range).
  if (pick(3) == 0) {
    const std::size_t frames = 1 + pick(n);
    for (std::size_t k = 0; k < frames; ++k) {
      const fs::path image = s.in / slices["slices"][pick(n)]["image"].as<std::string>();
      cv::Mat m = cv::imread(image.string(), cv::IMREAD_UNCHANGED);
      if (m.depth() == CV_8U) m.convertTo(m, CV_16U, 257.0);
      cv::imwrite(image.string(), m);
    }
    what << " " << frames << " frames at 16 bits";
    s.clean = false;
  }

  // Destination.
  s.dest = Destination(pick(kDestinations));
  s.cwd = s.root;
  test::writeFile(s.root / "user/thesis.tex", "a user's file\n");
  fs::copy(phantom, s.root / "earlier", fs::copy_options::recursive);  // an output of `xsect phantom`
  fs::create_directory_symlink(s.in, s.root / "link");
  switch (s.dest) {
    case Destination::fresh: s.out = s.root / "out"; break;
    case Destination::input_folder: s.out = s.in; break;
    case Destination::dot: s.out = "."; s.cwd = s.in; break;
    case Destination::ancestor: s.out = s.root; break;
    case Destination::input_file: s.out = s.in / "slices.yaml"; break;
    case Destination::user_folder: s.out = s.root / "user"; break;
    case Destination::images: s.out = s.in / "images"; break;
    case Destination::nested: s.out = s.root / "a/b/c"; break;
    case Destination::inside_input: s.out = s.in / "results"; break;
    case Destination::earlier_output: s.out = s.root / "earlier"; break;
    case Destination::config_default: s.out = ""; break;
    case Destination::link: s.out = s.root / "link"; break;
  }
  s.args = "run " + (s.in / "config.yaml").string() + (s.out.empty() ? "" : " --out " + s.out.string()) + " --quiet";
  what << " --out " << (s.out.empty() ? "(output.dir)" : s.out.string());
  s.what = what.str();
  return s;
}

class ConfigurationFuzz : public testing::TestWithParam<int> {};

TEST_P(ConfigurationFuzz, RandomSettingsPosesDepthsAndDestinationsNeverHangCrashOrTouchInputs) {
  const std::uint64_t count = envNumber("XSECT_CONFIG_FUZZ_CONFIGS", 60);
  const std::uint64_t first = envNumber("XSECT_CONFIG_FUZZ_SEED", 1) + std::uint64_t(GetParam()) * count;
  // The inputs: a sphere cut by 3 x 3 planes of 48 x 48 pixels, rendered once.
  const fs::path base = test::phantom("config-fuzz-base",
                                      "seed: 3\nshape: {kind: sphere, params: {radius: 4}}\n"
                                      "pattern: {kind: multiaxial, count: 3}\nimage: {pixel_mm: 0.25}\n");
  int exits[3] = {0, 0, 0};
  for (std::uint64_t seed = first; seed < first + count; ++seed) {
    const Sandbox s = draw(seed, base / "ph");
    const fs::path destination = s.out.empty() ? s.in / "out" : (s.out == "." ? s.in : s.out);
    const auto inputsBefore = tree(s.in);
    const auto destinationBefore = tree(destination);
    const fs::path here = fs::current_path();
    fs::current_path(s.cwd);
    const test::CliResult r = test::runXsect(s.args, 60);
    fs::current_path(here);
    ASSERT_TRUE(r.code == 0 || r.code == 1 || r.code == 2) << s.what << ": exit " << r.code << "\n" << r.err;
    ++exits[r.code];
    if (refused(s.dest)) EXPECT_EQ(r.code, 2) << s.what << "\n" << r.err;
    // With nothing else wrong, the refusal names the destination's key.
    if (refused(s.dest) && s.clean)
      EXPECT_TRUE(r.err.find("--out") != std::string::npos || r.err.find("output.dir") != std::string::npos)
          << s.what << "\n" << r.err;
    if (r.code == 2) EXPECT_NE(r.err.find("xsect: error: "), std::string::npos) << s.what << "\n" << r.err;
    // The inputs as they were (a new output folder inside the inputs' folder may be added).
    const auto inputsAfter = tree(s.in);
    for (const auto& [name, hash] : inputsBefore) {
      const auto it = inputsAfter.find(name);
      EXPECT_TRUE(it != inputsAfter.end() && it->second == hash) << s.what << ": input " << name << " changed";
    }
    // The destination: a complete output of xsect, or as it was.
    if (r.code == 0) {
      EXPECT_TRUE(isXsectOutputFolder(destination)) << s.what;
      EXPECT_TRUE(fs::exists(destination / "report.json")) << s.what;
    } else {
      EXPECT_EQ(tree(destination), destinationBefore) << s.what << "\n" << r.err;
    }
    EXPECT_EQ(test::slurp(s.root / "user/thesis.tex"), "a user's file\n") << s.what;
    for (const auto& e : fs::recursive_directory_iterator(s.root))
      EXPECT_EQ(e.path().filename().string().find(".partial-"), std::string::npos) << s.what << ": " << e.path();
    fs::remove_all(s.root);
  }
  fs::remove_all(base);
  std::cerr << "configuration fuzz shard " << GetParam() << " (seeds " << first << "-" << first + count - 1
            << "): exit 0 " << exits[0] << ", exit 1 " << exits[1] << ", exit 2 " << exits[2] << " of " << count << "\n";
}

INSTANTIATE_TEST_SUITE_P(Shards, ConfigurationFuzz, testing::Values(0, 1));

}  // namespace

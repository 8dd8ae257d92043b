// Issue 48, "the output folder is xsect's or nothing": every destination that holds an input or a
// user's file, the current folder, an ancestor, an existing file and a link are refused with exit
// 2 naming --out (or output.dir), and the input folder is byte-identical afterwards; absent,
// empty and earlier output folders of xsect are replaced; staging folders of killed runs are
// removed by the next run to the same destination, those of live processes and other hosts kept.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <map>

#include "cli.h"
#include "io/file_hash.h"
#include "io/output_destination.h"
#include "phantom_runs.h"

namespace fs = std::filesystem;
using namespace xsect;

namespace {

/// A small phantom (a sphere cut by 3 x 4 planes) rendered into dir/ph: its config, slices and
/// images are the inputs the tests protect.
fs::path smallPhantom(const std::string& tag) {
  return test::phantom(tag,
                       "seed: 1\nshape: {kind: sphere, params: {radius: 5}}\npattern: {kind: multiaxial, count: 4}\n"
                       "image: {pixel_mm: 0.25}\nconfig: {reconstruction: {voxel_size_mm: 0.5}}\n");
}

/// Every regular file under `dir` with its SHA-256 (relative paths).
std::map<std::string, std::string> treeHashes(const fs::path& dir) {
  std::map<std::string, std::string> h;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) h[fs::relative(e.path(), dir).string()] = sha256File(e.path().string());
  return h;
}

/// Runs `xsect ARGS` from `cwd`.
test::CliResult runIn(const fs::path& cwd, const std::string& args) {
  const fs::path here = fs::current_path();
  fs::current_path(cwd);
  const test::CliResult r = test::runXsect(args);
  fs::current_path(here);
  return r;
}

void expectRefusedLeavingInputs(const fs::path& dir, const fs::path& cwd, const std::string& args,
                                const std::string& key, const std::string& why) {
  const auto before = treeHashes(dir);
  const test::CliResult r = runIn(cwd, args);
  EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
  EXPECT_NE(r.err.find(key), std::string::npos) << args << "\n" << r.err;
  EXPECT_NE(r.err.find(why), std::string::npos) << args << "\n" << r.err;
  EXPECT_EQ(treeHashes(dir), before) << args;
  // Nothing staged beside the destination is left either.
  for (const auto& e : fs::recursive_directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".partial-"), std::string::npos) << e.path();
}

}  // namespace

TEST(OutputDestination, EveryDestinationHoldingInputsOrUserFilesIsRefusedAndTheInputsStayByteIdentical) {
  const fs::path dir = smallPhantom("dest-refused");
  const fs::path ph = dir / "ph";
  const std::string cfg = (ph / "config.yaml").string();
  test::writeFile(dir / "notes/keep.txt", "a user's file\n");
  test::writeFile(dir / "afile.txt", "not a folder\n");
  fs::create_symlink(ph, dir / "link");
  test::writeFile(dir / "foreign/manifest.json", "{\"mine\": true}\n");
  struct Case {
    std::string out, why;
    fs::path cwd;
  };
  const std::vector<Case> cases = {
      {ph.string(), "holds the input", dir},                 // the input's folder
      {ph.string() + "/", "holds the input", dir},           // the same, with a separator
      {".", "is the current folder", ph},                    // ., inside the input folder
      {dir.string(), "holds the current folder", ph},        // an ancestor of the current folder
      {(ph / "images").string(), "holds the input", dir},    // the images' folder
      {"/", "holds the current folder", dir},                // the root
      {(dir / "afile.txt").string(), "is an existing file", dir},
      {(dir / "afile.txt/sub").string(), "which is a file", dir},
      {(dir / "notes").string(), "xsect did not write", dir},
      {(dir / "link").string(), "is a symbolic link", dir},
      {(dir / "foreign").string(), "that xsect did not write", dir},
  };
  for (const Case& c : cases)
    expectRefusedLeavingInputs(dir, c.cwd, "run " + cfg + " --out " + c.out + " --quiet", "--out", c.why);
  // output.dir in the configuration: the same rules, the key named as the configuration's.
  expectRefusedLeavingInputs(dir, dir, "run " + cfg + " --set output.dir=. --quiet", "output.dir", "holds the input");
  // `check` refuses what `run` would.
  expectRefusedLeavingInputs(dir, dir, "check " + cfg + " --set output.dir=" + ph.string() + " --quiet", "output.dir",
                             "holds the input");
  // The other commands that write folders, and eval's file.
  expectRefusedLeavingInputs(dir, fs::temp_directory_path(),
                             "phantom " + (dir / "spec.yaml").string() + " --out " + dir.string() + " --quiet", "--out",
                             "holds the input");
  ASSERT_EQ(test::runXsect("run " + cfg + " --out " + (dir / "out").string() + " --quiet").code, 0);
  expectRefusedLeavingInputs(dir, dir,
                             "slice --mesh " + (dir / "out/mesh.ply").string() + " --planes " + (ph / "slices.yaml").string() +
                                 " --out " + (dir / "out").string() + " --quiet",
                             "--out", "holds the input");
  expectRefusedLeavingInputs(dir, dir,
                             "eval --mesh " + (dir / "out/mesh.ply").string() + " --truth " + (ph / "truth.yaml").string() +
                                 " --json " + (ph / "truth.yaml").string() + " --quiet",
                             "--json", "is one of the inputs");
  EXPECT_EQ(test::slurp(dir / "notes/keep.txt"), "a user's file\n");
  EXPECT_EQ(test::slurp(dir / "afile.txt"), "not a folder\n");
  // Inputs reached through a link: the configuration read as link/config.yaml lies in ph.
  expectRefusedLeavingInputs(dir, dir, "run " + (dir / "link/config.yaml").string() + " --out " + ph.string() + " --quiet",
                             "--out", "holds the input");
  // eval's file may not be an image its --slices lists.
  expectRefusedLeavingInputs(dir, dir,
                             "eval --mesh " + (dir / "out/mesh.ply").string() + " --truth " + (ph / "truth.yaml").string() +
                                 " --slices " + (ph / "slices.yaml").string() + " --json " +
                                 (ph / "images/000.png").string() + " --quiet",
                             "--json", "is one of the inputs");
  fs::remove_all(dir);
}

TEST(OutputDestination, AbsentEmptyAndEarlierOutputFoldersAreReplaced) {
  const fs::path dir = smallPhantom("dest-replaced");
  const std::string cfg = (dir / "ph/config.yaml").string();
  fs::create_directories(dir / "empty");
  for (const std::string out : {"fresh", "empty", "fresh"}) {  // the third replaces the first's output
    const test::CliResult r = test::runXsect("run " + cfg + " --out " + (dir / out).string() + " --quiet");
    ASSERT_EQ(r.code, 0) << out << "\n" << r.err;
    EXPECT_TRUE(isXsectOutputFolder(dir / out)) << out;
    const nlohmann::json m = test::readJson(dir / out / kManifestName);
    EXPECT_EQ(m["written_by"], "xsect");
    EXPECT_EQ(m["command"], "run");
    // The manifest lists exactly the folder's entries.
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir / out)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    EXPECT_EQ(m["outputs"].get<std::vector<std::string>>(), names);
  }
  // A run's output inside a phantom folder: re-rendering the phantom replaces both (both xsect's).
  ASSERT_EQ(test::runXsect("run " + cfg + " --quiet").code, 0);  // output.dir: ph/out
  ASSERT_TRUE(fs::exists(dir / "ph/out/mesh.ply"));
  const test::CliResult again =
      test::runXsect("phantom " + (dir / "spec.yaml").string() + " --out " + (dir / "ph").string() + " --quiet");
  EXPECT_EQ(again.code, 0) << again.err;
  // A file added inside a folder of an output makes it the user's too.
  test::writeFile(dir / "ph/images/mine.txt", "mine\n");
  const test::CliResult nested =
      test::runXsect("phantom " + (dir / "spec.yaml").string() + " --out " + (dir / "ph").string() + " --quiet");
  EXPECT_EQ(nested.code, 2) << nested.err;
  EXPECT_NE(nested.err.find("'images/mine.txt'"), std::string::npos) << nested.err;
  EXPECT_EQ(test::slurp(dir / "ph/images/mine.txt"), "mine\n");
  // A file added to an output folder makes it the user's.
  test::writeFile(dir / "fresh/my-notes.txt", "mine\n");
  const test::CliResult r = test::runXsect("run " + cfg + " --out " + (dir / "fresh").string() + " --quiet");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("'my-notes.txt'"), std::string::npos) << r.err;
  EXPECT_EQ(test::slurp(dir / "fresh/my-notes.txt"), "mine\n");
  fs::remove_all(dir);
}

TEST(OutputDestination, StagingFoldersOfKilledRunsAreRemovedByTheNextRun) {
  const fs::path dir = smallPhantom("dest-stale");
  const std::string cfg = (dir / "ph/config.yaml").string();
  // A process id that no longer exists: a child that has exited and been waited for.
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  ::waitpid(child, nullptr, 0);
  const std::string dead = std::to_string(child), alive = std::to_string(::getpid());
  const std::string tag = stagingTag();
  const std::string host = tag.substr(0, tag.rfind('-'));
  const std::vector<std::string> stale = {".out.partial-" + host + "-" + dead, ".out.old-" + host + "-" + dead,
                                          ".out.partial-" + dead};  // the last: an earlier version's name
  const std::vector<std::string> kept = {".out.partial-" + host + "-" + alive,       // a live process
                                         ".out.partial-elsewhere-" + dead,          // another host's
                                         ".other.partial-" + host + "-" + dead};    // another destination's
  for (const auto& s : stale) test::writeFile(dir / s / "mesh.ply", "half written");
  for (const auto& s : kept) test::writeFile(dir / s / "mesh.ply", "half written");
  const test::CliResult r = test::runXsect("run " + cfg + " --out " + (dir / "out").string() + " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const auto& s : stale) EXPECT_FALSE(fs::exists(dir / s)) << s;
  for (const auto& s : kept) EXPECT_TRUE(fs::exists(dir / s)) << s;
  fs::remove_all(dir);
}

TEST(OutputDestination, APreviousOutputMovedAsideByAKilledRunIsPutBack) {
  // Killed between commit's two renames: the destination absent, the previous output aside as
  // .out.old-HOST-PID of a dead process. It is put back, not removed.
  const fs::path dir = test::freshDir("dest-restore");
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ::waitpid(child, nullptr, 0);
  const std::string tag = stagingTag();
  const std::string host = tag.substr(0, tag.rfind('-'));
  const fs::path aside = dir / (".out.old-" + host + "-" + std::to_string(child));
  test::writeFile(aside / "report.json", "{}\n");
  test::writeFile(aside / kManifestName, "{\"written_by\": \"xsect\", \"outputs\": [\"report.json\"]}\n");
  removeStaleStaging(dir / "out");
  EXPECT_EQ(test::slurp(dir / "out/report.json"), "{}\n");
  EXPECT_FALSE(fs::exists(aside));
  fs::remove_all(dir);
}

TEST(OutputDestination, AKilledRunLeavesItsDestinationCompleteOrAbsent) {
  // A run killed at random moments (SIGKILL: no clean-up) leaves either no folder or a complete
  // one, and the next run removes what it staged.
  const fs::path dir = smallPhantom("dest-kill");
  const std::string cfg = (dir / "ph/config.yaml").string();
  int complete = 0, absent = 0;
  for (int k = 0; k < 8; ++k) {
    const fs::path out = dir / ("out" + std::to_string(k));
    const std::string cmd = "(" + std::string(XSECT_BIN) + " run " + cfg + " --out " + out.string() +
                            " --quiet >/dev/null 2>&1 & p=$!; sleep 0." + std::to_string(k + 1) +
                            "; kill -9 $p 2>/dev/null; wait $p 2>/dev/null) ; true";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    if (fs::exists(out)) {
      ++complete;
      EXPECT_TRUE(isXsectOutputFolder(out)) << out;
      EXPECT_TRUE(fs::exists(out / "report.json")) << out;
    } else {
      ++absent;
    }
    ASSERT_EQ(test::runXsect("run " + cfg + " --out " + out.string() + " --quiet").code, 0);
  }
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".partial-"), std::string::npos) << e.path();
  std::cerr << "killed runs: " << complete << " complete, " << absent << " absent\n";
  fs::remove_all(dir);
}

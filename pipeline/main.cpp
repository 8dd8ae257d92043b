// xsect command line: run | check | phantom | eval | slice, and --version (docs/commands.md).
// Exit codes: 0 success, 2 invalid input or configuration, 1 any other failure.
#include <CLI/CLI.hpp>
#include <iostream>
#include <memory>
#include <tbb/global_control.h>

#include "io/input_error.h"
#include "pipeline/allocator_tuning.h"
#include "pipeline/commands.h"
#include "pipeline/library_versions.h"

int main(int argc, char** argv) {
  using namespace xsect;
  restartWithHugePages(argv);
  keepFreedMemoryForReuse();
  CLI::App app{"xsect: 3D shapes from pose-tagged 2D slices, with topological guarantees"};
  app.require_subcommand(1);
  // `xsect --version`: the release, then the libraries it was built with (as manifest.json lists them).
  std::string version = std::string("xsect ") + XSECT_VERSION;
  for (const auto& [name, v] : libraryVersions())
    if (name != "xsect") version += "\n  " + name + " " + v;
  app.set_version_flag("--version", version, "print the version of xsect and of its libraries");
  int threads = 0;
  app.add_option("--threads", threads, "worker threads (0 = all cores)");

  RunOptions run;
  auto* runCmd = app.add_subcommand("run", "run the pipeline on a configuration");
  runCmd->add_option("config", run.config, "config.yaml")->required();
  runCmd->add_option("--out", run.out, "output folder (overrides output.dir)");
  runCmd->add_option("--set", run.overrides, "override a key: key.path=value")->take_all();
  runCmd->add_flag("--quiet,-q", run.quiet, "no progress on stderr");
  runCmd->add_option("--threads", threads, "worker threads (0 = all cores)");

  RunOptions check;
  auto* checkCmd = app.add_subcommand("check", "validate a configuration and its inputs");
  checkCmd->add_option("config", check.config, "config.yaml")->required();
  checkCmd->add_option("--set", check.overrides, "override a key: key.path=value")->take_all();
  checkCmd->add_flag("--quiet,-q", check.quiet, "no progress on stderr");
  checkCmd->add_flag("--json", check.json, "print the whole diagnosis as JSON instead of a summary");

  PhantomOptions phantom;
  auto* phantomCmd = app.add_subcommand("phantom", "render a synthetic phantom");
  phantomCmd->add_option("spec", phantom.spec, "phantom SPEC.yaml")->required();
  phantomCmd->add_option("--out", phantom.out, "output folder")->required();
  phantomCmd->add_flag("--quiet,-q", phantom.quiet, "no progress on stderr");

  EvalOptions eval;
  auto* evalCmd = app.add_subcommand("eval", "accuracy of a mesh against a truth or reference");
  evalCmd->add_option("--mesh", eval.mesh, "reconstructed mesh")->required();
  auto* truthOpt = evalCmd->add_option("--truth", eval.truth, "phantom truth.yaml");
  auto* refOpt = evalCmd->add_option("--reference", eval.reference, "reference mesh (stl/ply/obj)");
  truthOpt->excludes(refOpt);
  evalCmd->add_option("--slices", eval.slices, "slices.yaml: conformity with the input sections");
  evalCmd->add_option("--threshold", eval.threshold, "grey threshold for --slices images");
  evalCmd->add_option("--voxel", eval.voxel_mm, "voxel size in mm for Dice/IoU (0 = auto)");
  evalCmd->add_option("--json", eval.json, "also write every measure to this JSON file");
  evalCmd->add_flag("--quiet,-q", eval.quiet, "no progress on stderr");

  SliceOptions slice;
  auto* sliceCmd = app.add_subcommand("slice", "cut a closed mesh by planes into a .csl input");
  sliceCmd->add_option("--mesh", slice.mesh, "closed mesh (stl/ply/obj)")->required();
  sliceCmd->add_option("--planes", slice.planes, "poses YAML (slices: image_to_world) or .csl; may repeat")
      ->required();
  sliceCmd->add_option("--out", slice.out, "output folder (input.csl, config.yaml)")->required();
  sliceCmd->add_flag("--quiet,-q", slice.quiet, "no progress on stderr");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }

  std::unique_ptr<tbb::global_control> limit;
  if (threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  threads);
  run.threads = threads;
  try {
    if (*runCmd) return runCommand(run);
    if (*checkCmd) return checkCommand(check);
    if (*phantomCmd) return phantomCommand(phantom);
    if (*sliceCmd) return sliceCommand(slice);
    if (*evalCmd) {
      if (eval.truth.empty() && eval.reference.empty())
        throw InputError("", "--truth/--reference", "one of them is required");
      return evalCommand(eval);
    }
  } catch (const InputError& e) {
    std::cerr << "xsect: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "xsect: failure: " << e.what() << "\n";
    return 1;
  }
  return 1;
}

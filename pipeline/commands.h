// The commands of the command line (docs/commands.md): run, check, phantom, eval, and slice.
// Each returns the process exit code; invalid input is reported by throwing InputError (exit 2).
#pragma once

#include <string>
#include <vector>

namespace xsect {

struct RunOptions {
  std::string config;                  ///< path of config.yaml (with config_text: its name)
  std::string config_text;             ///< the configuration's YAML, when not read from `config`
  std::string out;                     ///< --out: overrides output.dir
  std::vector<std::string> overrides;  ///< --set key.path=value
  bool quiet = false;
  bool json = false;                   ///< check: print the whole diagnosis as JSON, not the summary
  int threads = 0;                     ///< 0 = all cores
};
int runCommand(const RunOptions& options);
int checkCommand(const RunOptions& options);

struct PhantomOptions {
  std::string spec;  ///< phantom SPEC.yaml
  std::string out;   ///< output folder
  bool quiet = false;
};
int phantomCommand(const PhantomOptions& options);

struct EvalOptions {
  std::string mesh;        ///< reconstruction to evaluate (ply, stl, obj)
  std::string truth;       ///< truth.yaml of a phantom (exclusive with reference)
  std::string reference;   ///< reference mesh (exclusive with truth)
  std::string slices;      ///< optional slices.yaml: conformity with the input sections
  std::string json;        ///< output JSON path
  double voxel_mm = 0.0;   ///< Dice/IoU grid voxel; 0 = automatic
  double threshold = 128;  ///< grey threshold used to segment --slices images
  bool quiet = false;
};
int evalCommand(const EvalOptions& options);

struct SliceOptions {
  std::string mesh;                 ///< closed mesh to cut (ply, stl, obj)
  std::vector<std::string> planes;  ///< plane files: poses YAML (advice.yaml) or .csl, in order
  std::string out;                  ///< output folder: input.csl, config.yaml
  bool quiet = false;
};
int sliceCommand(const SliceOptions& options);

}  // namespace xsect

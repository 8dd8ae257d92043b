// Helpers for acceptance tests through the binary: render a phantom from a spec into a fresh
// folder, reconstruct it, evaluate a run's mesh against the phantom's truth, read JSON outputs,
// and load the sections a run reconstructs from.
#pragma once

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "cli.h"
#include "io/run_config.h"
#include "io/slices_file.h"
#include "pipeline/load_sections.h"

namespace xsect::test {

inline nlohmann::json readJson(const std::filesystem::path& p) { return nlohmann::json::parse(slurp(p)); }

/// A fresh folder holding spec.yaml and the phantom rendered from it in ph/.
inline std::filesystem::path phantom(const std::string& tag, const std::string& spec) {
  const std::filesystem::path dir = freshDir(tag);
  writeFile(dir / "spec.yaml", spec);
  const auto r = runXsect("phantom " + (dir / "spec.yaml").string() + " --out " + (dir / "ph").string() + " --quiet");
  EXPECT_EQ(r.code, 0) << r.err;
  return dir;
}

/// `xsect eval` of dir/out/mesh.ply against the phantom's truth; its JSON (written to dir/out.json).
inline nlohmann::json eval(const std::filesystem::path& dir, const std::string& out) {
  const auto r = runXsect("eval --mesh " + (dir / out / "mesh.ply").string() + " --truth " +
                          (dir / "ph/truth.yaml").string() + " --json " + (dir / (out + ".json")).string() + " --quiet");
  EXPECT_EQ(r.code, 0) << r.err;
  return readJson(dir / (out + ".json"));
}

/// `xsect run` of the phantom in dir (ph/config.yaml) into dir/out with extra arguments `sets`;
/// its report.json.
inline nlohmann::json run(const std::filesystem::path& dir, const std::string& out, const std::string& sets) {
  const auto r = runXsect("run " + (dir / "ph/config.yaml").string() + " --out " + (dir / out).string() +
                          " --quiet " + sets);
  EXPECT_EQ(r.code, 0) << r.err;
  return readJson(dir / out / "report.json");
}

/// The sections `xsect run` reconstructs from, for the configuration.
inline std::vector<CuttingPlane> sectionsOf(const std::filesystem::path& config) {
  const RunConfig c = readRunConfig(config.string());
  return sectionsFromSlices(readSlicesFile(c.input_path), c.input_path, c.segmentation, c.path, {}).planes;
}

/// `xsect run` of the phantom in dir with `--set <bad>` must exit 2, name the key, and write nothing.
inline void expectRefused(const std::filesystem::path& dir, const std::string& bad) {
  const std::filesystem::path out = dir / "out";
  const auto r = runXsect("run " + (dir / "ph/config.yaml").string() + " --out " + out.string() + " --set " + bad);
  EXPECT_EQ(r.code, 2) << bad << "\n" << r.err;
  const std::string key = bad.substr(0, bad.find('='));
  EXPECT_NE(r.err.find(key), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out)) << bad;
}

/// A torus (tube radius 15 mm) cut by three orthogonal stacks of 10 planes. With jitter, the
/// recorded poses differ from the true ones by σ = 1 mm per axis and 1°, as a tracker would.
inline std::string torusSpec(int seed, bool jitter) {
  return "seed: " + std::to_string(seed) +
         "\nshape: {kind: torus, params: {major_radius: 40, minor_radius: 15}, rotation_deg: [20, 10, 0]}\n"
         "pattern: {kind: multiaxial, count: 10}\nimage: {pixel_mm: 0.5}\n" +
         (jitter ? "degradations: {pose_jitter_mm: 1, pose_jitter_deg: 1}\n" : "") +
         "config: {reconstruction: {voxel_size_mm: 0.5}}\n";
}

}  // namespace xsect::test

// The section scene of a run (see scene_stage.h).
#include "pipeline/scene_stage.h"

#include <algorithm>
#include <iostream>
#include <stdexcept>
#include <string>

#include "geometry/reconstruction/sampled_reconstruction.h"
#include "io/input_error.h"
#include "pipeline/machine_memory.h"

namespace xsect {

namespace {

/// Refuses, before allocating, a grid that would not fit in this machine's memory.
void checkMemory(const RunConfig& c, const ReconstructionLayout& L) {
  const double need = double(L.grid.count()) * kReconstructionBytesPerVoxel;
  const double have = physicalMemoryBytes();
  if (have > 0 && need > 0.8 * have)
    throw InputError(c.path, "reconstruction.voxel_size_mm",
                     "a grid of " + std::to_string(L.grid.count()) + " voxels needs about " +
                         std::to_string(int(need / 1e9)) + " GB, more than this machine has (" +
                         std::to_string(int(have / 1e9)) + " GB): increase the voxel size");
}

SectionCounts countSections(const std::vector<CuttingPlane>& planes) {
  SectionCounts n;
  for (const auto& p : planes) {
    n.sections += int(p.sections.size());
    n.planes_with_sections += !p.sections.empty();
  }
  return n;
}

}  // namespace

ReconstructionLayout layoutOf(const std::vector<CuttingPlane>& planes, const RunConfig& c) {
  try {
    return reconstructionLayout(planes, reconstructionParams(c));
  } catch (const std::invalid_argument& e) {
    throw InputError(c.path, "reconstruction.voxel_size_mm", e.what());
  }
}

VoxelSizeReport resolveVoxelSize(RunInputs& in, bool quiet) {
  VoxelSizeReport r = chooseVoxelSize(in.config, in.planes);
  if (!r.warning.empty()) {
    in.warnings.insert(in.warnings.begin(), r.warning);
    std::cerr << "WARNING: " << r.warning << "\n";
  }
  if (!quiet && r.automatic)
    std::cerr << "voxel size " << r.voxel_mm << " mm (auto, limited by " << voxelSizeLimitName(r.choice.limited_by)
              << "; " << r.choice.voxels << " voxels)\n";
  return r;
}

nlohmann::ordered_json voxelSizeJson(const VoxelSizeReport& r) {
  using json = nlohmann::ordered_json;
  return {{"voxel_size_mm", r.voxel_mm},
          {"auto", r.automatic},
          {"limited_by", r.automatic ? json(voxelSizeLimitName(r.choice.limited_by)) : json("configuration")},
          {"bounds_diagonal_mm", r.automatic ? json(r.choice.bounds_diagonal_mm) : json(nullptr)},
          {"median_pixel_mm", r.automatic ? json(r.choice.median_pixel_mm) : json(nullptr)},
          {"voxel_budget", r.automatic ? json(r.choice.voxel_budget) : json(nullptr)},
          {"median_section_width_mm", r.median_section_width_mm},
          {"min_section_width_mm", r.min_section_width_mm},
          {"sections_narrower_than_two_voxels", r.sections_narrower_than_two_voxels}};
}

SceneStage sceneStage(RunInputs& in, bool quiet) {
  SceneStage s;
  const RunConfig& c = in.config;
  s.counts = countSections(in.planes);
  if (s.counts.sections == 0)
    throw InputError(c.input_path, "", "no section found in any slice (check segmentation settings)");
  s.voxel_size = resolveVoxelSize(in, quiet);
  checkMemory(c, layoutOf(in.planes, c));
  try {
    s.scene = sectionScene(in.planes, reconstructionParams(c));
  } catch (const std::invalid_argument& e) {
    throw InputError(c.path, "reconstruction", e.what());
  }
  const ReconstructionLayout& L = s.scene.layout;
  in.warnings.push_back("open ends closed by 6 virtual empty planes at " + std::to_string(L.end_margin_mm) +
                        " mm beyond the sections' bounds" + (L.end_margin_auto ? " (automatic margin)" : ""));
  if (s.counts.planes_with_sections == 1) {
    // One plane (a single slice, or every slice at one pose, merged in stage 3) says nothing about
    // the object across it: method 1 extends its section to the end planes on both sides.
    const auto holder = std::find_if(in.planes.begin(), in.planes.end(),
                                     [](const CuttingPlane& p) { return !p.sections.empty(); });
    in.warnings.push_back("only one plane holds sections (slice " + std::to_string(holder->slice) +
                          "): the shape across it is unknown, and the result is its sections extended " +
                          std::to_string(L.end_margin_mm) + " mm to the end planes on each side");
  }
  return s;
}

}  // namespace xsect

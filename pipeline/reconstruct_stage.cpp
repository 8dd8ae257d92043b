// Stage 5: the solid on a grid (see reconstruct_stage.h).
#include "pipeline/reconstruct_stage.h"

#include <algorithm>
#include <iostream>
#include <stdexcept>

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

ReconstructStage reconstructStage(RunInputs& in, bool quiet, StageClock& clock, Progress& progress) {
  ReconstructStage r;
  const RunConfig& c = in.config;
  r.counts = countSections(in.planes);
  if (r.counts.sections == 0)
    throw InputError(c.input_path, "", "no section found in any slice (check segmentation settings)");
  r.voxel_size = resolveVoxelSize(in, quiet);

  progress.stage("reconstruct");
  r.params = reconstructionParams(c);
  checkMemory(c, layoutOf(in.planes, c));
  try {
    r.solid = reconstructOnGrid(in.planes, r.params, [&](double f) { progress.update(f); });
  } catch (const std::invalid_argument& e) {
    throw InputError(c.path, "reconstruction", e.what());
  }
  clock.end("reconstruct");
  const SampledReconstruction& rec = r.solid;
  if (rec.voxels_inside == 0) {
    // An automatic size the budget forced so coarse that nothing is left: the configuration must
    // change (exit 2); otherwise exit 1 with the size to use (issue 14).
    if (r.voxel_size.automatic && r.voxel_size.choice.limited_by == VoxelSizeLimit::voxel_budget)
      throw InputError(c.path, "reconstruction.voxel_budget", emptySolidMessage(r.voxel_size, r.counts.sections));
    throw std::runtime_error(emptySolidMessage(r.voxel_size, r.counts.sections));
  }
  in.warnings.push_back("open ends closed by 6 virtual empty planes at " +
                        std::to_string(rec.end_margin_mm) + " mm beyond the sections' bounds" +
                        (rec.end_margin_auto ? " (automatic margin)" : ""));
  if (r.counts.planes_with_sections == 1) {
    // One plane (a single slice, or every slice at one pose, merged in stage 3) says nothing about
    // the object across it: method 1 extends its section to the end planes on both sides.
    const auto holder = std::find_if(in.planes.begin(), in.planes.end(),
                                     [](const CuttingPlane& p) { return !p.sections.empty(); });
    in.warnings.push_back("only one plane holds sections (slice " + std::to_string(holder->slice) +
                          "): the shape across it is unknown, and the result is its sections extended " +
                          std::to_string(rec.end_margin_mm) + " mm to the end planes on each side");
  }
  return r;
}

}  // namespace xsect

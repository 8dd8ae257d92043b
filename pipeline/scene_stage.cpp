// The section scene of a run (see scene_stage.h).
#include "pipeline/scene_stage.h"

#include "geometry/scene/open_ends.h"

#include <algorithm>
#include <iostream>
#include <stdexcept>
#include <string>

#include "geometry/core/block_grid.h"
#include "geometry/reconstruction/solid_memory.h"
#include "io/input_error.h"
#include "pipeline/machine_memory.h"

namespace xsect {

namespace {

/// Refuses, before allocating, a grid whose solid would not fit in this machine's memory (issue
/// 17: what is kept, by blocks; a coarse trial measures it only when the worst case, every block
/// a leaf, would not fit, or `*trial` is wanted anyway: it is then kept there, measured once).
void checkMemory(const RunConfig& c, const std::vector<CuttingPlane>& planes, const ReconstructionLayout& L,
                 double voxel_mm, bool wanted, std::optional<SolidMemoryEstimate>* trial) {
  const double have = physicalMemoryBytes();
  const double budget = 0.8 * have;
  const double dense = denseBytesPerVoxel(c);
  const double blocks = double(blockCountOf(L.grid));
  const double rows = double(L.grid.dims[1]) * double(L.grid.dims[2]);
  const bool fits = !(have > 0) || worstCaseSolidBytes(blocks, rows) + double(L.grid.count()) * dense <= budget;
  if (fits && !wanted) return;
  *trial = estimateSolidMemory(planes, reconstructionParams(c, voxel_mm), dense);
  const SolidMemoryEstimate& e = **trial;
  if (fits || e.total() <= budget) return;
  const std::string setting = e.dense_bytes > 0.5 * e.total()
                                  ? "set smoothing.method: none (it holds the whole volume) or increase the voxel size"
                                  : "increase the voxel size";
  throw InputError(c.path, "reconstruction.voxel_size_mm",
                   "a grid of " + std::to_string(L.grid.count()) + " voxels needs about " +
                       std::to_string(int(std::ceil(e.total() / 1e9))) + " GB (" + memoryBreakdown(e) +
                       "), more than this machine has (" + std::to_string(int(have / 1e9)) + " GB): " + setting);
}

SectionCounts countSections(const std::vector<CuttingPlane>& planes) {
  SectionCounts n;
  for (const auto& p : planes) {
    n.sections += int(p.sections.size());
    n.planes_with_sections += !p.sections.empty();
  }
  return n;
}

/// The grid the reconstruction will use; configuration problems become InputError.
ReconstructionLayout layoutOf(const std::vector<CuttingPlane>& planes, const RunConfig& c, double voxel_mm) {
  try {
    return reconstructionLayout(planes, reconstructionParams(c, voxel_mm));
  } catch (const std::invalid_argument& e) {
    throw InputError(c.path, "reconstruction.voxel_size_mm", e.what());
  }
}

/// The voxel size for the run (auto resolved; a too coarse explicit size is a warning printed even
/// with --quiet).
VoxelSizeReport resolveVoxelSize(const RunInputs& in, bool quiet) {
  VoxelSizeReport r = chooseVoxelSize(in.config, in.planes);
  if (!r.warning.empty()) std::cerr << "WARNING: " << r.warning << "\n";
  if (!quiet && r.automatic)
    std::cerr << "voxel size " << r.voxel_mm << " mm (auto, limited by " << voxelSizeLimitName(r.choice.limited_by)
              << "; " << r.choice.voxels << " voxels)\n";
  return r;
}

}  // namespace

std::string memoryBreakdown(const SolidMemoryEstimate& e) {
  const auto mb = [](double bytes) { return std::to_string(std::int64_t(std::ceil(bytes / 1e6))) + " MB"; };
  return "solid by blocks " + mb(e.table_bytes + e.leaf_bytes) + ", meshes " + mb(e.mesh_bytes) +
         ", whole-volume stages " + mb(e.dense_bytes);
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

std::vector<std::string> warningsThroughScene(const RunInputs& in, const SceneStage& s) {
  std::vector<std::string> w;
  if (!s.voxel_size.warning.empty()) w.push_back(s.voxel_size.warning);
  w.insert(w.end(), in.warnings.begin(), in.warnings.end());
  w.insert(w.end(), s.warnings.begin(), s.warnings.end());
  return w;
}

SceneStage sceneStage(const RunInputs& in, bool quiet, double elapsed_s, bool want_memory_trial) {
  SceneStage s;
  const RunConfig& c = in.config;
  s.counts = countSections(in.planes);
  if (s.counts.sections == 0)
    throw InputError(c.input_path, "", "no section found in any slice (check segmentation settings)");
  s.voxel_size = resolveVoxelSize(in, quiet);
  const double voxel = s.voxel_size.voxel_mm;
  const ReconstructionLayout layout = layoutOf(in.planes, c, voxel);
  // The coarse trial is measured once: when the worst case would not fit, for `check`'s report, or
  // for the time estimate of a large grid.
  checkMemory(c, in.planes, layout, voxel, want_memory_trial || double(layout.grid.count()) > 1e8, &s.memory_trial);
  // The voxels the reconstruction evaluates: the grid's, or on a large grid the blocks the trial
  // finds filled (the others are decided per block).
  double voxels = double(layout.grid.count());
  if (voxels > 1e8) {
    const SolidMemoryEstimate& m = *s.memory_trial;
    voxels = double(m.blocks) + 512.0 * double(m.boundary_blocks + m.solid_blocks + m.plane_blocks);
  }
  s.time_estimate = sceneOnwardSeconds(in.planes, voxel, voxels, c);
  checkTimeBudget(s.time_estimate, elapsed_s, c);
  try {
    s.scene = sectionScene(in.planes, reconstructionParams(c, voxel), layout);
  } catch (const std::invalid_argument& e) {
    throw InputError(c.path, "reconstruction", e.what());
  }
  const ReconstructionLayout& L = s.scene.layout;
  // Every run closes the object by 6 virtual empty planes L.end_margin_mm beyond the sections' bounds
  // (docs/methods.md): said where a slice holds sections beyond all others (the object is cut open
  // there and the solid past it is extrapolated), not on every run.
  // Any section reaching past a plane shows the object's extent there (a multi-axial torus's
  // outermost planes are passed by 0.18 mm, its other stacks' sections): a hundredth of a voxel
  // only absorbs rounding.
  if (const std::vector<int> ends = openEndSlices(in.planes, 0.01 * voxel); !ends.empty()) {
    std::string named;
    for (std::size_t k = 0; k < ends.size() && k < 4; ++k) named += (k ? ", " : "") + std::to_string(ends[k]);
    if (ends.size() > 4) named += " and " + std::to_string(ends.size() - 4) + " more";
    s.warnings.push_back("open ends: slice" + std::string(ends.size() > 1 ? "s " : " ") + named +
                         (ends.size() > 1 ? " hold" : " holds") + " sections beyond every other slice's, where the object is cut open: past them the "
                         "solid is extrapolated up to the virtual empty planes " + std::to_string(L.end_margin_mm) +
                         " mm beyond" + (L.end_margin_auto ? " (automatic margin)" : ""));
  }
  if (s.counts.planes_with_sections == 1) {
    // One plane (a single slice, or every slice at one pose, merged in stage 3) says nothing about
    // the object across it: method 1 extends its section to the end planes on both sides.
    const auto holder = std::find_if(in.planes.begin(), in.planes.end(),
                                     [](const CuttingPlane& p) { return !p.sections.empty(); });
    s.warnings.push_back("only one plane holds sections (slice " + std::to_string(holder->slice) +
                         "): the shape across it is unknown, and the result is its sections extended " +
                         std::to_string(L.end_margin_mm) + " mm to the end planes on each side");
  }
  return s;
}

}  // namespace xsect

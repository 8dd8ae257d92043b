// The run's voxel size and its check against the sections' widths (see voxel_size_choice.h).
#include "pipeline/voxel_size_choice.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "geometry/core/block_grid.h"
#include "geometry/core/median.h"
#include "geometry/reconstruction/solid_memory.h"
#include "geometry/reconstruction/section_width.h"
#include "io/input_error.h"
#include "pipeline/machine_memory.h"

namespace xsect {

namespace {

std::string mm(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

/// Sizes the libraries cannot hold (issue 15): OpenVDB's transforms refuse voxels below about
/// 1.4e-5 (a scale whose determinant is under 3e-15), and meshes are single precision (PLY and
/// STL store floats, OpenVDB meshes in floats): far from the origin a float cannot tell voxel
/// corners apart. Both are input errors that say what to change, not a crash or a wrong mesh.
void checkRepresentable(const RunConfig& c, const std::vector<CuttingPlane>& planes, double h) {
  if (h < 2e-5)
    throw InputError(c.path, "reconstruction.voxel_size_mm",
                     "a voxel of " + mm(h) + " mm is below what OpenVDB's transforms hold (2e-5): the data are in "
                     "very small units; express them in smaller ones (e.g. micrometres instead of millimetres)");
  // The grid's box (end margins and outer layers included): where mesh vertices can be.
  GridSpec g;
  try {
    g = reconstructionLayout(planes, reconstructionParams(c, h)).grid;
  } catch (const std::invalid_argument& e) {  // past 2^40 voxels
    throw InputError(c.path, "reconstruction.voxel_size_mm", e.what());
  }
  const Vec3 lo = g.origin, hi = g.centre(g.dims[0] - 1, g.dims[1] - 1, g.dims[2] - 1);
  const double far = std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff());
  // A float's spacing at |x| is at most |x| 2^-23; a sixteenth of a voxel keeps the mesh's
  // vertices (on voxel edges) distinct.
  if (far * std::ldexp(1.0, -23) > h / 16)
    throw InputError(c.input_path, "",
                     "the grid reaches " + mm(far) + " mm from the origin while the voxel is " + mm(h) +
                         " mm: single-precision meshes (PLY, STL) cannot hold that detail there; translate the "
                         "data nearer the origin or use a voxel of at least " +
                         mm(twoSignificantDigits(16 * far * std::ldexp(1.0, -23), true)) + " mm");
}

/// A voxel many times wider than the sections is rarely a choice: a configuration written for
/// millimetres run on poses in metres (issue 48). Empty when the ratio is unremarkable.
std::string unitsHint(double voxel_mm, double median_width_mm) {
  if (!(median_width_mm > 0) || voxel_mm < 20 * median_width_mm) return "";
  return " (a voxel " + mm(twoSignificantDigits(voxel_mm / median_width_mm)) +
         " times the sections' median width: are the poses in other units than the configuration, e.g. metres "
         "against millimetres? auto sizes the voxel from the data in any units)";
}

/// Whether a run at `voxel_mm` fits in this machine's memory as the scene stage's check measures
/// it (the worst case, else the coarse trial's estimate, against 80% of the memory); `need`
/// receives the bytes estimated when it does not.
bool fitsInMemory(const RunConfig& c, const std::vector<CuttingPlane>& planes, double voxel_mm, double* need) {
  const double have = physicalMemoryBytes();
  if (!(have > 0)) return true;
  const ReconstructionParams p = reconstructionParams(c, voxel_mm);
  GridSpec g;
  try {
    g = reconstructionLayout(planes, p).grid;
  } catch (const std::invalid_argument&) {
    *need = INFINITY;
    return false;
  }
  const double dense = denseBytesPerVoxel(c);
  if (worstCaseSolidBytes(double(blockCountOf(g)), double(g.dims[1]) * double(g.dims[2])) + double(g.count()) * dense <=
      0.8 * have)
    return true;
  *need = estimateSolidMemory(planes, p, dense).total();
  return *need <= 0.8 * have;
}

/// "use reconstruction.voxel_size_mm: S" when a run at S fits in memory; otherwise what S would
/// need, so that no message advises a run `xsect check` would refuse.
std::string voxelAdvice(const RunConfig& c, const std::vector<CuttingPlane>& planes, double voxel_mm,
                        const std::string& advice) {
  double need = 0;
  if (fitsInMemory(c, planes, voxel_mm, &need)) return advice;
  return "a voxel fine enough for them (" + mm(voxel_mm) + " mm) would need about " +
         (std::isfinite(need) ? std::to_string(int(std::ceil(need / 1e9))) + " GB" : std::string("more memory")) +
         ", more than this machine has (" + std::to_string(int(physicalMemoryBytes() / 1e9)) +
         " GB): make the sections wider at their source instead";
}

/// Sections from images that most of are narrower than two voxels are most often the
/// segmentation's (speckle, noise): the counts, the width in pixels, and the keys to change.
/// Empty for contours given as such.
std::string segmentationHint(const RunConfig& c, const std::vector<CuttingPlane>& planes, const VoxelSizeReport& r) {
  if (c.input_kind != InputKind::slices && c.input_kind != InputKind::plus_sequence) return "";
  std::vector<double> pixels;
  int slices = 0;
  for (const CuttingPlane& p : planes)
    if (!p.is_virtual && p.slice >= 0) {
      ++slices;
      if (p.pixel_mm > 0) pixels.push_back(p.pixel_mm);
    }
  const double pixel = pixels.empty() ? 0 : upperMedian(pixels);
  std::ostringstream s;
  s << "the segmentation is the likely cause: the images gave " << r.sections << " sections in " << slices
    << " slices (" << twoSignificantDigits(double(r.sections) / std::max(1, slices)) << " per slice), median width "
    << mm(r.median_section_width_mm) << " mm";
  if (pixel > 0) s << " (" << twoSignificantDigits(r.median_section_width_mm / pixel) << " pixels)";
  s << ", as speckle or noise segmented as objects; segment for the structures you want: "
       "segmentation.preset: ultrasound for B-mode frames, or raise segmentation.min_area_mm2, sigma_mm and "
       "open_radius_mm. Otherwise: ";
  return s.str();
}

}  // namespace

double denseBytesPerVoxel(const RunConfig& c) {
  double dense = 0;
  if (c.smoothing_method != SmoothingMethod::none) dense += kSmoothingBytesPerVoxel;
  // Several materials: their solids are made from dense copies (field, labels, one label's set),
  // for every method (mesh_stage.cpp).
  if (c.segmentation.method == SegmentationMethod::labels) dense += 4 + 2 + 1;
  return dense;
}

ReconstructionParams reconstructionParams(const RunConfig& c, double voxel_mm) {
  ReconstructionParams p;
  p.voxel_mm = voxel_mm;
  p.method = c.reconstruction_method;
  p.end_margin_mm = c.end_margin_mm;
  p.planes = c.planes;
  return p;
}

VoxelSizeReport chooseVoxelSize(const RunConfig& c, const std::vector<CuttingPlane>& planes) {
  VoxelSizeReport r;
  const std::vector<double> widths = sectionWidths(planes);
  r.automatic = c.voxel_size_auto;
  if (c.voxel_size_auto) {
    try {
      r.choice = automaticVoxelSize(planes, widths, reconstructionParams(c, c.voxel_size_mm), c.voxel_budget);
    } catch (const std::invalid_argument& e) {
      throw InputError(c.path, "reconstruction.voxel_size_mm", e.what());
    }
  }
  r.voxel_mm = c.voxel_size_auto ? r.choice.voxel_mm : c.voxel_size_mm;
  checkRepresentable(c, planes, r.voxel_mm);
  r.sections = int(widths.size());
  r.median_section_width_mm = upperMedian(widths);
  r.min_section_width_mm = widths.empty() ? 0.0 : *std::min_element(widths.begin(), widths.end());
  r.sections_narrower_than_two_voxels =
      int(std::count_if(widths.begin(), widths.end(), [&](double w) { return w < 2 * r.voxel_mm; }));
  r.suggested_voxel_mm = twoSignificantDigits(r.median_section_width_mm / 4);
  if (2 * r.sections_narrower_than_two_voxels <= r.sections) return r;

  const std::string what = std::to_string(r.sections_narrower_than_two_voxels) + " of " +
                           std::to_string(r.sections) + " sections are narrower than two voxels (median width " +
                           mm(r.median_section_width_mm) + " mm)";
  // An automatic size on images: the segmentation is named first (issue 49; an explicit size is
  // the user's choice, warned about below). A voxel is advised only where a run at it fits in
  // memory.
  const std::string units = unitsHint(r.voxel_mm, r.median_section_width_mm);
  const std::string cause = units.empty() ? segmentationHint(c, planes, r) : "";
  if (c.voxel_size_auto && r.choice.limited_by == VoxelSizeLimit::pixel)
    // The rule stops at half a pixel: sections under a pixel wide are the segmentation's noise or
    // structures the images do not resolve; a finer grid is the user's explicit choice.
    throw InputError(c.path, "reconstruction.voxel_size_mm",
                     "at the automatic voxel size of " + mm(r.voxel_mm) + " mm (half the median pixel, " +
                         mm(r.choice.median_pixel_mm) + " mm), " + what + ": " + cause +
                         voxelAdvice(c, planes, r.suggested_voxel_mm,
                                     "the images hardly resolve them; set reconstruction.voxel_size_mm: " +
                                         mm(r.suggested_voxel_mm) +
                                         " (a quarter of the median width) to reconstruct them anyway"));
  if (c.voxel_size_auto) {
    // Otherwise only the budget makes the rule this coarse (h <= w/4 leaves the median section
    // four voxels wide): the size to use needs a larger budget.
    const ReconstructionParams p = reconstructionParams(c, r.suggested_voxel_mm);
    std::string voxels = "more";
    try {
      voxels = std::to_string(reconstructionLayout(planes, p).grid.count());
    } catch (const std::invalid_argument&) {
    }
    throw InputError(c.path, "reconstruction.voxel_size_mm",
                     "at the automatic voxel size of " + mm(r.voxel_mm) + " mm (limited by reconstruction.voxel_budget = " +
                         std::to_string(c.voxel_budget) + " voxels), " + what + ": " + cause +
                         voxelAdvice(c, planes, r.suggested_voxel_mm,
                                     "the grid cannot resolve them; set reconstruction.voxel_size_mm: " +
                                         mm(r.suggested_voxel_mm) +
                                         " (a quarter of the median width) and reconstruction.voxel_budget: " + voxels));
  }
  r.warning = "reconstruction.voxel_size_mm = " + mm(r.voxel_mm) + " mm is too coarse for these sections: " + what +
              units + "; the result may lose thin parts or be empty. " +
              voxelAdvice(c, planes, r.suggested_voxel_mm,
                          "Use reconstruction.voxel_size_mm: " + mm(r.suggested_voxel_mm) +
                              " (a quarter of the median width) or auto");
  return r;
}

std::string emptySolidMessage(const VoxelSizeReport& r, int sections) {
  return "the reconstructed solid is empty although the input has " + std::to_string(sections) +
         " sections: no voxel centre of the " + mm(r.voxel_mm) + " mm grid lies in it (median section width " +
         mm(r.median_section_width_mm) + " mm)" + unitsHint(r.voxel_mm, r.median_section_width_mm) + "; " +
         (r.automatic && r.choice.limited_by == VoxelSizeLimit::voxel_budget ? "the voxel budget forced the automatic size up: set reconstruction.voxel_size_mm: " +
                            mm(r.suggested_voxel_mm) + " and raise reconstruction.voxel_budget"
                      : "use a smaller reconstruction.voxel_size_mm, e.g. " + mm(r.suggested_voxel_mm) + ", or auto");
}

}  // namespace xsect

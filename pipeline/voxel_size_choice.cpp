// The run's voxel size and its check against the sections' widths (see voxel_size_choice.h).
#include "pipeline/voxel_size_choice.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "geometry/core/median.h"
#include "geometry/reconstruction/section_width.h"
#include "io/input_error.h"

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
void checkRepresentable(const RunConfig& c, const std::vector<CuttingPlane>& planes) {
  const double h = c.voxel_size_mm;
  if (h < 2e-5)
    throw InputError(c.path, "reconstruction.voxel_size_mm",
                     "a voxel of " + mm(h) + " mm is below what OpenVDB's transforms hold (2e-5): the data are in "
                     "very small units; express them in smaller ones (e.g. micrometres instead of millimetres)");
  // The grid's box (end margins and outer layers included): where mesh vertices can be.
  GridSpec g;
  try {
    g = reconstructionLayout(planes, reconstructionParams(c)).grid;
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

}  // namespace

ReconstructionParams reconstructionParams(const RunConfig& c) {
  ReconstructionParams p;
  p.voxel_mm = c.voxel_size_mm;
  p.method = c.reconstruction_method;
  p.end_margin_mm = c.end_margin_mm;
  p.planes = c.planes;
  return p;
}

VoxelSizeReport chooseVoxelSize(RunConfig& c, const std::vector<CuttingPlane>& planes) {
  VoxelSizeReport r;
  const std::vector<double> widths = sectionWidths(planes);
  r.automatic = c.voxel_size_auto;
  if (c.voxel_size_auto) {
    try {
      r.choice = automaticVoxelSize(planes, widths, reconstructionParams(c), c.voxel_budget);
    } catch (const std::invalid_argument& e) {
      throw InputError(c.path, "reconstruction.voxel_size_mm", e.what());
    }
    c.voxel_size_mm = r.choice.voxel_mm;
  }
  r.voxel_mm = c.voxel_size_mm;
  checkRepresentable(c, planes);
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
  if (c.voxel_size_auto && r.choice.limited_by == VoxelSizeLimit::pixel)
    // The rule stops at half a pixel: sections under a pixel wide are the segmentation's noise or
    // structures the images do not resolve; a finer grid is the user's explicit choice.
    throw InputError(c.path, "reconstruction.voxel_size_mm",
                     "at the automatic voxel size of " + mm(r.voxel_mm) + " mm (half the median pixel, " +
                         mm(r.choice.median_pixel_mm) + " mm), " + what +
                         ": the images hardly resolve them; set reconstruction.voxel_size_mm: " +
                         mm(r.suggested_voxel_mm) + " (a quarter of the median width) to reconstruct them anyway");
  if (c.voxel_size_auto) {
    // Otherwise only the budget makes the rule this coarse (h <= w/4 leaves the median section
    // four voxels wide): the size to use needs a larger budget.
    ReconstructionParams p = reconstructionParams(c);
    p.voxel_mm = r.suggested_voxel_mm;
    std::string voxels = "more";
    try {
      voxels = std::to_string(reconstructionLayout(planes, p).grid.count());
    } catch (const std::invalid_argument&) {
    }
    throw InputError(c.path, "reconstruction.voxel_size_mm",
                     "at the automatic voxel size of " + mm(r.voxel_mm) + " mm (limited by reconstruction.voxel_budget = " +
                         std::to_string(c.voxel_budget) + " voxels), " + what +
                         ": the grid cannot resolve them; set reconstruction.voxel_size_mm: " +
                         mm(r.suggested_voxel_mm) + " (a quarter of the median width) and reconstruction.voxel_budget: " +
                         voxels);
  }
  r.warning = "reconstruction.voxel_size_mm = " + mm(r.voxel_mm) + " mm is too coarse for these sections: " + what +
              unitsHint(r.voxel_mm, r.median_section_width_mm) +
              "; the result may lose thin parts or be empty. Use reconstruction.voxel_size_mm: " +
              mm(r.suggested_voxel_mm) + " (a quarter of the median width) or auto";
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

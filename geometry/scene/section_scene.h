// The section scene: what every stage after conformity (docs/methods.md stages 4-7) reads, built once.
//  - the cutting planes with their sections, the real ones in input order, then the six virtual
//    end planes with empty sections that close the arrangement's open cells (end_planes.h; thesis
//    ch. 1 §1.2: R of an unbounded cell would be an infinite prism);
//  - per plane, the raster of f_P, the signed distance to its sections (thesis ch. 1 §1.1,
//    section_distance_field.h; the end planes' rasters are empty: they hold no section);
//  - the grid on which solids are sampled and the end margin (ReconstructionLayout).
// The flat section ids (geometry/core/section_ids.h) number the sections of `planes`: the end
// planes hold none, so the ids are those of the real planes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "geometry/core/plane_extent.h"
#include "geometry/core/reconstruction_method.h"
#include "geometry/core/section_ids.h"
#include "geometry/core/types.h"
#include "geometry/scene/observed_piece.h"
#include "geometry/scene/section_distance_field.h"

namespace xsect {

struct ReconstructionParams {
  ReconstructionMethod method = ReconstructionMethod::nearest_plane;
  double voxel_mm = 0.5;                ///< grid spacing, mm (> 0)
  std::optional<double> end_margin_mm;  ///< distance of the virtual end planes beyond the
                                        ///< sections' bounds, mm; empty = automatic (end_planes.h)
  double band_voxels = 3.0;             ///< distance rasters keep exact values within this band
  /// Method 2: half-thickness of the thickened planes in voxels (Fig. 2.6); √3/2 makes every
  /// 26-connected voxel path across a plane meet the slab.
  double slab_voxels = 0.8660254037844386;
  /// Whether a plane cuts space only where its slice was observed (issue 20, observed_piece.h).
  PlaneExtent planes = PlaneExtent::whole;
};

/// The grid and end margin of a scene, without building anything (for `xsect check`, memory
/// estimates and the automatic voxel size).
struct ReconstructionLayout {
  GridSpec grid;
  double end_margin_mm = 0;
  bool end_margin_auto = false;
  Vec3 sections_min = Vec3::Zero(), sections_max = Vec3::Zero();
};

/// @param planes  the real cutting planes with their sections.
/// The grid holds R (method 1), R' (method 2) or R'' (method 3) with two layers of outside voxels
/// around it.
/// Throws std::invalid_argument when there is no section at all, the voxel size is not positive
/// or the grid would be too large (over 2^40 voxels).
ReconstructionLayout reconstructionLayout(const std::vector<CuttingPlane>& planes,
                                          const ReconstructionParams& params);

struct SectionScene {
  ReconstructionParams params;
  ReconstructionLayout layout;
  std::vector<CuttingPlane> planes;           ///< the real planes in input order, then the end planes
  std::size_t real_planes = 0;                ///< how many of `planes` are real (the first ones)
  std::vector<SectionDistanceField> fields;   ///< f_P, one per plane of `planes`
  /// The observed piece of each plane of `planes` (all whole with params.planes == whole).
  std::vector<ObservedPiece> pieces;

  const GridSpec& grid() const { return layout.grid; }
  /// The end planes' index range in `planes`: [real_planes, planes.size()).
  std::size_t end_planes() const { return planes.size() - real_planes; }
  /// Flat ids of the sections (the real planes'; end planes hold none).
  SectionIds ids() const { return SectionIds(planes); }
  /// Method 2's thickened planes: half-thickness, mm.
  double slab_mm() const { return params.slab_voxels * params.voxel_mm; }
};

/// The node spacing of a plane's f_P raster, mm: its pixel (`pixel_mm`, 0 when unknown) clamped to
/// [voxel/8, voxel/2], so that the raster's cost per contour edge is bounded whatever the ratio.
double rasterStep(double pixel_mm, double voxel_mm);

/// Builds the scene of the real planes (copied in): the layout, the end planes, every plane's
/// f_P raster (node spacing the plane's pixel clamped to [an eighth of a voxel, half a voxel], so
/// that its cost per contour edge is bounded whatever the ratio of voxel to pixel; exact within the
/// larger of band_voxels voxels and 3 nodes of a contour). Parallel over planes; deterministic.
/// Throws std::invalid_argument as reconstructionLayout.
SectionScene sectionScene(const std::vector<CuttingPlane>& realPlanes, const ReconstructionParams& params);
/// The same on the layout already computed for these planes and parameters (reconstructionLayout).
SectionScene sectionScene(const std::vector<CuttingPlane>& realPlanes, const ReconstructionParams& params,
                          const ReconstructionLayout& layout);

}  // namespace xsect

// Method 1 or 2 on the scene's grid, with the sampled topology repaired
// (see sampled_reconstruction.h).
#include "geometry/reconstruction/sampled_reconstruction.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

#include "geometry/reconstruction/nearest_plane_reconstruction.h"
#include "geometry/reconstruction/observed_section_voronoi.h"

namespace xsect {

namespace {

/// The method's values on one block of 8³ voxels (BlockGrid's offsets), as both methods give them.
struct EvaluatedBlock {
  static constexpr int kVoxels = BlockGrid<float>::kVoxels;
  const float* value;           ///< in-plane signed distance, negative in the method's set
  const float* plane_distance;  ///< distance to the nearest plane, mm
  const int* nearest_plane;     ///< that plane (-1: none, method 2 far from every section)
  const int* section_plane;     ///< plane whose section decided an inside voxel (-1 otherwise)
  const float* lift;            ///< height of an inside voxel above that section's plane, mm
  bool far_outside = false;     ///< every value the same positive one, no voxel next to a plane
};

/// Turns evaluated blocks into the solid's parts: the field and section planes by block, the
/// voxel set and the repair's evidence by voxel, the longest lift.
class SolidAssembly {
 public:
  SolidAssembly(const SectionScene& scene, SampledReconstruction& out)
      : scene_(scene), out_(out), grid_(scene.grid()) {
    out.field = BlockGrid<float>(grid_, 0.f);
    out.section_plane = BlockGrid<int>(grid_, -1);
    out.inside = BlockGrid<std::uint8_t>(grid_, 0);
    in_anchor = BlockGrid<std::uint8_t>(grid_, 0);
    out_anchor = BlockGrid<std::uint8_t>(grid_, 0);
    block_lift_.assign(std::size_t(out.field.blockCount()), 0.f);
  }

  // Evidence for the repair: voxels next to a plane (within half a voxel diagonal), clearly inside
  // or clearly outside its sections (by half a voxel). Method 2 marks voxels that no plane's
  // sections can reach by projection (nearest_plane -1) as outside evidence too. Voxels of the
  // block beyond the grid repeat its first voxel, so they keep a uniform block a tile.
  void add(std::int64_t b, const EvaluatedBlock& e) {
    if (e.far_outside) {  // the tiles each grid starts with, the field's value aside
      out_.field.setTile(b, e.value[0]);
      return;
    }
    const double h = grid_.voxel;
    const float near = float(0.5 * std::sqrt(3.0) * h), margin = float(0.5 * h);
    constexpr int kN = EvaluatedBlock::kVoxels;
    std::array<int, kN> plane;
    std::array<std::uint8_t, kN> in, inAnchor, outAnchor;
    float lift = 0;
    for (int q = 0; q < kN; ++q) {
      const float v = e.value[q];
      const int sp = v < 0 ? e.section_plane[q] : -1;
      plane[std::size_t(q)] = sp >= int(scene_.real_planes) ? -1 : sp;
      in[std::size_t(q)] = v < 0;
      if (v < 0) lift = std::max(lift, e.lift[q]);
      const int p = e.nearest_plane[q];
      const bool next = p >= 0 && e.plane_distance[q] <= near;
      inAnchor[std::size_t(q)] = next && v <= -margin && !scene_.planes[std::size_t(p)].is_virtual;
      outAnchor[std::size_t(q)] = p < 0 || (next && v >= margin);
    }
    out_.field.setBlock(b, e.value);
    out_.section_plane.setBlock(b, plane.data());
    out_.inside.setBlock(b, in.data());
    in_anchor.setBlock(b, inAnchor.data());
    out_anchor.setBlock(b, outAnchor.data());
    block_lift_[std::size_t(b)] = lift;
  }

  double maxLift() const {
    float m = 0;
    for (const float l : block_lift_) m = std::max(m, l);
    return m;
  }

  BlockGrid<std::uint8_t> in_anchor, out_anchor;

 private:
  const SectionScene& scene_;
  SampledReconstruction& out_;
  const GridSpec& grid_;
  std::vector<float> block_lift_;
};

}  // namespace

SampledReconstruction reconstructOnGrid(const SectionScene& scene,
                                        const std::function<void(std::int64_t, std::int64_t)>& progress,
                                        bool keep_raw_inside) {
  const ReconstructionParams& params = scene.params;
  const double h = params.voxel_mm;
  const GridSpec& grid = scene.grid();
  SampledReconstruction out;

  const auto t0 = std::chrono::steady_clock::now();
  SolidAssembly assembly(scene, out);
  if (params.method == ReconstructionMethod::nearest_plane) {
    // Method 1 straight into blocks: no per-voxel value, distance or plane of the whole grid.
    forEachNearestPlaneBlock(scene.planes, scene.fields, grid, [&](std::int64_t b, const NearestPlaneBlock& v) {
      assembly.add(b, {v.value.data(), v.plane_distance.data(), v.nearest_plane.data(), v.nearest_plane.data(),
                       v.plane_distance.data(), v.far_outside});
    }, true, progress, &scene.pieces);
  } else {
    // Method 2; on observed pieces R'_Ω (observed_section_voronoi.h), which is R' itself when
    // every piece is a whole plane.
    SectionVoronoiParams vp;
    vp.slab_mm = params.slab_voxels * h;
    ObservedSectionVoronoiStatistics statistics;
    forEachObservedSectionVoronoiBlock(scene.planes, scene.fields, scene.pieces, grid, vp,
                                       [&](std::int64_t b, const SectionVoronoiBlock& v) {
      assembly.add(b, {v.value.data(), v.plane_distance.data(), v.nearest_plane.data(), v.section_plane.data(),
                       v.lift_height.data()});
    }, progress, &statistics);
    out.exact_face_tests = statistics.voronoi.exact_face_tests;
    out.cells_clipped = statistics.voronoi.cells_clipped;
    out.observed_lift_voxels_kept = statistics.lift_voxels_kept;
    out.observed_lift_voxels_dropped = statistics.lift_voxels_dropped;
    out.observed_pieces_voxels_added = statistics.pieces_voxels_added;
  }
  out.max_lift_mm = assembly.maxLift();
  out.evaluate_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  if (keep_raw_inside) out.raw_inside = out.inside;
  out.storage.blocks = out.field.blockCount();
  out.storage.anchor_leaves = assembly.in_anchor.leafCount() + assembly.out_anchor.leafCount();
  out.repair = repairSampledTopology(out.inside, assembly.in_anchor, assembly.out_anchor);
  assembly.in_anchor = {};
  assembly.out_anchor = {};

  // The field for meshing: the evaluated values, with their sign forced to the repaired set.
  imposeSolid(out.field, out.inside, float(0.05 * h));
  out.voxels_inside = out.inside.count(1);
  out.storage.field_leaves = out.field.leafCount();
  out.storage.section_leaves = out.section_plane.leafCount();
  out.storage.inside_leaves = out.inside.leafCount();
  out.voxel_betti = voxelBetti(out.inside);
  return out;
}

}  // namespace xsect

// How much to trust a solid's topology (issue 52): the thesis' sampling verdict is a sufficient
// condition that real data rarely meets, so beside it each result says whether its Betti numbers
// survive the smallest changes the sampling cannot rule out. Spurious features of sparse sections
// are thin: tunnels and fins between planes a voxel or two across, necks where two lifts barely
// meet, specks; a true handle or cavity of the object is many voxels across.
//
// The probes. With B the solid's voxel set and Ball(r) the voxel centres within r, the closing
// B • Ball(r) fills the gaps, holes and cavities narrower than 2r and joins parts facing each other
// across less than that (walls; two convex parts join only where no ball of radius r passes between);
// the opening B ∘ Ball(r) cuts the necks and handles thinner than 2r and removes specks
// (geometry/core/block_ball_morphology.h, window by window). A feature "in doubt at r" is a change of a Betti number by
// either, counted per kind (components beyond the first, tunnels b1, cavities b2):
// |b - b(closing)| + |b - b(opening)|. A feature the closing would make counts too: two parts
// within 2r of each other may be one tunnel or one component that the sections missed.
// Two radii:
//  - r = 1 voxel: what the voxels themselves cannot tell (the thinnest spurious tunnels);
//  - r = the data's scale: half the largest height of a cell holding sections (the sampling
//    diagnosis' upper bound h_C, thesis ch. 1 §2.3), at least 2 voxels. Between planes that far
//    apart the solid is the method's extrapolation, and a feature smaller than that was not seen
//    by the sections: the thesis' density condition C1 asks the reach to exceed the heights for
//    the topology to be right.
// The level:
//  - low: something is in doubt at 1 voxel (the data's scale is then not probed: it cannot raise
//    the level);
//  - medium: nothing at 1 voxel, something at the data's scale;
//  - high: nothing at either.
// What each level has meant in measured rates is in docs/topology.md ("Topology confidence").
#pragma once

#include <array>
#include <string>
#include <vector>

#include "geometry/core/block_grid.h"
#include "geometry/core/digital_topology.h"
#include "geometry/core/named_choice.h"
#include "geometry/core/types.h"

namespace xsect {

enum class ConfidenceLevel { high, medium, low };
constexpr std::array<NamedChoice<ConfidenceLevel>, 3> kConfidenceLevels{{
    {ConfidenceLevel::high, "high"},
    {ConfidenceLevel::medium, "medium"},
    {ConfidenceLevel::low, "low"},
}};

/// The solid's Betti numbers after a closing and an opening by a ball of `radius_voxels`.
struct TopologyProbe {
  double radius_voxels = 1;
  Betti closed{0, 0, 0};
  Betti opened{0, 0, 0};
};

/// The features of one kind and their level: `count` of the solid's, of which `in_doubt_1` change
/// at 1 voxel and `in_doubt_2` more at the data's scale (a changed count can exceed the solid's when
/// the closing would make features: near contacts).
struct FeatureDoubt {
  const char* kind = "tunnel";  ///< "component" (beyond the first), "tunnel", "cavity"
  int count = 0;
  int in_doubt_1 = 0;
  int in_doubt_2 = 0;
  ConfidenceLevel level = ConfidenceLevel::high;
};

struct TopologyConfidence {
  ConfidenceLevel level = ConfidenceLevel::high;
  Betti betti{0, 0, 0};
  std::array<TopologyProbe, 2> probes{};       ///< 1 voxel and the data's scale
  /// Whether the data's scale was probed: not when the voxel's probe already made the result low
  /// (its Betti numbers and in_doubt_2 are then not known).
  bool scale_probed = false;
  std::array<FeatureDoubt, 3> kinds{};         ///< components, tunnels, cavities
  std::int64_t voxels = 0;                     ///< the solid's voxels
  double voxel_mm = 0;                         ///< the grid's voxel
};

/// @param inside  the solid (1 = in).
/// @param betti   its Betti numbers (voxelBetti's), as the report gives them.
/// @param scale_mm  the data's scale (half the largest cell height, mm); the second probe's radius
///                  is the larger of it and 2 voxels.
TopologyConfidence topologyConfidence(const BlockGrid<std::uint8_t>& inside, const Betti& betti, double scale_mm);

/// The same for a solid given as one byte per voxel of `grid`.
TopologyConfidence topologyConfidence(const std::vector<std::uint8_t>& inside, const GridSpec& grid,
                                      const Betti& betti, double scale_mm);

/// One line for people: "high", or "low: 9 tunnels at most 2 voxels (0.8 mm) across" and the like.
std::string confidenceText(const TopologyConfidence& c);

}  // namespace xsect

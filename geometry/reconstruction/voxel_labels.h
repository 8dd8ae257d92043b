// Several materials (thesis remark after Def. 17): the reconstruction runs on the union of the
// labelled sections; each voxel of the solid then takes the label of the section its lift comes
// from: the labelled section holding its projection on the plane that decided it (method 1: the
// nearest plane; method 2: the plane of the section whose Voronoi cell holds it). The labelled
// solids are disjoint and their union is the one-material solid, by construction.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/core/block_grid.h"
#include "geometry/core/types.h"
#include "geometry/scene/observed_piece.h"

namespace xsect {

/// @param inside         the (repaired) solid, 1 = in.
/// @param section_plane  per voxel, the plane that decided it (-1: none, e.g. added by the repair),
///                       on the solid's grid.
/// @param planes         the planes (their frames), in the indices section_plane refers to.
/// @param labelled       per plane, its sections with their labels; empty: the planes' own
///                       sections (and their labels).
/// @returns per voxel the label (0 outside), by blocks. Voxels without a deciding plane, or whose
///          projection falls on no labelled section (within rounding of a contour), take the label
///          of the nearest labelled voxel of the solid (breadth-first, 26-neighbours; ties by scan
///          order).
/// @param pieces         null, or the planes' observed pieces (issue 20): a voxel's label is read at
///                       the point of its plane's piece nearest to it, not at its projection.
BlockGrid<std::uint16_t> voxelLabels(const BlockGrid<std::uint8_t>& inside, const BlockGrid<int>& section_plane,
                                     const std::vector<CuttingPlane>& planes,
                                     const std::vector<std::vector<Section>>& labelled,
                                     const std::vector<ObservedPiece>* pieces = nullptr);

/// The field of one label for meshing: the solid's field where the voxel has that label, and the
/// mirror value (|v|, at least `nudge`) inside other labels, so that neighbouring labels share
/// their interface half-way between voxel centres.
ScalarField labelField(const ScalarField& field, const std::vector<std::uint16_t>& labels,
                       std::uint16_t label, float nudge);

}  // namespace xsect

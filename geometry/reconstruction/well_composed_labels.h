// Several materials (thesis remark after Def. 17), one solid each (issue 49): the labels of the
// union's voxels changed, where two voxels of one label meet at an edge or a vertex only, so that
// every label's voxel set is well-composed at once (digital_topology.h makeWellComposed: its
// 26-connected components, its 6-connected complement and the iso-surface between voxel centres
// have one topology) while the labels stay a partition of the union. Making each label
// well-composed on its own adds voxels of its neighbours to it, so the labels' solids overlap and
// labels.nrrd is not what the label meshes bound (4 of 24 two-material runs of test_one_solid had
// a label whose voxels and mesh differed).
//
// The rule, at every critical configuration of a label M (a 2x2 checkerboard in an axis plane, or
// a 2x2x2 cube in which M, or what is not M, is exactly two opposite corners): the changes that
// remove it are a voxel of another label there joining M, or one of M's voxels there taking the
// label of such a neighbour. The first (in a fixed order) that keeps both labels' Betti numbers
// (the voxel simple for both: isSimpleCube) is taken, on a voxel not changed before or lowering
// its label; else the first that lowers a label (a checkerboard of two labels: one of them loses
// the edge contact). Every change either adds a voxel to the union, or changes a voxel never
// changed before, or lowers a label, so the passes end; and a label's configuration always has
// such a change when the union is well-composed (its other two corners outside would make it the
// union's). Where the union itself is not (method 3's voxels sampled by centres, no voxel mesh),
// its configuration is removed first as makeWellComposed does, by a voxel added next to it (the
// first simple for the union and for the label it takes, the label of the union's voxel it is
// next to). On random wavy interfaces (tests/test_well_composed_labels.cpp) 56 of 70 labels keep
// their Betti numbers (47 when changes only lower labels).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

struct LabelComposition {
  std::int64_t voxels_relabelled = 0;  ///< voxels of the union whose label changed
  std::int64_t voxels_added = 0;       ///< voxels added to the union (it was not well-composed)
};

/// Whether a voxel is simple for a set of voxels taken as closed unit cubes: its cube meets the
/// cubes of the set's other voxels in its 3x3x3 neighbourhood in a contractible set K, so that
/// adding the voxel to the set, or taking it out, keeps the homotopy type of the union of cubes
/// (glued along, or cut along, a contractible set), hence its Betti numbers as voxelBetti counts
/// them. K is a subcomplex of the cube's boundary sphere (a face when its face neighbour is in the
/// set, an edge when one of the three voxels around it is, a corner when one of the seven is);
/// such a K is contractible when it is not empty, connected, not the whole sphere, and its Euler
/// characteristic V - E + F is 1 (its first Betti number is then 0, by Alexander duality).
/// @param set  the 3x3x3 neighbourhood, index (dx + 1) + 3 (dy + 1) + 9 (dz + 1); the centre is
///             ignored.
bool isSimpleCube(const std::array<bool, 27>& set);

/// @param labels  per voxel of `grid` (x fastest), 0 outside the union, else the voxel's label;
///                changed in place.
/// Deterministic: passes in scan order until one changes nothing.
LabelComposition makeLabelsWellComposed(std::vector<std::uint16_t>& labels, const GridSpec& grid);

}  // namespace xsect

// Evidence the planes give about a sampled solid (thesis ch. 1 §1, the characterisation of R used
// by digital_topology.h): a voxel next to a cutting plane is certainly inside the object when its
// projection lies clearly inside the plane's sections, certainly outside when it lies clearly
// outside them. Any reconstruction that interpolates the sections (methods 1 and 2, Shepard's f,
// whose zero set meets every plane in its sections) agrees with these voxels, so a component of
// its sampled solid without inside evidence, or a cavity without outside evidence, is an artefact
// of the grid or of the interpolation, not something the sections show.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/scene/observed_piece.h"
#include "geometry/scene/section_distance_field.h"
#include "geometry/core/types.h"

namespace xsect {

struct PlaneEvidence {
  std::vector<std::uint8_t> inside;   ///< 1 = voxel certainly inside (one byte per voxel, x fastest)
  std::vector<std::uint8_t> outside;  ///< 1 = voxel certainly outside
};

/// @param planes     cutting planes (real ones, then any virtual end planes: those give outside
///                   evidence only).
/// @param fields     f_i of each plane, same order (section_distance_field.h).
/// @param grid       the voxel lattice.
/// @param near_mm    a voxel is next to a plane when its centre is within this distance (mm, >= 0);
///                   among several, the nearest plane decides; planes equally near (within a
///                   millionth of a voxel: coincident planes) decide together, inside when one
///                   says inside, outside when all say outside.
/// @param margin_mm  clearly inside / outside: f_i at the projection <= -margin / >= margin (mm).
/// @param pieces     optional observed piece of each plane (issue 20): a plane gives evidence only
///                   at voxels whose projection lies in its piece (beyond an image nothing was seen).
/// Throws std::invalid_argument when fields.size() != planes.size(), pieces (if given) do not match
/// the planes, or a length is negative.
PlaneEvidence planeEvidence(const std::vector<CuttingPlane>& planes,
                            const std::vector<SectionDistanceField>& fields, const GridSpec& grid,
                            double near_mm, double margin_mm,
                            const std::vector<ObservedPiece>* pieces = nullptr);

}  // namespace xsect

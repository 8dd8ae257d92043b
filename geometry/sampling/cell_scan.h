// The cells of the arrangement of the cutting planes met by a lattice, each with bounds on its
// height h_C (thesis ch. 1 §2.3, Def. 23), including the cells that hold no section.
//
// Why a lattice gives h_C: for x in a cell C, d(x, ∂C) = D(x) := min over all planes P of d(x, P)
// (a plane that does not bound C is at least as far as ∂C, since the segment to it leaves C), so
// h_C = max over C of D. On a lattice of spacing s, with ρ = s·√3/2 its half diagonal:
//   - lower bound: max of D over the lattice points inside C;
//   - upper bound: max(ρ, that max + ρ): a point x of C lies within ρ of a lattice point q; if q
//     lies in another cell the segment [x, q] crosses a plane, so D(x) ≤ ρ; otherwise D(x) ≤ D(q) + ρ
//     (D is 1-Lipschitz). A cell met by no lattice point has h_C ≤ ρ.
// Cells are told apart by their sign vectors against all planes, kept as 64-bit Zobrist keys (the
// XOR of one fixed random key per plane on whose positive side the point lies).
#pragma once

#include <algorithm>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

/// Zobrist keys of sign vectors against a list of planes.
class CellKeys {
 public:
  explicit CellKeys(const std::vector<Plane>& planes);
  /// The key of the cell holding x. `onPlane` (if ≥ 0) is a plane x lies on, taken on side
  /// `side` (+1: the normal's side, −1 the other), whatever rounding says; `onPlane2`, `side2` a
  /// second one (a point where a contour crosses another plane's trace).
  /// `clearance`, if given, receives the least distance of x to the other planes (mm).
  std::uint64_t of(const Vec3& x, int onPlane = -1, int side = 0, double* clearance = nullptr, int onPlane2 = -1,
                   int side2 = 0) const;
  /// The signs (+1 / −1) of x against every plane, with the same convention.
  std::vector<int> sides(const Vec3& x, int onPlane = -1, int side = 0, int onPlane2 = -1, int side2 = 0) const;
  std::uint64_t key(std::size_t plane) const { return keys_[plane]; }

 private:
  // Structure of arrays, so that the loops over planes vectorise.
  std::vector<double> nx_, ny_, nz_, offsets_;  ///< unit normals; offsets n · origin
  std::vector<std::uint64_t> keys_;
};

/// A cell met by the lattice.
struct ScannedCell {
  std::uint64_t key = 0;
  double max_distance_mm = 0;  ///< max of D over its lattice points (a lower bound of h_C)
  Vec3 farthest = Vec3::Zero();///< the lattice point where that max is reached (first in scan order)
  std::int64_t points = 0;     ///< lattice points inside it
  bool on_box = false;         ///< it holds a lattice point on the box's boundary (an end cell)
};

struct CellScan {
  GridSpec lattice;            ///< the lattice: points origin + spacing·(i, j, k)
  double half_diagonal_mm = 0; ///< ρ
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  ///< the box scanned
  std::vector<ScannedCell> cells;             ///< in the order the scan first meets them
  std::vector<std::int32_t> cell_of_point;    ///< per lattice point: index into cells, −1 outside the box
  std::unordered_map<std::uint64_t, int> index_of_key;

  /// Index of the cell with this key, −1 if the lattice met no point of it.
  int find(std::uint64_t key) const {
    const auto it = index_of_key.find(key);
    return it == index_of_key.end() ? -1 : it->second;
  }
  /// Upper bound of h_C for a scanned cell (see the file comment).
  double heightBound(const ScannedCell& c) const {
    return std::max(half_diagonal_mm, c.max_distance_mm + half_diagonal_mm);
  }
};

/// The lattice spacing for scanning `planes` over [lo, hi]: the voxel size, coarsened until
/// points × planes stays within `work` (the scan costs one distance per point and plane) and the
/// points within `max_points` (16 bytes each while scanning).
double scanSpacing(const Vec3& lo, const Vec3& hi, double voxel_mm, std::size_t planes, double work = 1e9,
                   double max_points = 1e6);

/// @param planes   all cutting planes, real and virtual (unit normals).
/// @param lo, hi   the box (mm); points outside it belong to no cell. In practice the end planes'
///                 box, so that every cell is closed.
/// @param spacing  lattice spacing, mm (> 0).
/// Parallel over lattice rows; the result does not depend on the thread count.
CellScan scanCells(const std::vector<Plane>& planes, const CellKeys& keys, const Vec3& lo, const Vec3& hi,
                   double spacing);

}  // namespace xsect

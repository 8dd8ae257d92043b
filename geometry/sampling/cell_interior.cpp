// A point strictly inside a cell (see cell_interior.h).
#include "geometry/sampling/cell_interior.h"

#include "geometry/sampling/cell_height.h"

namespace xsect {

std::vector<int> KeyPoint::sides(const CellKeys& keys, const Vec3& x) const {
  return keys.sides(x, plane, side, trace_plane, trace_side);
}

Interior cellInterior(const CellSampling& c, const std::vector<Plane>& ps, const CellKeys& keys,
                      const std::vector<KeyPoint>& keyPoints, const Vec3& lo, const Vec3& hi,
                      std::vector<int>* sides, Vec3* interior) {
  const bool inside = c.scanned >= 0 || c.height_exact;
  const KeyPoint* key = inside || c.arrangement_cell < 0 ? nullptr : &keyPoints[std::size_t(c.arrangement_cell)];
  *sides = key ? key->sides(keys, c.centre) : keys.sides(c.centre);
  *interior = c.centre;
  if (inside && c.height_lo_mm > 0) return Interior::found;
  const CellHeight h = cellHeight(ps, *sides, lo, hi, false);
  if (h.open || !(h.height > 1e-9 * (hi - lo).norm())) return key && !key->generic ? Interior::none : Interior::unknown;
  if (keys.of(h.centre) != c.key) return Interior::unknown;
  *interior = h.centre;
  return Interior::found;
}

}  // namespace xsect

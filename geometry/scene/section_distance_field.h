// The function f_i of thesis ch. 1 §1.1 on one cutting plane: the signed Euclidean distance to the
// section-contours (negative inside the sections), sampled on a regular raster in plane coordinates
// and read back bilinearly. Exact at raster nodes within `band` of a contour; beyond the band only
// the sign is kept (value ±band). Outside the raster (farther than `band` from every section) the
// value is +band: the plane holds no section there.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

struct SectionDistanceField {
  Vec2 origin = Vec2::Zero();  ///< plane coordinates of node (0, 0), mm
  double step = 1.0;           ///< node spacing, mm
  int nu = 0, nv = 0;          ///< nodes along u and v (0 when the plane has no section)
  float band = 1.0f;           ///< clamp, mm

  /// Nodes are stored by tiles of kTile x kTile: a tile no contour comes within the band of holds
  /// one value (+band outside, -band inside the sections), not its nodes, so that the memory
  /// follows the contours' length, not the sections' area (issue 17).
  static constexpr int kTile = 8;

  /// The value at node (i, j), 0 <= i < nu, 0 <= j < nv.
  float node(int i, int j) const {
    const std::int32_t t = tiles_[std::size_t(j / kTile) * std::size_t(tilesU_) + std::size_t(i / kTile)];
    if (t < 0) return t == kOutside ? band : -band;
    return pool_[std::size_t(t) * kTileNodes + std::size_t(j % kTile) * kTile + std::size_t(i % kTile)];
  }

  /// Bilinear value at plane coordinates (a, b) in mm; exactly ±band where the four nodes around
  /// (a, b) all hold that value (beyond the band: only the sign is known, and interpolating equal
  /// values in floating point could round off it).
  float sample(double a, double b) const {
    Square q;
    if (!square(a, b, &q)) return band;
    return q.beyondBand(band) ? q.r00 : q.value();
  }

  /// sample() and its gradient (per mm of a and b) within the raster square holding (a, b): the
  /// derivative of the bilinear interpolant there. Zero gradient where sample() is a constant
  /// ±band (beyond the band, or off the raster).
  float sampleWithGradient(double a, double b, Vec2* gradient) const {
    *gradient = Vec2::Zero();
    Square q;
    if (!square(a, b, &q)) return band;
    if (q.beyondBand(band)) return q.r00;
    *gradient = Vec2(((1 - q.fy) * (q.r01 - q.r00) + q.fy * (q.r11 - q.r10)) / step,
                     ((1 - q.fx) * (q.r10 - q.r00) + q.fx * (q.r11 - q.r01)) / step);
    return q.value();
  }

  /// Whether sample() is +band everywhere in the rectangle [a0, a1] x [b0, b1] of plane
  /// coordinates (mm): every raster square meeting it lies in tiles no contour comes within the
  /// band of, outside the sections, or off the raster. Conservative (a tile of stored nodes is
  /// never taken as outside).
  bool outsideOver(double a0, double a1, double b0, double b1) const {
    if (nu < 2 || nv < 2) return true;
    const double x0 = (a0 - origin.x()) / step, x1 = (a1 - origin.x()) / step;
    const double y0 = (b0 - origin.y()) / step, y1 = (b1 - origin.y()) / step;
    if (!(x1 >= 0.0 && y1 >= 0.0 && x0 <= nu - 1.0 && y0 <= nv - 1.0)) return true;  // off the raster
    // The nodes of every square meeting the rectangle (locate's squares: lower node clamped).
    const int i0 = std::min(int(std::max(0.0, x0)), nu - 2), i1 = std::min(int(std::min(x1, nu - 1.0)), nu - 2) + 1;
    const int j0 = std::min(int(std::max(0.0, y0)), nv - 2), j1 = std::min(int(std::min(y1, nv - 1.0)), nv - 2) + 1;
    for (int tj = j0 / kTile; tj <= j1 / kTile; ++tj)
      for (int ti = i0 / kTile; ti <= i1 / kTile; ++ti)
        if (tiles_[std::size_t(tj) * std::size_t(tilesU_) + std::size_t(ti)] != kOutside) return false;
    return true;
  }

  /// Bilinear value at (a, b) when the four nodes around it all hold exact distances (within the
  /// band): returns false, leaving *v alone, where a node is clamped or (a, b) is off the raster.
  bool sampleWithinBand(double a, double b, float* v) const {
    Square q;
    if (!square(a, b, &q)) return false;
    const float lim = band;
    if (!(std::abs(q.r00) < lim && std::abs(q.r01) < lim && std::abs(q.r10) < lim && std::abs(q.r11) < lim))
      return false;
    *v = q.value();
    return true;
  }

  /// A raster of nu x nv nodes (row by row, u fastest) whose tiles of values all equal to +band or
  /// all to -band are kept as one value.
  static SectionDistanceField fromNodes(const Vec2& origin, double step, int nu, int nv, float band,
                                        const std::vector<float>& values);

 private:
  friend SectionDistanceField sectionDistanceField(const std::vector<Section>&, double, double);
  static constexpr std::int32_t kOutside = -1, kInside = -2;
  static constexpr std::size_t kTileNodes = std::size_t(kTile) * kTile;

  /// A raster square's four nodes and where a point lies across it.
  struct Square {
    float fx, fy;              ///< fractions across the square along u and v
    float r00, r01, r10, r11;  ///< nodes (i, j), (i+1, j), (i, j+1), (i+1, j+1)
    float value() const { return (1 - fy) * ((1 - fx) * r00 + fx * r01) + fy * ((1 - fx) * r10 + fx * r11); }
    /// All four nodes hold the same ±band (the value there is exactly that, not a rounding of it).
    bool beyondBand(float band) const { return r00 == r01 && r00 == r10 && r00 == r11 && std::abs(r00) == band; }
  };
  /// The square holding plane point (a, b); false off the raster.
  bool square(double a, double b, Square* q) const {
    int i, j;
    if (!locate(a, b, &i, &j, &q->fx, &q->fy)) return false;
    corners(i, j, &q->r00, &q->r01, &q->r10, &q->r11);
    return true;
  }
  /// The raster square holding plane point (a, b): its lower node (i, j) and the fractions
  /// (fx, fy) across it; false off the raster.
  bool locate(double a, double b, int* i, int* j, float* fx, float* fy) const {
    const double x = (a - origin.x()) / step, y = (b - origin.y()) / step;
    if (!(x >= 0.0 && y >= 0.0 && x <= nu - 1.0 && y <= nv - 1.0)) return false;
    *i = std::min(int(x), nu - 2);
    *j = std::min(int(y), nv - 2);
    *fx = float(x - *i);
    *fy = float(y - *j);
    return true;
  }
  /// The four nodes (i, j), (i+1, j), (i, j+1), (i+1, j+1).
  void corners(int i, int j, float* r00, float* r01, float* r10, float* r11) const {
    if (i % kTile != kTile - 1 && j % kTile != kTile - 1) {  // one tile holds all four
      const std::int32_t t = tiles_[std::size_t(j / kTile) * std::size_t(tilesU_) + std::size_t(i / kTile)];
      if (t < 0) {
        *r00 = *r01 = *r10 = *r11 = t == kOutside ? band : -band;
        return;
      }
      const float* p = &pool_[std::size_t(t) * kTileNodes + std::size_t(j % kTile) * kTile + std::size_t(i % kTile)];
      *r00 = p[0];
      *r01 = p[1];
      *r10 = p[kTile];
      *r11 = p[kTile + 1];
      return;
    }
    *r00 = node(i, j);
    *r01 = node(i + 1, j);
    *r10 = node(i, j + 1);
    *r11 = node(i + 1, j + 1);
  }
  /// Mutable node of a stored tile (building).
  float& stored(int i, int j) {
    const std::int32_t t = tiles_[std::size_t(j / kTile) * std::size_t(tilesU_) + std::size_t(i / kTile)];
    return pool_[std::size_t(t) * kTileNodes + std::size_t(j % kTile) * kTile + std::size_t(i % kTile)];
  }
  int tilesU_ = 0, tilesV_ = 0;
  std::vector<std::int32_t> tiles_;  ///< per tile: index of its values in pool_, or kOutside / kInside
  std::vector<float> pool_;          ///< kTile² values per stored tile, row by row
};

/// @param sections  polygons with holes in plane coordinates (mm).
/// @param step      raster node spacing in mm (> 0).
/// @param band      distance beyond which only the sign is kept, mm (> step).
SectionDistanceField sectionDistanceField(const std::vector<Section>& sections, double step,
                                          double band);

}  // namespace xsect

// The observed piece Ω_P of a cutting plane (issue 20; README "Observed pieces"): the part of P
// where its slice was seen, its image rectangle ∩ its field of view, eroded by one pixel (the
// outermost pixels are where a segmentation's contour follows the image's edge, not the object's:
// on the eroded piece a section that runs out of the image is still a section, by a pixel, where
// the piece ends). Virtual planes, contour files and `planes: whole` give the whole plane.
//
// What the reconstruction needs of Ω_P: for a plane point p, its distance o(p) to Ω_P (0 inside)
// and the nearest point of Ω_P. The distance from x to Ω_P is then sqrt(s(x)² + o(proj_P x)²),
// s the signed distance to P, and the nearest point of Ω_P to x is the nearest point of Ω_P to
// proj_P(x) (Pythagoras: Ω_P lies in P). A field of view is rasterised at the image's pixel and
// every node keeps its nearest observed node (OpenCV's labelled distance transform), shared by the
// planes that have the same field of view (a probe's sector: one raster for the sweep).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

/// Nodes of a raster over a rectangle of a plane, each with its nearest node of the observed region.
struct FieldOfViewRaster {
  Vec2 origin = Vec2::Zero();  ///< plane coordinates of node (0, 0), mm
  double step = 1.0;           ///< node spacing, mm
  int nu = 0, nv = 0;          ///< nodes along u and v
  std::vector<std::int32_t> nearest;  ///< per node (row by row, u fastest): nearest observed node's index
  std::vector<float> depth;           ///< per node: distance to the nearest unobserved node, mm (0 outside)
};

struct ObservedPiece {
  bool whole = true;        ///< Ω_P = P
  bool empty = false;       ///< nothing observed: Ω_P = ∅ (distance +inf)
  PlaneRect rect;           ///< the eroded image rectangle, plane coordinates (mm)
  /// The field of view within `rect` (null: all of rect). Shared between planes.
  std::shared_ptr<const FieldOfViewRaster> fov;
  /// Error bound of distance(): the field of view's raster step (0 for rectangles), mm.
  double slack = 0.0;

  /// o(p): the distance from plane point (a, b) to Ω_P, mm (0 inside), and in (*na, *nb) the
  /// nearest point of Ω_P (a, b themselves inside). Outside `rect` with a field of view: the
  /// distance through the nearest point of rect (an upper bound within `slack` of exact for
  /// fields of view that reach the rectangle's sides, as a sector does).
  double distance(double a, double b, double* na, double* nb) const {
    if (whole) {
      *na = a;
      *nb = b;
      return 0.0;
    }
    if (empty) {
      *na = a;
      *nb = b;
      return std::numeric_limits<double>::infinity();
    }
    const double ca = std::min(std::max(a, rect.min.x()), rect.max.x());
    const double cb = std::min(std::max(b, rect.min.y()), rect.max.y());
    double qa = ca, qb = cb;
    if (fov) {
      const FieldOfViewRaster& r = *fov;
      const int i = std::min(r.nu - 1, std::max(0, int(std::lround((ca - r.origin.x()) / r.step))));
      const int j = std::min(r.nv - 1, std::max(0, int(std::lround((cb - r.origin.y()) / r.step))));
      const std::int32_t n = r.nearest[std::size_t(j) * std::size_t(r.nu) + std::size_t(i)];
      if (n != std::int32_t(j) * r.nu + i) {  // the node is not observed: its nearest observed node
        qa = r.origin.x() + r.step * (n % r.nu);
        qb = r.origin.y() + r.step * (n / r.nu);
      }
    }
    *na = qa;
    *nb = qb;
    return std::hypot(a - qa, b - qb);
  }
};

/// Whether Ω_P holds the whole disc of `radius` (mm) about plane point (a, b): then the nearest
/// point of Ω_P to every point of the disc is the point itself (o = 0 there), and method 1 may
/// treat P as a whole plane over it. Conservative (by `slack`).
inline bool covers(const ObservedPiece& piece, double a, double b, double radius) {
  if (piece.whole) return true;
  if (piece.empty) return false;
  const PlaneRect& r = piece.rect;
  if (!(a - radius >= r.min.x() && a + radius <= r.max.x() && b - radius >= r.min.y() && b + radius <= r.max.y()))
    return false;
  if (!piece.fov) return true;
  const FieldOfViewRaster& f = *piece.fov;
  const int i = std::min(f.nu - 1, std::max(0, int(std::lround((a - f.origin.x()) / f.step))));
  const int j = std::min(f.nv - 1, std::max(0, int(std::lround((b - f.origin.y()) / f.step))));
  return f.depth[std::size_t(j) * std::size_t(f.nu) + std::size_t(i)] >= radius + 2 * piece.slack;
}

/// The observed pieces of `planes` (one per plane, in order). Whole pieces for virtual planes,
/// planes observed everywhere (contour files) and every plane when `observed` is false; an empty
/// piece for a plane observed nowhere (an empty extent). Fields of view that are equal (the same
/// rings, rectangle and pixel) share one raster.
std::vector<ObservedPiece> observedPieces(const std::vector<CuttingPlane>& planes, bool observed);

}  // namespace xsect

// The observed piece Ω_P of a cutting plane (issue 20; docs/methods.md, "Observed pieces"): the part of P
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
#include "geometry/scene/section_distance_field.h"

namespace xsect {

/// sqrt(x² + y²) without std::hypot's care for overflow (values here are millimetres): the
/// per-voxel loops of method 1 call it for every candidate piece.
inline double planeNorm(double x, double y) { return std::sqrt(x * x + y * y); }

/// Nodes of a raster over a rectangle of a plane (the image rectangle grown by a margin, which is
/// unobserved), each with its nearest observed node.
struct FieldOfViewRaster {
  Vec2 origin = Vec2::Zero();  ///< plane coordinates of node (0, 0), mm
  double step = 1.0;           ///< node spacing, mm
  int nu = 0, nv = 0;          ///< nodes along u and v
  std::vector<std::int32_t> nearest;  ///< per node (row by row, u fastest): nearest observed node's index
  std::vector<float> depth;           ///< per node: distance to the nearest unobserved node, mm (0 outside)

  PlaneRect domain() const {
    return {origin, origin + step * Vec2(nu - 1, nv - 1)};
  }
  std::size_t node(double a, double b) const {
    const int i = std::min(nu - 1, std::max(0, int(std::floor((a - origin.x()) / step + 0.5))));
    const int j = std::min(nv - 1, std::max(0, int(std::floor((b - origin.y()) / step + 0.5))));
    return std::size_t(j) * std::size_t(nu) + std::size_t(i);
  }
  Vec2 point(std::size_t n) const {
    return origin + step * Vec2(double(n % std::size_t(nu)), double(n / std::size_t(nu)));
  }
};

struct ObservedPiece {
  bool whole = true;        ///< Ω_P = P
  bool empty = false;       ///< nothing observed: Ω_P = ∅ (distance +inf)
  PlaneRect rect;           ///< the eroded image rectangle, plane coordinates (mm)
  /// The field of view (null: all of rect), on a raster over rect grown by a quarter of its size,
  /// shared between planes.
  std::shared_ptr<const FieldOfViewRaster> fov;
  /// No section reaches the piece's edge: f_P is +band (its raster's outside value) all along the
  /// piece's boundary, where every point beyond the piece finds its nearest point (set by
  /// markSectionsClearOfEdges).
  bool edge_outside = false;

  /// o(p): the distance from plane point (a, b) to Ω_P, mm (0 inside), and in (*na, *nb) the
  /// nearest point of Ω_P (a, b themselves inside). Exact for a rectangle. With a field of view,
  /// the distance to the observed node nearest the node of c, c the point of the raster's domain
  /// nearest (a, b) (c = (a, b) within it): within fovSlack of exact inside the domain (a labelled
  /// chamfer distance transform), an upper bound beyond it.
  double distance(double a, double b, double* na, double* nb) const {
    *na = a;
    *nb = b;
    if (whole) return 0.0;
    if (empty) return std::numeric_limits<double>::infinity();
    if (!fov) {
      *na = std::min(std::max(a, rect.min.x()), rect.max.x());
      *nb = std::min(std::max(b, rect.min.y()), rect.max.y());
      return planeNorm(a - *na, b - *nb);
    }
    const PlaneRect d = fov->domain();
    const double ca = std::min(std::max(a, d.min.x()), d.max.x());
    const double cb = std::min(std::max(b, d.min.y()), d.max.y());
    const std::size_t n = fov->node(ca, cb);
    const std::size_t q = std::size_t(fov->nearest[n]);
    if (q == n) return 0.0;  // an observed node (the domain's margin is unobserved: then (a, b) = c)
    const Vec2 p = fov->point(q);
    *na = p.x();
    *nb = p.y();
    return planeNorm(a - p.x(), b - p.y());
  }

  /// Whether plane point (a, b) lies in Ω_P (distance() is 0 there).
  bool holds(double a, double b) const {
    double na, nb;
    return distance(a, b, &na, &nb) == 0;
  }

  /// How far distance() may exceed the true distance near a field-of-view distance D (mm): the
  /// raster's rounding (two nodes) and the chamfer transform's relative error (5%).
  double fovSlack(double D) const { return fov ? 2 * fov->step + 0.05 * D : 0.0; }

  /// Bounds of distance() over the disc of radius `rho` (mm) about plane point (a, b): *lo <=
  /// distance() <= *hi there. A rectangle's distance is 1-Lipschitz. With a field of view, c the
  /// domain's point nearest (a, b) at t from it and D = distance(c): the domain is convex and holds
  /// Ω_P, so o(p)² >= |p - c(p)|² + o(c(p))², and |p - q| <= |p - c(p)| + |c(p) - q|.
  void bounds(double a, double b, double rho, double* lo, double* hi) const {
    double na, nb;
    if (!fov || whole || empty) {
      const double o = distance(a, b, &na, &nb);
      *lo = std::max(0.0, o - rho);
      *hi = o + rho;
      return;
    }
    const PlaneRect d = fov->domain();
    const double ca = std::min(std::max(a, d.min.x()), d.max.x());
    const double cb = std::min(std::max(b, d.min.y()), d.max.y());
    const double t = planeNorm(a - ca, b - cb), D = distance(ca, cb, &na, &nb);
    *lo = planeNorm(std::max(0.0, t - rho), std::max(0.0, D - rho - fovSlack(D)));
    *hi = t + D + 2 * rho + fovSlack(D);
  }
};

/// Whether Ω_P holds the whole disc of `radius` (mm) about plane point (a, b): then the nearest
/// point of Ω_P to every point of the disc is the point itself (o = 0 there), and method 1 may
/// treat P as a whole plane over it. Conservative (by two raster nodes).
inline bool covers(const ObservedPiece& piece, double a, double b, double radius) {
  if (piece.whole) return true;
  if (piece.empty) return false;
  const PlaneRect& r = piece.rect;
  if (!(a - radius >= r.min.x() && a + radius <= r.max.x() && b - radius >= r.min.y() && b + radius <= r.max.y()))
    return false;
  if (!piece.fov) return true;
  return piece.fov->depth[piece.fov->node(a, b)] >= radius + 2 * piece.fov->step;
}

/// Sets ObservedPiece::edge_outside of each piece from its plane's section raster: whether the
/// raster is +band (exactly, by whole tiles) within a raster step of every point of the piece's
/// boundary (the rectangle's sides sampled at the pixel, or the field of view's boundary nodes).
void markSectionsClearOfEdges(std::vector<ObservedPiece>& pieces, const std::vector<SectionDistanceField>& fields);

/// The observed pieces of `planes` (one per plane, in order). Whole pieces for virtual planes,
/// planes observed everywhere (contour files) and every plane when `observed` is false; an empty
/// piece for a plane observed nowhere (an empty extent). Fields of view that are equal (the same
/// rings, rectangle and pixel) share one raster.
std::vector<ObservedPiece> observedPieces(const std::vector<CuttingPlane>& planes, bool observed);

}  // namespace xsect

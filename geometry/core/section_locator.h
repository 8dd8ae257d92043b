// Point location among one plane's sections (plane coordinates, mm): which section holds a point
// and which contour point is nearest. Containment counts crossings with the edges listed in the
// query's horizontal slab (slabs of equal height, about four edges each); nearest points scan the
// rings' edges in runs of 32 whose bounds prune them. The crossing rule is polygon.h's
// ringContains (strictly inside, even-odd) with its arithmetic, so answers equal sectionContains
// over the sections; the cost follows the edges near the query, not the rings' length. Why: on
// three orthogonal stacks of 40 planes through a torus, method 3 tests every grounded triangle and
// edge of its Delaunay cells and every face of its plane triangulations against the sections, and
// the linear scans there were the largest items of its profile (ringContains 10%, the gluing's
// serial per-plane pass more); with the pruning changes of the same issue the bench scenario
// multiaxial-3x40-m3 went 7.71 -> 6.13 s.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

class SectionLocator {
 public:
  /// A ring with the bounds of its runs of kRun consecutive edges (run k holds the edges that
  /// join vertex v to v + 1 for v in [k kRun, (k + 1) kRun)).
  struct RingRef {
    int section = -1;
    const Ring* ring = nullptr;
    bool outer = true;
    Eigen::AlignedBox2d box;
    std::vector<Eigen::AlignedBox2d> runs;
  };
  static constexpr std::size_t kRun = 32;

  /// A contour point: its distance to the query (mm), where it is, and its section.
  struct Nearest {
    double d = std::numeric_limits<double>::infinity();
    Vec2 q = Vec2::Zero();
    int section = -1;
  };

  SectionLocator() = default;
  /// Keeps a pointer to `sections`, which must outlive the locator and not change.
  explicit SectionLocator(const std::vector<Section>& sections);

  /// The section strictly holding p (outer ring in, no hole in), or -1.
  int holding(const Vec2& p) const;
  /// The contour point nearest to p (d = +inf without rings).
  Nearest nearestContour(const Vec2& p) const;
  /// A lower bound of the in-plane distance from p to the sections (their boxes), mm.
  double boxBound(const Vec2& p) const;

  const std::vector<Eigen::AlignedBox2d>& boxes() const { return boxes_; }  ///< per section
  const std::vector<RingRef>& rings() const { return rings_; }
  bool empty() const { return boxes_.empty(); }

  /// Calls f(a, b) for the edges (a = ring[v], b = ring[v + 1]) of the runs whose bounds satisfy
  /// near(box).
  template <class Near, class F>
  static void forEdges(const RingRef& r, Near&& near, F&& f) {
    const Ring& R = *r.ring;
    for (std::size_t k = 0; k < r.runs.size(); ++k) {
      if (!near(r.runs[k])) continue;
      for (std::size_t v = k * kRun; v < std::min((k + 1) * kRun, R.size()); ++v) f(R[v], R[(v + 1) % R.size()]);
    }
  }

 private:
  std::vector<Eigen::AlignedBox2d> boxes_;  ///< per section, over all its rings
  std::vector<RingRef> rings_;              ///< section by section, outer ring first
  std::vector<std::size_t> first_ring_;     ///< rings_ of section s: [first_ring_[s], first_ring_[s + 1])
  /// Horizontal slabs [y0 + k h, y0 + (k + 1) h): the edges (ring, v: vertex v to v + 1) whose
  /// half-open y-range [min, max) meets slab k are slab_edges_[slab_start_[k] .. slab_start_[k + 1]).
  double y0_ = 0, h_ = 1;
  std::vector<std::uint32_t> slab_start_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> slab_edges_;
  int holdingByRuns(const Vec2& p) const;
};

}  // namespace xsect

// Point location among a plane's sections (see section_locator.h).
#include "geometry/core/section_locator.h"

#include <algorithm>

#include "geometry/core/polygon.h"

namespace xsect {
namespace {

double boxDistance(const Eigen::AlignedBox2d& b, const Vec2& p) {
  return (p - p.cwiseMax(b.min()).cwiseMin(b.max())).norm();
}

}  // namespace

SectionLocator::SectionLocator(const std::vector<Section>& sections) {
  const auto add = [&](int s, const Ring& r, bool outer) {
    RingRef ref{s, &r, outer, ringBounds(r), {}};
    for (std::size_t v = 0; v < r.size(); v += kRun) {
      Eigen::AlignedBox2d b;
      for (std::size_t k = v; k <= std::min(v + kRun, r.size()); ++k) b.extend(r[k % r.size()]);
      ref.runs.push_back(b);
    }
    rings_.push_back(std::move(ref));
    return rings_.back().box;
  };
  for (std::size_t s = 0; s < sections.size(); ++s) {
    first_ring_.push_back(rings_.size());
    const Section& sec = sections[s];
    Eigen::AlignedBox2d box = add(int(s), sec.outer, true);
    for (const Ring& h : sec.holes) box.extend(add(int(s), h, false));
    boxes_.push_back(box);
  }
  first_ring_.push_back(rings_.size());

  // Slabs: about four edges per slab (over the rings' y-range), at most 2^16 of them.
  Eigen::AlignedBox2d all;
  std::size_t edges = 0;
  for (const RingRef& r : rings_) {
    all.extend(r.box);
    edges += r.ring->size() >= 3 ? r.ring->size() : 0;
  }
  if (edges == 0 || all.isEmpty()) return;
  const std::size_t slabs = std::clamp<std::size_t>(edges / 4, 1, std::size_t(1) << 16);
  y0_ = all.min().y();
  h_ = std::max((all.max().y() - y0_) / double(slabs), 1e-300);
  const auto slabOf = [&](double y) {
    return std::size_t(std::clamp((y - y0_) / h_, 0.0, double(slabs - 1)));
  };
  std::vector<std::uint32_t> count(slabs + 1, 0);
  const auto forEachEdge = [&](auto&& f) {
    for (std::size_t k = 0; k < rings_.size(); ++k) {
      const Ring& R = *rings_[k].ring;
      if (R.size() < 3) continue;
      for (std::size_t v = 0; v < R.size(); ++v) {
        const double ya = R[v].y(), yb = R[(v + 1) % R.size()].y();
        if (ya == yb) continue;  // a horizontal edge crosses no row
        for (std::size_t s = slabOf(std::min(ya, yb)), e = slabOf(std::max(ya, yb)); s <= e; ++s) f(s, k, v);
      }
    }
  };
  forEachEdge([&](std::size_t s, std::size_t, std::size_t) { ++count[s + 1]; });
  for (std::size_t s = 0; s < slabs; ++s) count[s + 1] += count[s];
  slab_start_ = count;
  slab_edges_.resize(count[slabs]);
  forEachEdge([&](std::size_t s, std::size_t k, std::size_t v) {
    slab_edges_[count[s]++] = {std::uint32_t(k), std::uint32_t(v)};
  });
}

int SectionLocator::holding(const Vec2& p) const {
  if (slab_start_.empty()) return -1;  // no ring of 3 vertices or more: nothing is held
  const double f = (p.y() - y0_) / h_;
  const std::size_t slabs = slab_start_.size() - 1;
  if (!(f >= 0) || f >= double(slabs) + 1) return -1;  // beyond every ring's rows (or NaN)
  const std::size_t k = std::min(std::size_t(f), slabs - 1);
  // Rings crossed an odd number of times to the right of p: toggled in a small list.
  constexpr std::size_t kMax = 64;
  std::uint32_t odd[kMax];
  std::size_t n = 0;
  for (std::uint32_t e = slab_start_[k]; e < slab_start_[k + 1]; ++e) {
    const auto [ring, v] = slab_edges_[e];
    const Ring& R = *rings_[ring].ring;
    const Vec2& b = R[v];
    const Vec2& a = R[(v + 1) % R.size()];  // ringContains' (r[i], r[i - 1])
    if ((a.y() > p.y()) == (b.y() > p.y()) ||
        !(p.x() < a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y())))
      continue;
    std::size_t i = 0;
    while (i < n && odd[i] != ring) ++i;
    if (i < n) odd[i] = odd[--n];  // crossed twice: even again
    else if (n < kMax) odd[n++] = ring;
    else return holdingByRuns(p);  // too many rings at once for the list
  }
  // The first section whose outer ring is odd and none of whose holes is (sectionContains' in
  // section order, should sections overlap).
  int found = -1;
  for (std::size_t i = 0; i < n; ++i) {
    const RingRef& r = rings_[odd[i]];
    if (!r.outer || (found >= 0 && r.section > found)) continue;
    bool inHole = false;
    for (std::size_t j = 0; j < n && !inHole; ++j) inHole = !rings_[odd[j]].outer && rings_[odd[j]].section == r.section;
    if (!inHole) found = r.section;
  }
  return found;
}

int SectionLocator::holdingByRuns(const Vec2& p) const {
  for (std::size_t s = 0; s < boxes_.size(); ++s) {
    if (!boxes_[s].contains(p)) continue;
    bool outer = false, hole = false;
    for (std::size_t k = first_ring_[s]; k < first_ring_[s + 1]; ++k) {
      const RingRef& r = rings_[k];
      if (r.ring->size() < 3) continue;
      bool in = false;
      const auto right = [&](const Eigen::AlignedBox2d& b) {
        return p.y() >= b.min().y() && p.y() < b.max().y() && p.x() <= b.max().x();
      };
      forEdges(r, right, [&](const Vec2& b, const Vec2& a) {  // ringContains' (r[i], r[i - 1])
        if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y()))
          in = !in;
      });
      if (r.outer) outer = in;
      else hole = hole || in;
    }
    if (outer && !hole) return int(s);
  }
  return -1;
}

SectionLocator::Nearest SectionLocator::nearestContour(const Vec2& p) const {
  Nearest n;
  for (const RingRef& r : rings_) {
    if (boxDistance(r.box, p) >= n.d) continue;
    forEdges(r, [&](const Eigen::AlignedBox2d& b) { return boxDistance(b, p) < n.d; },
             [&](const Vec2& a, const Vec2& b) {
               const Vec2 q = nearestOnSegment(p, a, b);
               const double d = (q - p).norm();
               if (d < n.d) n = {d, q, r.section};
             });
  }
  return n;
}

double SectionLocator::boxBound(const Vec2& p) const {
  double d = std::numeric_limits<double>::infinity();
  for (const auto& b : boxes_) d = std::min(d, boxDistance(b, p));
  return d;
}

}  // namespace xsect

// The facet planes of an arrangement cell by clipping a box (see cell_facets.h).
#include "geometry/arrangement/cell_facets.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace xsect {

void ClippedBox::reset(const Vec3& lo, const Vec3& hi, double tolerance_mm) {
  tolerance_ = tolerance_mm;
  points_.clear();
  start_.assign(1, 0);
  plane_.clear();
  const auto corner = [&](int m) {
    return Vec3((m & 1) ? hi.x() : lo.x(), (m & 2) ? hi.y() : lo.y(), (m & 4) ? hi.z() : lo.z());
  };
  // The six faces, each counter-clockwise seen from outside (orientation is not relied on).
  static constexpr int kFaces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1},
                                       {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
  for (const auto& f : kFaces) {
    for (const int m : f) points_.push_back(corner(m));
    start_.push_back(int(points_.size()));
    plane_.push_back(-1);
  }
}

bool ClippedBox::clip(const Vec3& n, double d, int side, int id) {
  const double eps = tolerance_;
  ++clips_;
  value_.resize(points_.size());
  bool cuts = false;
  for (std::size_t i = 0; i < points_.size(); ++i) {
    value_[i] = side * (n.dot(points_[i]) - d);
    cuts = cuts || value_[i] < -eps;
  }
  if (!cuts) return false;
  nextPoints_.clear();
  nextStart_.assign(1, 0);
  nextPlane_.clear();
  cap_.clear();
  for (std::size_t f = 0; f + 1 < start_.size(); ++f) {
    const int b = start_[f], e = start_[f + 1], m = e - b;
    bool anyIn = false, anyOut = false;
    for (int i = b; i < e; ++i) {
      anyIn = anyIn || value_[std::size_t(i)] > eps;
      anyOut = anyOut || value_[std::size_t(i)] < -eps;
    }
    if (!anyIn) continue;  // beyond the plane, or on it: the cap replaces it
    for (int k = 0; k < m; ++k) {
      const int i = b + k, j = b + (k + 1) % m;
      const double va = value_[std::size_t(i)], vb = value_[std::size_t(j)];
      const Vec3& A = points_[std::size_t(i)];
      if (va >= -eps) {
        nextPoints_.push_back(A);
        if (va <= eps) cap_.push_back(A);
      }
      // The edge crosses the plane strictly between its ends: the crossing is a new vertex.
      if ((va > eps && vb < -eps) || (va < -eps && vb > eps)) {
        const Vec3 X = A + (va / (va - vb)) * (points_[std::size_t(j)] - A);
        nextPoints_.push_back(X);
        cap_.push_back(X);
      }
    }
    if (!anyOut) {  // untouched (its vertices on the plane are already in the cap)
      nextStart_.push_back(int(nextPoints_.size()));
      nextPlane_.push_back(plane_[f]);
      continue;
    }
    if (int(nextPoints_.size()) - nextStart_.back() >= 3) {
      nextStart_.push_back(int(nextPoints_.size()));
      nextPlane_.push_back(plane_[f]);
    } else {
      nextPoints_.resize(std::size_t(nextStart_.back()));
    }
  }
  // The cap: the polytope's points on the plane, a convex polygon, ordered by angle about their
  // centroid; each appears once per face meeting it, so near-equal neighbours are merged.
  if (cap_.size() >= 3) {
    Vec3 c = Vec3::Zero();
    for (const Vec3& p : cap_) c += p;
    c /= double(cap_.size());
    const Vec3 u = n.unitOrthogonal(), v = n.cross(u);
    byAngle_.resize(cap_.size());
    for (std::size_t i = 0; i < cap_.size(); ++i) {
      const Vec3 r = cap_[i] - c;
      byAngle_[i] = {std::atan2(r.dot(v), r.dot(u)), int(i)};
    }
    std::sort(byAngle_.begin(), byAngle_.end());
    const std::size_t first = nextPoints_.size();
    for (const auto& [angle, i] : byAngle_) {
      const Vec3& p = cap_[std::size_t(i)];
      if (nextPoints_.size() > first && (nextPoints_.back() - p).norm() <= eps) continue;
      nextPoints_.push_back(p);
    }
    while (nextPoints_.size() > first + 1 && (nextPoints_.back() - nextPoints_[first]).norm() <= eps)
      nextPoints_.pop_back();
    if (nextPoints_.size() - first >= 3) {
      nextStart_.push_back(int(nextPoints_.size()));
      nextPlane_.push_back(id);
    } else {
      nextPoints_.resize(first);
    }
  }
  points_.swap(nextPoints_);
  start_.swap(nextStart_);
  plane_.swap(nextPlane_);
  return true;
}

double ClippedBox::farthestVertexDistance(const Vec3& x) const {
  double best = 0;
  for (const Vec3& p : points_) best = std::max(best, (p - x).squaredNorm());
  return std::sqrt(best);
}

void ClippedBox::facetPlanes(std::vector<int>* out) const {
  out->clear();
  for (const int p : plane_)
    if (p >= 0) out->push_back(p);
  std::sort(out->begin(), out->end());
  out->erase(std::unique(out->begin(), out->end()), out->end());
}

double cellFacets(const Vec3& x0, const std::vector<Vec3>& normals, const std::vector<double>& offsets,
                const std::vector<int>& order, const std::vector<double>& lower_bound, const Vec3& lo,
                const Vec3& hi, double tolerance_mm, ClippedBox& box, std::vector<int>* facets) {
  if (normals.size() != offsets.size()) throw std::invalid_argument("cellFacets: one offset per normal");
  if (order.size() != lower_bound.size()) throw std::invalid_argument("cellFacets: one bound per plane");
  box.reset(lo, hi, tolerance_mm);
  double farthest = box.farthestVertexDistance(x0);
  for (std::size_t k = 0; k < order.size(); ++k) {
    if (lower_bound[k] > farthest + tolerance_mm) break;
    const std::size_t q = std::size_t(order[k]);
    const double s = normals[q].dot(x0) - offsets[q];
    if (std::abs(s) > farthest + tolerance_mm) continue;
    if (box.clip(normals[q], offsets[q], s >= 0 ? 1 : -1, int(q))) farthest = box.farthestVertexDistance(x0);
    if (box.empty()) break;
  }
  box.facetPlanes(facets);
  return farthest;
}

}  // namespace xsect

// Mesh-plane cut and the scan-line IoU of the enclosed region against sections (plane_cut.h).
// The cut is computed directly per triangle rather than with CGAL::Polygon_mesh_slicer: the
// slicer reports tangential contacts (a vertex or an edge lying in the plane) as degenerate
// polylines, which break the even-odd parity the IoU relies on, whereas the symbolic
// perturbation used here (a vertex on the plane counts as above it) always yields closed loops.
#include "geometry/evaluation/plane_cut.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace xsect {
namespace {

struct Box2 {
  Vec2 min{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  Vec2 max{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  void add(const Vec2& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  void add(const Box2& b) {
    min = min.cwiseMin(b.min);
    max = max.cwiseMax(b.max);
  }
  bool empty() const { return !(min.x() < max.x() && min.y() < max.y()); }
};

/// Edges of all rings of the sections as segments (orientation irrelevant for even-odd).
std::vector<Segment2> sectionEdges(const std::vector<Section>& sections) {
  std::vector<Segment2> edges;
  auto addRing = [&](const Ring& ring) {
    for (std::size_t i = 0; i < ring.size(); ++i)
      edges.push_back({ring[i], ring[(i + 1) % ring.size()]});
  };
  for (const Section& s : sections) {
    addRing(s.outer);
    for (const Ring& h : s.holes) addRing(h);
  }
  return edges;
}

Box2 boundsOf(const std::vector<Segment2>& segments) {
  Box2 b;
  for (const auto& s : segments) {
    b.add(s[0]);
    b.add(s[1]);
  }
  return b;
}

/// The scan lines: `rows` lines at v = v0 + (r + 0.5) * dv.
struct ScanLines {
  double v0 = 0, dv = 1;
  int rows = 0;
  double at(int r) const { return v0 + (r + 0.5) * dv; }
};

ScanLines scanLines(double vmin, double vmax, double resolution) {
  ScanLines s;
  s.v0 = vmin;
  s.rows = std::max(1, int(std::ceil((vmax - vmin) / resolution)));
  s.dv = (vmax - vmin) / s.rows;
  return s;
}

/// Per scan line, the inside intervals [x0, x1] of the even-odd region of `segments`, clipped
/// to [umin, umax], sorted and disjoint. A segment crosses line v when exactly one endpoint has
/// v-coordinate > v (half-open rule: shared endpoints are counted once).
std::vector<std::vector<std::array<double, 2>>> insideIntervals(
    const std::vector<Segment2>& segments, const ScanLines& lines, double umin, double umax) {
  std::vector<std::vector<double>> xs(lines.rows);
  for (const auto& s : segments) {
    const Vec2 &p = s[0], &q = s[1];
    if (p.y() == q.y()) continue;
    const double lo = std::min(p.y(), q.y()), hi = std::max(p.y(), q.y());
    const int r0 = std::max(0, int(std::floor((lo - lines.v0) / lines.dv - 0.5)) - 1);
    const int r1 = std::min(lines.rows - 1, int(std::ceil((hi - lines.v0) / lines.dv - 0.5)) + 1);
    for (int r = r0; r <= r1; ++r) {
      const double v = lines.at(r);
      if ((p.y() > v) == (q.y() > v)) continue;
      xs[r].push_back(p.x() + (v - p.y()) * (q.x() - p.x()) / (q.y() - p.y()));
    }
  }
  std::vector<std::vector<std::array<double, 2>>> intervals(lines.rows);
  for (int r = 0; r < lines.rows; ++r) {
    auto& x = xs[r];
    std::sort(x.begin(), x.end());
    for (std::size_t i = 0; i + 1 < x.size(); i += 2) {
      const double a = std::max(x[i], umin), b = std::min(x[i + 1], umax);
      if (b > a) intervals[r].push_back({a, b});
    }
  }
  return intervals;
}

double length(const std::vector<std::array<double, 2>>& iv) {
  double l = 0;
  for (const auto& i : iv) l += i[1] - i[0];
  return l;
}

/// Length of the intersection of two sorted lists of disjoint intervals.
double overlap(const std::vector<std::array<double, 2>>& a,
               const std::vector<std::array<double, 2>>& b) {
  double l = 0;
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    const double lo = std::max(a[i][0], b[j][0]), hi = std::min(a[i][1], b[j][1]);
    if (hi > lo) l += hi - lo;
    if (a[i][1] < b[j][1]) ++i;
    else ++j;
  }
  return l;
}

}  // namespace

std::vector<Segment2> cutMesh(const TriangleMesh& mesh, const Plane& plane) {
  std::vector<double> d(mesh.vertices.size());
  for (std::size_t i = 0; i < d.size(); ++i)
    d[i] = plane.signedDistance(mesh.vertices[i].cast<double>());
  auto crossing = [&](std::uint32_t i, std::uint32_t j) {
    if (j < i) std::swap(i, j);  // same arithmetic from both triangles sharing the edge
    const Vec3 a = mesh.vertices[i].cast<double>(), b = mesh.vertices[j].cast<double>();
    const double t = d[i] / (d[i] - d[j]);
    return plane.toPlane(a + t * (b - a));
  };
  std::vector<Segment2> segments;
  for (const auto& tri : mesh.triangles) {
    const bool above[3] = {d[tri[0]] >= 0, d[tri[1]] >= 0, d[tri[2]] >= 0};
    if (above[0] == above[1] && above[1] == above[2]) continue;
    // The lone vertex k (on its own side) and the two edges leaving it.
    const int k = above[0] == above[1] ? 2 : (above[0] == above[2] ? 1 : 0);
    const std::uint32_t a = tri[k], b = tri[(k + 1) % 3], c = tri[(k + 2) % 3];
    segments.push_back({crossing(a, b), crossing(a, c)});
  }
  return segments;
}

double regionIoU(const std::vector<Segment2>& cut, const std::vector<Section>& sections,
                 double resolution_mm, const PlaneRect* clip) {
  if (!(resolution_mm > 0)) throw std::invalid_argument("regionIoU: resolution must be positive");
  const std::vector<Segment2> edges = sectionEdges(sections);
  Box2 box = boundsOf(cut);
  box.add(boundsOf(edges));
  if (clip) {
    box.min = box.min.cwiseMax(clip->min);
    box.max = box.max.cwiseMin(clip->max);
  }
  if (box.empty()) return std::numeric_limits<double>::quiet_NaN();
  const ScanLines lines = scanLines(box.min.y(), box.max.y(), resolution_mm);
  const auto a = insideIntervals(cut, lines, box.min.x(), box.max.x());
  const auto b = insideIntervals(edges, lines, box.min.x(), box.max.x());
  double inter = 0, uni = 0;
  for (int r = 0; r < lines.rows; ++r) {
    const double both = overlap(a[r], b[r]);
    inter += both;
    uni += length(a[r]) + length(b[r]) - both;
  }
  if (!(uni > 0)) return std::numeric_limits<double>::quiet_NaN();
  return inter / uni;
}

double cutArea(const std::vector<Segment2>& cut, double resolution_mm) {
  if (!(resolution_mm > 0)) throw std::invalid_argument("cutArea: resolution must be positive");
  const Box2 box = boundsOf(cut);
  if (box.empty()) return 0.0;
  const ScanLines lines = scanLines(box.min.y(), box.max.y(), resolution_mm);
  double area = 0;
  for (const auto& row : insideIntervals(cut, lines, box.min.x(), box.max.x())) area += length(row);
  return area * lines.dv;
}

}  // namespace xsect

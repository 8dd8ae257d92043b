// Coincident cutting planes (see coincident_planes.h).
#include "geometry/arrangement/coincident_planes.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace xsect {
namespace {

constexpr double kMaxAngleDeg = 1.0;
const double kPi = std::acos(-1.0);

std::array<Vec3, 4> extentCorners(const CuttingPlane& p) {
  const PlaneRect& e = p.extent;
  return {p.plane.toWorld(e.min), p.plane.toWorld({e.max.x(), e.min.y()}), p.plane.toWorld(e.max),
          p.plane.toWorld({e.min.x(), e.max.y()})};
}

double angleDeg(const Vec3& a, const Vec3& b) {
  return std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized())))) * 180.0 / kPi;
}

/// Largest distance of b's extent corners to a's plane and of a's to b's plane.
double offsetMm(const CuttingPlane& a, const CuttingPlane& b) {
  double d = 0.0;
  for (const Vec3& c : extentCorners(b)) d = std::max(d, std::abs(a.plane.signedDistance(c)));
  for (const Vec3& c : extentCorners(a)) d = std::max(d, std::abs(b.plane.signedDistance(c)));
  return d;
}

}  // namespace

double coincidenceTolerance(const CuttingPlane& a, const CuttingPlane& b) {
  double pixel = 0.0;
  for (const double px : {a.pixel_mm, b.pixel_mm})
    if (px > 0 && (pixel == 0.0 || px < pixel)) pixel = px;
  if (pixel > 0) return 1e-3 * pixel;
  double scale = std::max((a.extent.max - a.extent.min).norm(), (b.extent.max - b.extent.min).norm());
  for (const CuttingPlane* p : {&a, &b})
    for (const Vec3& c : extentCorners(*p)) scale = std::max(scale, c.cwiseAbs().maxCoeff());
  return 1e-6 * scale;
}

bool planesCoincide(const CuttingPlane& a, const CuttingPlane& b) {
  if (a.is_virtual || b.is_virtual) return false;
  const auto empty = [](const PlaneRect& e) { return !(e.max.x() > e.min.x() && e.max.y() > e.min.y()); };
  if (empty(a.extent) || empty(b.extent)) return false;
  if (angleDeg(a.plane.normal, b.plane.normal) >= kMaxAngleDeg) return false;
  const double d = offsetMm(a, b);
  return std::isfinite(d) && d <= coincidenceTolerance(a, b);
}

std::vector<CoincidentGroup> coincidentGroups(const std::vector<CuttingPlane>& planes) {
  std::vector<CoincidentGroup> groups;
  std::vector<char> grouped(planes.size(), 0);
  for (std::size_t i = 0; i < planes.size(); ++i) {
    if (grouped[i]) continue;
    CoincidentGroup g;
    g.members.push_back(i);
    for (std::size_t j = i + 1; j < planes.size(); ++j) {
      if (grouped[j] || !planesCoincide(planes[i], planes[j])) continue;
      grouped[j] = 1;
      g.members.push_back(j);
      g.max_offset_mm = std::max(g.max_offset_mm, offsetMm(planes[i], planes[j]));
      g.max_angle_deg = std::max(g.max_angle_deg, angleDeg(planes[i].plane.normal, planes[j].plane.normal));
    }
    if (g.members.size() > 1) groups.push_back(std::move(g));
  }
  return groups;
}

}  // namespace xsect

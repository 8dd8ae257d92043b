// The geometric fuzzer of issue 15: random plane sets with snapped (degenerate) angles and
// offsets, repeated and nearly coincident planes, and random sections (disks, squares, slivers,
// specks, collinear and self-intersecting rings, holes), written as a .csl file with a run
// configuration. Every configuration must give exit 0 with a watertight mesh, or exit 2 with a
// message naming the file: never a crash, a hang or exit 1.
#pragma once

#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace xsect::test {

struct FuzzCase {
  std::string csl;     ///< the .csl text
  std::string config;  ///< config.yaml text (input: csl: input.csl)
  std::string what;    ///< a one-line description, for failure messages
};

/// The configuration drawn from `seed` (deterministic).
inline FuzzCase geometricFuzzCase(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const auto pick = [&](int n) { return int(rng() % std::uint64_t(n)); };
  std::ostringstream what;
  // Units: tiny, unit, millimetre-like, and far from the origin.
  // (Data too small for OpenVDB's transforms or too far for single-precision meshes are refused
  // with exit 2: one configuration in twenty tries each.)
  const int unit = pick(20);
  const double scale = unit == 0 ? 1e-5 : std::vector<double>{1e-3, 1.0, 25.0}[std::size_t(pick(3))];
  const Eigen::Vector3d shift = unit == 1   ? Eigen::Vector3d(1e6, -2e6, 5e5)
                                : pick(4) == 0 ? Eigen::Vector3d(1e3 * scale * Eigen::Vector3d(1, -2, 0.5))
                                               : Eigen::Vector3d::Zero();
  what << "seed " << seed << " scale " << scale << " shift " << shift.transpose();
  const std::vector<Eigen::Vector3d> snapped = {
      {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, -1, 0}, {-1, 0, 0}};
  struct P {
    Eigen::Vector3d n;
    double offset;
    std::vector<std::vector<Eigen::Vector2d>> outers, holes;
  };
  std::vector<P> planes;
  const int count = 1 + pick(10);
  for (int k = 0; k < count; ++k) {
    P p;
    const int kind = planes.empty() ? 1 + pick(2) : pick(8);
    if (kind == 0) {  // a repeat of an earlier plane, exactly or nearly
      p = planes[std::size_t(pick(int(planes.size())))];
      const int how = pick(3);
      if (how == 1) p.offset += 1e-9;
      if (how == 2) p.n = (p.n + Eigen::Vector3d(1e-7, -1e-7, 1e-7)).normalized();
      planes.push_back(p);
      continue;
    }
    p.n = kind <= 5 ? snapped[std::size_t(pick(int(snapped.size())))].normalized()
                    : Eigen::Vector3d(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized();
    p.offset = 0.5 * (pick(9) - 4);  // snapped: planes through each other's lines and vertices
    const int sections = pick(4);
    for (int s = 0; s < sections; ++s) {
      const Eigen::Vector2d c(0.5 * (pick(7) - 3), 0.5 * (pick(7) - 3));
      std::vector<Eigen::Vector2d> ring;
      const int shape = pick(16);
      if (shape <= 2 || shape >= 9) {  // disk, 3 to 40 vertices
        const double r = 0.2 + 2 * u(rng);
        const int n = 3 + pick(38);
        for (int v = 0; v < n; ++v)
          ring.push_back(c + r * Eigen::Vector2d(std::cos(2 * M_PI * v / n), std::sin(2 * M_PI * v / n)));
        if (pick(3) == 0) {  // a hole
          std::vector<Eigen::Vector2d> hole;
          for (int v = n - 1; v >= 0; --v)
            hole.push_back(c + 0.4 * r * Eigen::Vector2d(std::cos(2 * M_PI * v / n), std::sin(2 * M_PI * v / n)));
          p.holes.push_back(hole);
        }
      } else if (shape == 3) {  // square on the snapped lattice
        ring = {c, c + Eigen::Vector2d(1, 0), c + Eigen::Vector2d(1, 1), c + Eigen::Vector2d(0, 1)};
      } else if (shape == 4) {  // sliver
        const double w = std::pow(10.0, -1 - 5 * u(rng));
        ring = {c, c + Eigen::Vector2d(2, 0), c + Eigen::Vector2d(2, w), c + Eigen::Vector2d(0, w)};
      } else if (shape == 5) {  // speck
        const double r = std::pow(10.0, -3 - 4 * u(rng));
        ring = {c, c + Eigen::Vector2d(r, 0), c + Eigen::Vector2d(0, r)};
      } else if (shape == 6) {  // collinear: zero area
        ring = {c, c + Eigen::Vector2d(1, 1), c + Eigen::Vector2d(2, 2)};
      } else if (shape == 7) {  // self-intersecting bow tie
        ring = {c, c + Eigen::Vector2d(1, 1), c + Eigen::Vector2d(1, 0), c + Eigen::Vector2d(0, 1)};
      } else {  // repeated vertices
        ring = {c, c, c + Eigen::Vector2d(1, 0), c + Eigen::Vector2d(1, 0), c + Eigen::Vector2d(0, 1)};
      }
      p.outers.push_back(ring);
    }
    planes.push_back(p);
  }
  std::ostringstream csl;
  csl.precision(17);
  csl << "CSLC\n" << planes.size() << " 1\n";
  for (std::size_t k = 0; k < planes.size(); ++k) {
    const P& p = planes[k];
    const Eigen::Vector3d n = p.n, e1 = n.unitOrthogonal(), e2 = n.cross(e1);
    const Eigen::Vector3d origin = scale * p.offset * n + shift;
    std::vector<Eigen::Vector3d> pts;
    std::ostringstream comps;
    int rings = 0;
    const auto add = [&](const std::vector<Eigen::Vector2d>& ring, bool hole) {
      comps << ring.size() << (hole ? "h" : "") << " 1";
      for (const auto& q : ring) {
        comps << " " << pts.size();
        pts.push_back(origin + scale * (q.x() * e1 + q.y() * e2));
      }
      comps << "\n";
      ++rings;
    };
    for (const auto& r : p.outers) add(r, false);
    for (const auto& r : p.holes) add(r, true);
    csl << "\n" << k + 1 << " " << pts.size() << " " << rings << " " << n.x() << " " << n.y() << " " << n.z() << " "
        << -n.dot(origin) << "\n\n";
    for (const auto& q : pts) csl << q.x() << " " << q.y() << " " << q.z() << "\n";
    csl << comps.str();
  }
  const char* methods[] = {"nearest_plane", "section_voronoi"};
  const char* smoothing[] = {"none", "none", "none", "none", "shepard", "level_set"};
  const std::string method = methods[pick(2)], smooth = smoothing[pick(6)];
  what << " planes " << planes.size() << " method " << method << " smoothing " << smooth;
  FuzzCase f;
  f.csl = csl.str();
  f.config = "input:\n  csl: input.csl\nreconstruction:\n  method: " + method +
             "\n  voxel_budget: 30000\nsmoothing:\n  method: " + smooth + "\noutput:\n  dir: out\n";
  f.what = what.str();
  return f;
}

}  // namespace xsect::test

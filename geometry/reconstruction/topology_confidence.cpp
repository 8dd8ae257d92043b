// How much to trust a solid's topology (see topology_confidence.h).
#include "geometry/reconstruction/topology_confidence.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "geometry/core/ball_morphology.h"
#include "geometry/core/solid_box.h"

namespace xsect {
namespace {

int changes(int now, int closed, int opened) { return std::abs(now - closed) + std::abs(now - opened); }

ConfidenceLevel levelOf(int in_doubt_1, int in_doubt_2) {
  return in_doubt_1 > 0 ? ConfidenceLevel::low : in_doubt_2 > 0 ? ConfidenceLevel::medium : ConfidenceLevel::high;
}

std::string number(double v) {
  std::ostringstream s;
  s.precision(v < 10 ? 2 : 3);
  s << v;
  return s.str();
}

}  // namespace

TopologyConfidence topologyConfidence(const std::vector<std::uint8_t>& inside, const GridSpec& grid,
                                      const Betti& betti, double scale_mm) {
  TopologyConfidence c;
  c.betti = betti;
  c.voxel_mm = grid.voxel;
  const double scale = std::max(2.0, std::isfinite(scale_mm) ? scale_mm / grid.voxel : 2.0);
  // Empty voxels kept around the solid, so that the closing means what it means on an unbounded grid.
  const SolidBox cropped = solidBox(inside, grid, int(std::ceil(scale)) + 1);
  const GridSpec& box = cropped.grid;
  const std::vector<std::uint8_t> solid = intoBox(inside, grid, cropped);
  c.voxels = box.count();
  const char* names[3] = {"component", "tunnel", "cavity"};
  for (int b = 0; b < 3; ++b) {
    c.kinds[std::size_t(b)].kind = names[b];
    c.kinds[std::size_t(b)].count = b == 0 ? std::max(betti[0] - 1, 0) : betti[std::size_t(b)];
  }
  if (solid.empty()) return c;
  c.probes[0].radius_voxels = 1.0;
  c.probes[1].radius_voxels = scale;
  const BallMorphology morphology(solid, box, scale);
  // The probe at one voxel first (no distance transform); the data's scale only when it leaves
  // the level open: a result in doubt at one voxel is low whatever the larger ball says.
  const auto probe = [&](TopologyProbe& p) {
    tbb::parallel_for(0, 2, [&](int t) {
      if (t == 0) p.closed = voxelBetti(morphology.closing(p.radius_voxels), box);
      else p.opened = voxelBetti(morphology.opening(p.radius_voxels), box);
    });
  };
  probe(c.probes[0]);
  int at1 = 0;
  for (std::size_t q = 0; q < 3; ++q) at1 += changes(betti[q], c.probes[0].closed[q], c.probes[0].opened[q]);
  c.scale_probed = at1 == 0;
  if (c.scale_probed) probe(c.probes[1]);
  for (int b = 0; b < 3; ++b) {
    FeatureDoubt& f = c.kinds[std::size_t(b)];
    const std::size_t q = std::size_t(b);
    f.in_doubt_1 = changes(betti[q], c.probes[0].closed[q], c.probes[0].opened[q]);
    if (c.scale_probed)
      f.in_doubt_2 = std::max(changes(betti[q], c.probes[1].closed[q], c.probes[1].opened[q]) - f.in_doubt_1, 0);
    f.level = levelOf(f.in_doubt_1, f.in_doubt_2);
  }
  int at2 = 0;
  for (const FeatureDoubt& f : c.kinds) at2 += f.in_doubt_2;
  c.level = levelOf(at1, at2);
  return c;
}

std::string confidenceText(const TopologyConfidence& c) {
  std::string text = std::string(nameOf(kConfidenceLevels, c.level));
  const double scale_mm = c.probes[1].radius_voxels * c.voxel_mm;
  if (c.level == ConfidenceLevel::high)
    return text + ": no feature made or unmade by closing or opening " + number(scale_mm) +
           " mm (half the largest cell height, at least 2 voxels)";
  const bool voxel = c.level == ConfidenceLevel::low;
  std::string parts;
  for (const FeatureDoubt& f : c.kinds) {
    const int n = voxel ? f.in_doubt_1 : f.in_doubt_2;
    if (n == 0) continue;
    const std::string kind = f.kind;
    const std::string plural = kind == "cavity" ? "cavities" : kind + "s";
    parts += (parts.empty() ? "" : ", ") + std::to_string(n) + " " + (n > 1 ? plural : kind);
  }
  return text + ": " + parts + " made or unmade by closing or opening " +
         (voxel ? "1 voxel (" + number(c.voxel_mm) + " mm)" : number(scale_mm) + " mm (half the largest cell height)");
}

}  // namespace xsect

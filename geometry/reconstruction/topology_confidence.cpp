// How much to trust a solid's topology (see topology_confidence.h).
#include "geometry/reconstruction/topology_confidence.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "geometry/core/block_ball_morphology.h"

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

TopologyConfidence topologyConfidence(const BlockGrid<std::uint8_t>& inside, const Betti& betti, double scale_mm) {
  TopologyConfidence c;
  c.betti = betti;
  const GridSpec& grid = inside.grid();
  c.voxel_mm = grid.voxel;
  const double scale = std::max(2.0, std::isfinite(scale_mm) ? scale_mm / grid.voxel : 2.0);
  const char* names[3] = {"component", "tunnel", "cavity"};
  for (int b = 0; b < 3; ++b) {
    c.kinds[std::size_t(b)].kind = names[b];
    c.kinds[std::size_t(b)].count = b == 0 ? std::max(betti[0] - 1, 0) : betti[std::size_t(b)];
  }
  // The solid's bounding box grown by the margin the closing needs (the voxels a dense probe would
  // have held; report.json's voxels_probed).
  const int margin = int(std::ceil(scale)) + 1;
  const std::optional<VoxelBox> box = setBoundingBox(inside);
  if (!box) return c;
  c.voxels = 1;
  for (std::size_t a = 0; a < 3; ++a) c.voxels *= std::int64_t(box->hi[a] - box->lo[a] + 1 + 2 * margin);
  // Empty voxels around the solid, so that the closing means what it means on an unbounded grid.
  const BlockGrid<std::uint8_t> solid =
      paddedBlockGrid(inside, (margin + BlockGrid<std::uint8_t>::kSide - 1) / BlockGrid<std::uint8_t>::kSide);
  c.probes[0].radius_voxels = 1.0;
  c.probes[1].radius_voxels = scale;
  // The probe at one voxel first; the data's scale only when it leaves the level open: a result in
  // doubt at one voxel is low whatever the larger ball says. The closing and the opening one after
  // the other (each window's loop is parallel): the run's peak memory holds one of them at a time.
  const auto probe = [&](TopologyProbe& p) {
    p.closed = voxelBetti(blockBallClosing(solid, p.radius_voxels));
    p.opened = voxelBetti(blockBallOpening(solid, p.radius_voxels));
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

TopologyConfidence topologyConfidence(const std::vector<std::uint8_t>& inside, const GridSpec& grid,
                                      const Betti& betti, double scale_mm) {
  return topologyConfidence(blockValues(inside, grid), betti, scale_mm);
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

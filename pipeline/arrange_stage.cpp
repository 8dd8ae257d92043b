// Stage 4: arrangement and graphs (see arrange_stage.h).
#include "pipeline/arrange_stage.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>

#include "geometry/core/polygon.h"
#include "geometry/delaunay/branching_diagram.h"
#include "io/input_error.h"

namespace xsect {

double arrangementSpacing(double voxel_mm, const std::vector<CuttingPlane>& planes, std::size_t realPlanes) {
  double area = 0;
  for (std::size_t p = 0; p < realPlanes; ++p)
    for (const auto& s : planes[p].sections) area += sectionArea(s);
  // Lattice of section points: the voxel size, coarser when it would exceed 250 000 points.
  return std::max(voxel_mm, std::sqrt(area / 250000.0));
}

int edgesMissing(const std::vector<GraphEdge>& sub, const std::vector<GraphEdge>& super) {
  int missing = 0;
  for (const GraphEdge& e : sub) missing += !std::binary_search(super.begin(), super.end(), e);
  return missing;
}

ArrangeStage arrangeStage(const RunConfig& c, const SectionScene& scene) {
  ArrangeStage a;
  a.arrangement = arrangeSections(scene.planes, arrangementSpacing(scene.params.voxel_mm, scene.planes, scene.real_planes));
  const ReconstructionMethod method = scene.params.method;
  if (method == ReconstructionMethod::delaunay && a.arrangement.pencil_crossings > 0) {
    // Method 3 glues cells along sub-sections whose corners lie on two planes at a time (general
    // position, ch. 3 §2.4); where three planes of a pencil meet on a contour, the cells around
    // the common line are decided by rounding (the fan of configs/phantoms/ellipsoid-fan.yaml
    // made 614 cells and an open mesh). Methods 1 and 2 need no such position.
    std::array<int, 3> p = a.arrangement.pencil_planes;
    std::sort(p.begin(), p.end());
    throw InputError(c.path, "reconstruction.method",
                     "delaunay (method 3) needs planes in general position along the sections, but " +
                         std::to_string(a.arrangement.pencil_crossings) +
                         " contour crossings lie on three or more planes through one line (a fan of planes; "
                         "e.g. planes " + std::to_string(p[0]) + ", " + std::to_string(p[1]) + " and " +
                         std::to_string(p[2]) + "): use nearest_plane or section_voronoi for these slices");
  }
  SectionVoronoiParams vp;
  vp.slab_mm = scene.slab_mm();
  a.with_g_prime = method == ReconstructionMethod::section_voronoi || method == ReconstructionMethod::delaunay;
  // Method 3's branching diagram needs the arrangement only: it is computed beside the graphs
  // (each is parallel inside but has serial stretches; multiaxial-3x40: 0.35 s and 0.80 s one
  // after the other).
  std::optional<BranchingDiagram> diagram;
  tbb::parallel_invoke([&] { a.graphs = connectivityGraphs(scene, a.arrangement, vp, a.with_g_prime); },
                       [&] {
                         if (method == ReconstructionMethod::delaunay) diagram = branchingDiagram(scene, a.arrangement);
                       });
  if (a.with_g_prime) {
    a.g_not_in_g_prime = edgesMissing(a.graphs.g, a.graphs.g_prime);
    a.g_in_g_prime = a.g_not_in_g_prime == 0;
  }
  if (method == ReconstructionMethod::delaunay) {
    // Method 3 (ch. 3 §1): the branching points its Delaunay triangulations add, and G''.
    BranchingDiagram& d = *diagram;
    a.branching = std::move(d.points);
    a.branching_rays = d.rays;
    a.branching_labelled = d.labelled;
    a.graphs.g_double_prime = std::move(d.g_double_prime);
    std::vector<GraphEdge>& g2 = a.graphs.g_double_prime;  // sorted and unique, as G and G' are
    std::sort(g2.begin(), g2.end());
    g2.erase(std::unique(g2.begin(), g2.end()), g2.end());
    a.with_g_double_prime = true;
    a.g_prime_not_in_g_double_prime = edgesMissing(a.graphs.g_prime, a.graphs.g_double_prime);
  }
  return a;
}

}  // namespace xsect

// The confidence in the run's topology (see confidence_stage.h).
#include "pipeline/confidence_stage.h"

#include <algorithm>
#include <cmath>

#include "geometry/core/block_grid.h"

namespace xsect {

double dataScaleMm(const SamplingStage& sampling) {
  double height = 0;
  for (const CellSampling& c : sampling.diagnosis.cells)
    if (holdsSections(c) && std::isfinite(c.height_hi_mm)) height = std::max(height, c.height_hi_mm);
  return 0.5 * height;
}

ConfidenceStage confidenceStage(const ReconstructStage& reconstruction, const SmoothStage* smooth, const Betti& betti,
                                const SamplingStage& sampling) {
  ConfidenceStage out;
  const double scale = dataScaleMm(sampling);
  if (smooth) {
    std::vector<std::uint8_t> in(smooth->field.values.size());
    for (std::size_t q = 0; q < in.size(); ++q) in[q] = smooth->field.values[q] < 0;
    out.confidence = topologyConfidence(in, smooth->field.grid, betti, scale);
  } else {
    out.confidence = topologyConfidence(reconstruction.solid.inside, betti, scale);
  }
  return out;
}

}  // namespace xsect

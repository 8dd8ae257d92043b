// The method interface's defaults and the choice of a method (see method.h).
#include "pipeline/methods/method.h"

#include "pipeline/methods/delaunay_method.h"
#include "pipeline/methods/sampled_methods.h"

namespace xsect {

void Method::requireArrangement(const RunConfig&, const SectionArrangement&) const {}

const char* Method::progressUnit() const { return "blocks"; }

ReconstructionMethod Method::samplingConditions() const { return id(); }

const std::vector<GraphEdge>* Method::joinsRealised(const ReconstructStage&) const { return nullptr; }

void Method::addToReport(const RunResults&, nlohmann::ordered_json&) const {}

std::unique_ptr<const Method> methodFor(ReconstructionMethod method) {
  switch (method) {
    case ReconstructionMethod::nearest_plane: return std::make_unique<NearestPlaneMethod>();
    case ReconstructionMethod::section_voronoi: return std::make_unique<SectionVoronoiMethod>();
    case ReconstructionMethod::delaunay: return std::make_unique<DelaunayMethod>();
  }
  return std::make_unique<NearestPlaneMethod>();
}

}  // namespace xsect

// Labels and per-label sections of a run (see material_sections.h).
#include "pipeline/material_sections.h"

#include <algorithm>

namespace xsect {

bool anyLabelled(const RunInputs& in) {
  return std::any_of(in.labelled.begin(), in.labelled.end(), [](const auto& l) { return !l.empty(); });
}

std::vector<std::uint16_t> materialLabels(const RunInputs& in) {
  const bool labelled = anyLabelled(in);
  std::vector<std::uint16_t> values;
  for (std::size_t p = 0; p < in.planes.size(); ++p) {
    if (labelled && p >= in.labelled.size()) continue;
    for (const auto& s : labelled ? in.labelled[p] : in.planes[p].sections) values.push_back(std::uint16_t(s.label));
  }
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end()), values.end());
  return values;
}

std::vector<CuttingPlane> materialPlanes(const RunInputs& in, std::uint16_t label) {
  const bool labelled = anyLabelled(in);
  std::vector<CuttingPlane> planes = in.planes;
  for (std::size_t p = 0; p < planes.size(); ++p) {
    const std::vector<Section>* from =
        labelled ? (p < in.labelled.size() ? &in.labelled[p] : nullptr) : &in.planes[p].sections;
    planes[p].sections.clear();
    if (!from) continue;
    for (const Section& s : *from)
      if (s.label == label) planes[p].sections.push_back(s);
  }
  return planes;
}

}  // namespace xsect

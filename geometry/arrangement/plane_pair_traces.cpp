// Pairs of planes and their traces (see plane_pair_traces.h).
#include "geometry/arrangement/plane_pair_traces.h"

#include <tbb/parallel_for.h>

#include <atomic>
#include <cmath>
#include <optional>

namespace xsect {

PlanePairSearch planePairTraces(const std::vector<CuttingPlane>& planes, double min_angle_deg,
                                bool keep_unmeasured, const std::function<void(std::int64_t, std::int64_t)>& progress) {
  const int n = int(planes.size());
  struct Row {
    std::vector<PlanePairTraces> pairs, unmeasured;
    int near_parallel = 0, empty = 0;
  };
  std::vector<Row> rows(std::size_t(std::max(n, 0)));
  const auto searchRow = [&](int a) {
    if (planes[a].is_virtual) return;
    Row& row = rows[std::size_t(a)];
    for (int b = a + 1; b < n; ++b) {
      if (planes[b].is_virtual) continue;
      const auto line = commonLine(planes[a].plane, planes[b].plane);
      if (!line) continue;
      const PlaneLine la = lineInPlane(planes[a].plane, *line), lb = lineInPlane(planes[b].plane, *line);
      // The image rectangles first (the fields of view lie inside them): most pairs of a sweep
      // end there.
      if (intersectTraces(imageTrace(planes[a], la), imageTrace(planes[b], lb)).empty()) continue;
      const Trace common = intersectTraces(observedTrace(planes[a], la), observedTrace(planes[b], lb));
      if (common.empty()) continue;
      const bool nearParallel = line->angle_deg < min_angle_deg;
      if (nearParallel && !keep_unmeasured) {
        ++row.near_parallel;
        continue;
      }
      PlanePairTraces p;
      p.a = a;
      p.b = b;
      p.line = *line;
      p.common = common;
      p.trace_a = sectionsTrace(planes[a].sections, la);
      p.trace_b = sectionsTrace(planes[b].sections, lb);
      const bool empty = intersectTraces(uniteTraces(p.trace_a, p.trace_b), common).empty();
      if (nearParallel || empty) {
        (nearParallel ? row.near_parallel : row.empty) += 1;
        p.disagreement = traceDisagreement(p.trace_a, p.trace_b, common);
        row.unmeasured.push_back(std::move(p));
        continue;
      }
      p.disagreement = traceDisagreement(p.trace_a, p.trace_b, common);
      row.pairs.push_back(std::move(p));
    }
  };
  const std::int64_t pairs = std::int64_t(n) * std::max(n - 1, 0) / 2;
  std::atomic<std::int64_t> examined{0};
  tbb::parallel_for(0, n, [&](int a) {
    searchRow(a);
    if (progress) progress(examined.fetch_add(n - 1 - a, std::memory_order_relaxed) + (n - 1 - a), pairs);
  });
  PlanePairSearch s;
  for (Row& r : rows) {
    s.pairs.insert(s.pairs.end(), std::make_move_iterator(r.pairs.begin()),
                   std::make_move_iterator(r.pairs.end()));
    s.unmeasured.insert(s.unmeasured.end(), std::make_move_iterator(r.unmeasured.begin()),
                        std::make_move_iterator(r.unmeasured.end()));
    s.pairs_near_parallel += r.near_parallel;
    s.pairs_without_sections += r.empty;
  }
  return s;
}

std::vector<PlanePairTraces> retrace(const std::vector<PlanePairTraces>& pairs,
                                     const std::vector<CuttingPlane>& planes) {
  std::vector<PlanePairTraces> out = pairs;
  tbb::parallel_for(std::size_t(0), out.size(), [&](std::size_t k) {
    PlanePairTraces& p = out[k];
    p.trace_a = sectionsTrace(planes[std::size_t(p.a)].sections, lineInPlane(planes[std::size_t(p.a)].plane, p.line));
    p.trace_b = sectionsTrace(planes[std::size_t(p.b)].sections, lineInPlane(planes[std::size_t(p.b)].plane, p.line));
    p.disagreement = traceDisagreement(p.trace_a, p.trace_b, p.common);
  });
  return out;
}

std::vector<PlanePairTraces> commonRegions(const std::vector<PlanePairTraces>& pairs,
                                           const std::vector<CuttingPlane>& planes) {
  std::vector<std::optional<PlanePairTraces>> moved(pairs.size());
  tbb::parallel_for(std::size_t(0), pairs.size(), [&](std::size_t k) {
    const CuttingPlane &a = planes[std::size_t(pairs[k].a)], &b = planes[std::size_t(pairs[k].b)];
    const auto line = commonLine(a.plane, b.plane);
    if (!line) return;
    const Trace common = intersectTraces(observedTrace(a, lineInPlane(a.plane, *line)),
                                         observedTrace(b, lineInPlane(b.plane, *line)));
    if (common.empty()) return;
    PlanePairTraces p;
    p.a = pairs[k].a;
    p.b = pairs[k].b;
    p.line = *line;
    p.common = common;
    moved[k] = std::move(p);
  });
  std::vector<PlanePairTraces> out;
  for (auto& m : moved)
    if (m) out.push_back(std::move(*m));
  return out;
}

}  // namespace xsect

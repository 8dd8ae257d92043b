// Consensus of coincident observations (see coincident_consensus.h).
#include "segmentation/coincident_consensus.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <opencv2/core.hpp>

#include "geometry/polygon.h"
#include "geometry/section_distance_field.h"
#include "segmentation/iso_contours.h"

namespace xsect {
namespace {

constexpr double kBandSteps = 16.0;        // signed distances are exact within at least this many steps
constexpr double kMaxNodes = 4.0e6;        // the raster's step grows past this many nodes
constexpr double kStepsPerDiagonal = 1024; // raster step for contours given without pixels

/// Nodes origin + step * (i, j), i < nu, j < nv, in the first member's plane coordinates (mm).
struct Raster {
  Vec2 origin = Vec2::Zero();
  double step = 1.0;
  int nu = 0, nv = 0;
  Vec2 node(int i, int j) const { return origin + step * Vec2(i, j); }
  std::size_t count() const { return std::size_t(nu) * std::size_t(nv); }
};

/// A member's point in the first member's plane coordinates (through the world).
Vec2 toFirst(const CuttingPlane& first, const CuttingPlane& member, const Vec2& p) {
  return first.plane.toPlane(member.plane.toWorld(p));
}

std::vector<Section> sectionsInFirstFrame(const CuttingPlane& first, const CuttingPlane& member,
                                          const std::vector<Section>& sections) {
  std::vector<Section> out = sections;
  for (Section& s : out) {
    for (Vec2& p : s.outer) p = toFirst(first, member, p);
    for (Ring& h : s.holes)
      for (Vec2& p : h) p = toFirst(first, member, p);
  }
  return out;
}

/// Whether `member` observed the point q of the first member's plane.
bool observes(const CuttingPlane& first, const CuttingPlane& member, const Vec2& q) {
  if (member.observed_everywhere) return true;
  const Vec2 p = member.plane.toPlane(first.plane.toWorld(q));
  if (!member.extent.contains(p)) return false;
  if (member.field_of_view.empty()) return true;
  bool inside = false;  // even-odd over the field-of-view rings, as section_traces.cpp reads them
  for (const Ring& r : member.field_of_view) inside ^= ringContains(r, p);
  return inside;
}

/// Rings of {field > 0} as plane coordinates on the raster, split into sections.
std::vector<Section> sectionsOfField(const cv::Mat& field, const Raster& r, int label) {
  std::vector<Ring> outers, holes;
  for (Ring ring : isoContours(field)) {
    for (Vec2& p : ring) p = r.node(0, 0) + r.step * p;
    (signedArea(ring) > 0 ? outers : holes).push_back(std::move(ring));
  }
  std::vector<Section> sections = sectionsFromRings(std::move(outers), std::move(holes));
  for (Section& s : sections) s.label = label;
  return sections;
}

/// Up to 2000 of the vertices of the sections' contours, evenly spread.
std::vector<Vec2> someContourVertices(const std::vector<Section>& sections) {
  std::vector<Vec2> all;
  for (const Section& s : sections) {
    all.insert(all.end(), s.outer.begin(), s.outer.end());
    for (const Ring& h : s.holes) all.insert(all.end(), h.begin(), h.end());
  }
  const std::size_t every = all.size() / 2000 + 1;
  std::vector<Vec2> some;
  for (std::size_t k = 0; k < all.size(); k += every) some.push_back(all[k]);
  return some;
}

/// The largest distance from a contour vertex of one member to another member's contours, over
/// the members holding sections: how far apart the observations are (a symmetric Hausdorff
/// distance between contours, on up to 2000 vertices each).
double largestGap(const std::vector<std::vector<Section>>& members) {
  double gap = 0.0;
  for (std::size_t a = 0; a < members.size(); ++a) {
    if (members[a].empty()) continue;
    const std::vector<Vec2> vertices = someContourVertices(members[a]);
    for (std::size_t b = 0; b < members.size(); ++b)
      if (b != a && !members[b].empty())
        for (const Vec2& v : vertices) gap = std::max(gap, std::abs(signedDistanceToSections(members[b], v)));
  }
  return gap;
}

/// The median of the values (the mean of the two middle ones for an even count); `v` is reordered.
double median(std::vector<float>& v) {
  const std::size_t n = v.size(), h = n / 2;
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(h), v.end());
  if (n % 2) return v[h];
  const float upper = v[h];
  return 0.5 * (double(upper) + double(*std::max_element(v.begin(), v.begin() + std::ptrdiff_t(h))));
}

/// The consensus of the members' sections (already in the first member's frame) on the raster;
/// `observed[m][node]` says whether member m observed the node. Accumulates the disagreement.
/// `band`: signed distances are exact within it (more than the largest gap between members, so
/// that the median is decided by exact values wherever the members disagree).
std::vector<Section> consensusSections(const std::vector<std::vector<Section>>& members,
                                       const std::vector<std::vector<char>>& observed, const Raster& r,
                                       double band, int label, CoincidentConsensus* stats) {
  std::vector<SectionDistanceField> fields;
  for (const auto& sections : members) fields.push_back(sectionDistanceField(sections, r.step, band));
  cv::Mat field(r.nv, r.nu, CV_32F);
  double disagreeing = 0;
  std::vector<float> values(fields.size()), seenValues;
  for (int j = 0; j < r.nv; ++j)
    for (int i = 0; i < r.nu; ++i) {
      const std::size_t n = std::size_t(j) * std::size_t(r.nu) + std::size_t(i);
      const Vec2 q = r.node(i, j);
      seenValues.clear();
      int inside = 0;
      for (std::size_t m = 0; m < fields.size(); ++m) {
        if (!observed[m][n]) continue;
        values[m] = fields[m].sample(q.x(), q.y());
        seenValues.push_back(values[m]);
        inside += values[m] < 0;
      }
      const int seen = int(seenValues.size());
      const double consensus = seen ? median(seenValues) : band;
      field.at<float>(j, i) = float(-consensus);
      if (seen == int(fields.size()) && inside > 0 && inside < seen) disagreeing += 1;
      for (std::size_t m = 0; m < fields.size(); ++m)
        if (observed[m][n] && (values[m] < 0) != (consensus < 0))
          stats->max_correction_mm = std::max(stats->max_correction_mm, double(std::abs(values[m])));
    }
  stats->disagreement_area_mm2 += disagreeing * r.step * r.step;
  return sectionsOfField(field, r, label);
}

CuttingPlane mergeGroup(const std::vector<CuttingPlane>& planes, const CoincidentGroup& g,
                        std::vector<std::vector<Section>>* labelled, CoincidentConsensus* stats) {
  const CuttingPlane& first = planes[g.members.front()];
  // The members' sections and observed extents in the first member's frame.
  std::vector<std::vector<Section>> sections;
  Eigen::AlignedBox2d box, extentBox;
  double pixel = 0.0;
  bool everywhere = true;
  for (const std::size_t k : g.members) {
    const CuttingPlane& m = planes[k];
    sections.push_back(sectionsInFirstFrame(first, m, m.sections));
    for (const Section& s : sections.back()) box.extend(ringBounds(s.outer));
    if (!m.observed_everywhere)
      for (const Vec2& c : {m.extent.min, Vec2(m.extent.max.x(), m.extent.min.y()), m.extent.max,
                            Vec2(m.extent.min.x(), m.extent.max.y())})
        extentBox.extend(toFirst(first, m, c));
    everywhere = everywhere && m.observed_everywhere;
    if (m.pixel_mm > 0 && (pixel == 0.0 || m.pixel_mm < pixel)) pixel = m.pixel_mm;
  }
  CuttingPlane merged = first;
  merged.pixel_mm = pixel;
  merged.observed_everywhere = everywhere;
  if (!everywhere) merged.extent = {extentBox.min(), extentBox.max()};
  merged.field_of_view.clear();
  Eigen::AlignedBox2d all = box;
  if (!everywhere) all.extend(extentBox);
  if (all.isEmpty()) {  // nothing observed, no section: nothing to agree on
    merged.sections.clear();
    return merged;
  }
  const double diag = std::max(all.diagonal().norm(), 1e-300);
  Raster r;
  r.step = pixel > 0 ? pixel : diag / kStepsPerDiagonal;
  const double gap = std::min(largestGap(sections), diag);
  double band = std::max(kBandSteps * r.step, 1.5 * gap + 2 * r.step);
  const double margin = band + 2 * r.step;
  const Vec2 lo = all.min() - Vec2::Constant(margin), hi = all.max() + Vec2::Constant(margin);
  const double area = (hi - lo).prod();
  if (area / (r.step * r.step) > kMaxNodes) r.step = std::sqrt(area / kMaxNodes);
  r.origin = Vec2(std::floor(lo.x() / r.step) * r.step, std::floor(lo.y() / r.step) * r.step);
  r.nu = int(std::ceil((hi.x() - r.origin.x()) / r.step)) + 1;
  r.nv = int(std::ceil((hi.y() - r.origin.y()) / r.step)) + 1;
  band = std::max(band, kBandSteps * r.step);  // the step may have grown

  std::vector<std::vector<char>> observed(g.members.size(), std::vector<char>(r.count()));
  std::vector<char> observedAny(r.count(), 0);
  for (std::size_t m = 0; m < g.members.size(); ++m)
    for (int j = 0; j < r.nv; ++j)
      for (int i = 0; i < r.nu; ++i) {
        const std::size_t n = std::size_t(j) * std::size_t(r.nu) + std::size_t(i);
        observed[m][n] = observes(first, planes[g.members[m]], r.node(i, j));
        observedAny[n] |= observed[m][n];
      }
  const int label = first.sections.empty() ? 1 : first.sections.front().label;
  merged.sections = consensusSections(sections, observed, r, band, label, stats);
  if (labelled && !labelled->empty()) {
    std::set<int> labels;
    for (const std::size_t k : g.members)
      for (const Section& s : (*labelled)[k]) labels.insert(s.label);
    std::vector<Section> perLabel;
    CoincidentConsensus ignored;  // the disagreement is reported for the union of the labels
    for (const int L : labels) {
      std::vector<std::vector<Section>> ofLabel;
      for (const std::size_t k : g.members) {
        std::vector<Section> withL;
        for (const Section& s : (*labelled)[k])
          if (s.label == L) withL.push_back(s);
        ofLabel.push_back(sectionsInFirstFrame(first, planes[k], withL));
      }
      for (Section& s : consensusSections(ofLabel, observed, r, band, L, &ignored)) perLabel.push_back(std::move(s));
    }
    (*labelled)[g.members.front()] = std::move(perLabel);
  }
  // The merged plane's field of view: where any member observed, unless that is the whole rectangle.
  if (!everywhere) {
    bool whole = true;
    const Vec2 shrink = Vec2::Constant(0.5 * r.step);
    cv::Mat seen(r.nv, r.nu, CV_32F);
    for (int j = 0; j < r.nv; ++j)
      for (int i = 0; i < r.nu; ++i) {
        const std::size_t n = std::size_t(j) * std::size_t(r.nu) + std::size_t(i);
        seen.at<float>(j, i) = observedAny[n] ? 0.5f : -0.5f;
        const Vec2 q = r.node(i, j);
        if (!observedAny[n] && (q.array() > (extentBox.min() + shrink).array()).all() &&
            (q.array() < (extentBox.max() - shrink).array()).all())
          whole = false;
      }
    if (!whole)
      for (Ring ring : isoContours(seen)) {
        for (Vec2& p : ring) p = r.node(0, 0) + r.step * p;
        merged.field_of_view.push_back(std::move(ring));
      }
  }
  return merged;
}

}  // namespace

CoincidentMerge mergeCoincidentPlanes(std::vector<CuttingPlane> planes,
                                      std::vector<std::vector<Section>> labelled) {
  CoincidentMerge out;
  const std::vector<CoincidentGroup> groups = coincidentGroups(planes);
  std::vector<char> absorbed(planes.size(), 0);
  std::vector<CuttingPlane> mergedOf(planes.size());
  for (const CoincidentGroup& g : groups) {
    CoincidentConsensus c;
    c.group = g;
    for (const std::size_t k : g.members) c.slices.push_back(planes[k].slice);
    mergedOf[g.members.front()] = mergeGroup(planes, g, labelled.empty() ? nullptr : &labelled, &c);
    for (std::size_t m = 1; m < g.members.size(); ++m) absorbed[g.members[m]] = 1;
    out.consensus.push_back(std::move(c));
  }
  std::vector<char> isFirst(planes.size(), 0);
  for (const CoincidentGroup& g : groups) isFirst[g.members.front()] = 1;
  for (std::size_t i = 0; i < planes.size(); ++i) {
    if (absorbed[i]) continue;
    out.planes.push_back(isFirst[i] ? std::move(mergedOf[i]) : std::move(planes[i]));
    if (!labelled.empty()) out.labelled.push_back(std::move(labelled[i]));
  }
  return out;
}

}  // namespace xsect

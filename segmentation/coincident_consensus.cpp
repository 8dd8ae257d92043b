// Consensus of coincident observations (see coincident_consensus.h).
#include "segmentation/coincident_consensus.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "geometry/core/polygon.h"
#include "segmentation/iso_contours.h"
#include "segmentation/section_raster.h"

namespace xsect {
namespace {

constexpr double kMaxNodes = 4.0e6;         // the raster's step grows past this many nodes
constexpr double kMaxRegionNodes = 1.0e6;   // the raster of the merged observed region
constexpr double kStepsPerExtent = 1024.0;  // raster step for contours without pixels

enum class Reduce { median, least };

/// The median (the mean of the two middle values for an even count) or the least of the values;
/// `v` is reordered.
double reduce(std::vector<float>& v, Reduce how) {
  if (how == Reduce::least) return *std::min_element(v.begin(), v.end());
  const std::size_t n = v.size(), h = n / 2;
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(h), v.end());
  if (n % 2) return v[h];
  const float upper = v[h];
  return 0.5 * (double(upper) + double(*std::max_element(v.begin(), v.begin() + std::ptrdiff_t(h))));
}

/// The members holding sections: the voters (see the header).
std::vector<std::size_t> votersOf(const std::vector<std::vector<Section>>& sections) {
  std::vector<std::size_t> voters;
  for (std::size_t m = 0; m < sections.size(); ++m)
    if (!sections[m].empty()) voters.push_back(m);
  return voters;
}

/// The consensus field (positive inside, for isoContours) of the voters' sections (first frame; a
/// voter without sections here, e.g. without this label, votes outside everywhere). Accumulates the
/// disagreement where every voter observed.
cv::Mat consensusField(const std::vector<std::vector<Section>>& sections, const std::vector<std::size_t>& voters,
                       const std::vector<cv::Mat>& observed, const SectionRaster& r, Reduce how,
                       CoincidentConsensus* stats) {
  const float outside = float(kSectionRasterBandSteps * r.step);
  if (stats) stats->voting = int(voters.empty() ? sections.size() : voters.size());
  if (voters.empty()) return cv::Mat(r.nv, r.nu, CV_32F, cv::Scalar(-outside));
  std::vector<cv::Mat> d;
  for (const std::size_t m : voters) d.push_back(signedDistanceOnRaster(sections[m], r));
  cv::Mat field(r.nv, r.nu, CV_32F);
  std::vector<float> seen;
  double disagreeing = 0;
  for (int j = 0; j < r.nv; ++j)
    for (int i = 0; i < r.nu; ++i) {
      seen.clear();
      int inside = 0;
      for (std::size_t k = 0; k < voters.size(); ++k) {
        if (!observed[voters[k]].at<unsigned char>(j, i)) continue;
        const float v = d[k].at<float>(j, i);
        seen.push_back(v);
        inside += v < 0;
      }
      const bool all = seen.size() == voters.size();
      const double c = seen.empty() ? double(outside) : reduce(seen, how);
      field.at<float>(j, i) = float(-c);
      if (!stats) continue;
      if (all && inside > 0 && inside < int(voters.size())) disagreeing += 1;
      for (std::size_t k = 0; k < voters.size(); ++k) {
        const float v = d[k].at<float>(j, i);
        if (observed[voters[k]].at<unsigned char>(j, i) && (v < 0) != (c < 0))
          stats->max_correction_mm = std::max(stats->max_correction_mm, double(std::abs(v)));
      }
    }
  if (stats) stats->disagreement_area_mm2 += disagreeing * r.step * r.step;
  return field;
}

bool sameRing(const Ring& a, const Ring& b, double tol) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k)
    if ((a[k] - b[k]).norm() > tol) return false;
  return true;
}

bool sameSections(const std::vector<Section>& a, const std::vector<Section>& b, double tol) {
  if (a.size() != b.size()) return false;
  for (std::size_t s = 0; s < a.size(); ++s) {
    if (a[s].label != b[s].label || !sameRing(a[s].outer, b[s].outer, tol) || a[s].holes.size() != b[s].holes.size())
      return false;
    for (std::size_t h = 0; h < a[s].holes.size(); ++h)
      if (!sameRing(a[s].holes[h], b[s].holes[h], tol)) return false;
  }
  return true;
}

/// Whether every member holding sections holds the first such member's, within `tol`.
bool votersAgree(const std::vector<std::vector<Section>>& sections, double tol) {
  const std::vector<Section>* reference = nullptr;
  for (const auto& s : sections) {
    if (s.empty()) continue;
    if (!reference) reference = &s;
    else if (!sameSections(*reference, s, tol)) return false;
  }
  return true;
}

/// The region the merged plane observed: the first member's when every member observed the same
/// rectangle and field of view; otherwise the bounding rectangle of the extents, narrowed by the
/// union of the observed regions (traced on a raster of at most kMaxRegionNodes nodes).
void observedUnion(const std::vector<CuttingPlane>& planes, const CoincidentGroup& g, double tol,
                   CuttingPlane& merged) {
  const CuttingPlane& first = planes[g.members.front()];
  bool same = true;
  Eigen::AlignedBox2d box;
  double pixel = 0.0;
  for (const std::size_t k : g.members) {
    const CuttingPlane& m = planes[k];
    if (m.pixel_mm > 0 && (pixel == 0.0 || m.pixel_mm < pixel)) pixel = m.pixel_mm;
    if (!extentIsEmpty(m.extent))
      for (const Vec2& c : extentCorners(m.extent)) box.extend(inReferenceFrame(first, m, c));
    if (m.observed_everywhere != first.observed_everywhere ||
        extentIsEmpty(m.extent) != extentIsEmpty(first.extent) ||
        m.field_of_view.size() != first.field_of_view.size()) {
      same = false;
      continue;
    }
    for (int c = 0; c < 4; ++c)
      same = same && (inReferenceFrame(first, m, extentCorners(m.extent)[c]) - extentCorners(first.extent)[c]).norm() <= tol;
    for (std::size_t f = 0; f < m.field_of_view.size(); ++f)
      same = same && sameRing(ringInReferenceFrame(first, m, m.field_of_view[f]), first.field_of_view[f], tol);
  }
  if (same || first.observed_everywhere || box.isEmpty()) return;
  merged.extent = {box.min(), box.max()};
  merged.field_of_view.clear();
  const SectionRaster r = sectionRasterAround(box, std::max(pixel, box.diagonal().norm() / kStepsPerExtent), 1, kMaxRegionNodes);
  cv::Mat any(r.nv, r.nu, CV_8U, cv::Scalar(0));
  for (const std::size_t k : g.members) any |= observedMask(first, planes[k], r);
  cv::Mat field(r.nv, r.nu, CV_32F);
  bool whole = true;
  const Vec2 shrink = Vec2::Constant(0.5 * r.step);
  for (int j = 0; j < r.nv; ++j)
    for (int i = 0; i < r.nu; ++i) {
      const bool seen = any.at<unsigned char>(j, i) != 0;
      field.at<float>(j, i) = seen ? 0.5f : -0.5f;
      const Vec2 q = r.node(i, j);
      if (!seen && (q.array() > (box.min() + shrink).array()).all() && (q.array() < (box.max() - shrink).array()).all())
        whole = false;
    }
  if (whole) return;
  for (Ring ring : isoContours(field)) {
    for (Vec2& p : ring) p = r.node(0, 0) + r.step * p;
    merged.field_of_view.push_back(std::move(ring));
  }
}

CuttingPlane mergeGroup(const std::vector<CuttingPlane>& planes, const CoincidentGroup& g,
                        std::vector<std::vector<Section>>* labelled, CoincidentConsensus* stats) {
  const CuttingPlane& first = planes[g.members.front()];
  const Reduce how = first.observed_everywhere ? Reduce::least : Reduce::median;
  stats->rule = how == Reduce::least ? "union" : "median";
  std::vector<std::vector<Section>> sections;
  Eigen::AlignedBox2d box;
  double pixel = 0.0, tol = 0.0;
  for (const std::size_t k : g.members) {
    const CuttingPlane& m = planes[k];
    sections.push_back(sectionsInReferenceFrame(first, m, m.sections));
    for (const Section& s : sections.back()) box.extend(ringBounds(s.outer));
    if (m.pixel_mm > 0 && (pixel == 0.0 || m.pixel_mm < pixel)) pixel = m.pixel_mm;
    tol = std::max(tol, coincidenceTolerance(first, m));
  }
  CuttingPlane merged = first;
  merged.pixel_mm = pixel;
  observedUnion(planes, g, tol, merged);
  const bool anyLabels = labelled && std::any_of(g.members.begin(), g.members.end(),
                                                 [&](std::size_t k) { return !(*labelled)[k].empty(); });
  if (box.isEmpty()) {  // no member holds a section
    merged.sections.clear();
    stats->voting = int(g.members.size());
    return merged;
  }
  int voting = 0;
  for (const auto& s : sections) voting += !s.empty();
  if (votersAgree(sections, tol) && !anyLabels) {  // one contour set, seen again: kept as it is
    stats->voting = voting;
    stats->rule = "identical";
    merged.sections = *std::find_if(sections.begin(), sections.end(), [](const auto& s) { return !s.empty(); });
    return merged;
  }
  int layers = int(g.members.size());
  std::set<int> labels;
  if (anyLabels)
    for (const std::size_t k : g.members)
      for (const Section& s : (*labelled)[k]) labels.insert(s.label);
  layers += int(labels.size()) * int(g.members.size());
  const SectionRaster r = sectionRasterAround(box, pixel > 0 ? pixel : box.diagonal().norm() / kStepsPerExtent, layers, kMaxNodes);
  std::vector<cv::Mat> observed;
  for (const std::size_t k : g.members) observed.push_back(observedMask(first, planes[k], r));
  const int label = first.sections.empty() ? 1 : first.sections.front().label;
  const std::vector<std::size_t> voters = votersOf(sections);
  const cv::Mat unionField = consensusField(sections, voters, observed, r, how, stats);
  merged.sections = sectionsOfRasterRings(isoContours(unionField), r, label);
  if (anyLabels) {
    // Each label's consensus field f_L on the same raster. The labels are traced together so that
    // they tile the plane, from g_L = f_L + (U - max_M f_M), U the union's field: the same
    // boundaries between labels (g_L - g_M = f_L - f_M), and max_L g_L = U, so that the labels'
    // union is the plane's sections (iso_contours.h: labelIsoContours decides the background as
    // isoContours decides it on the largest field).
    std::vector<LabelField> fields;
    cv::Mat all(r.nv, r.nu, CV_32F, cv::Scalar(-1e30f));
    for (const int L : labels) {
      std::vector<std::vector<Section>> ofLabel;
      for (const std::size_t k : g.members) {
        std::vector<Section> withL;
        for (const Section& s : (*labelled)[k])
          if (s.label == L) withL.push_back(s);
        ofLabel.push_back(sectionsInReferenceFrame(first, planes[k], std::move(withL)));
      }
      // The union's voters vote on every label: one that saw the region as another label votes
      // against this one.
      LabelField f{L, cv::Rect(0, 0, r.nu, r.nv), consensusField(ofLabel, voters, observed, r, how, nullptr)};
      all = cv::max(all, f.field);
      fields.push_back(std::move(f));
    }
    const cv::Mat lift = unionField - all;
    for (LabelField& f : fields) f.field += lift;
    std::map<int, std::vector<Ring>> ringsOf;
    for (LabelRing& lr : labelIsoContours(cv::Size(r.nu, r.nv), fields, -1.0f))
      ringsOf[lr.label].push_back(std::move(lr.ring));
    std::vector<Section> perLabel;
    for (auto& [L, rings] : ringsOf)
      for (Section& s : sectionsOfRasterRings(std::move(rings), r, L)) perLabel.push_back(std::move(s));
    (*labelled)[g.members.front()] = std::move(perLabel);
  }
  if (merged.observed_everywhere) {  // a contour plane's extent is its sections' bounds
    Eigen::AlignedBox2d bounds;
    for (const Section& s : merged.sections) bounds.extend(ringBounds(s.outer));
    if (!bounds.isEmpty()) merged.extent = {bounds.min(), bounds.max()};
  }
  return merged;
}

}  // namespace

CoincidentMerge mergeCoincidentPlanes(std::vector<CuttingPlane> planes,
                                      std::vector<std::vector<Section>> labelled) {
  if (!labelled.empty() && labelled.size() != planes.size())
    throw std::invalid_argument("mergeCoincidentPlanes: one row of labelled sections per plane, or none");
  CoincidentMerge out;
  const std::vector<CoincidentGroup> groups = coincidentGroups(planes);
  std::vector<char> absorbed(planes.size(), 0), isFirst(planes.size(), 0);
  std::vector<CuttingPlane> mergedOf(planes.size());
  for (const CoincidentGroup& g : groups) {
    CoincidentConsensus c;
    c.group = g;
    for (const std::size_t k : g.members) c.slices.push_back(planes[k].slice);
    mergedOf[g.members.front()] = mergeGroup(planes, g, labelled.empty() ? nullptr : &labelled, &c);
    isFirst[g.members.front()] = 1;
    for (std::size_t m = 1; m < g.members.size(); ++m) absorbed[g.members[m]] = 1;
    out.consensus.push_back(std::move(c));
  }
  for (std::size_t i = 0; i < planes.size(); ++i) {
    if (absorbed[i]) continue;
    out.planes.push_back(isFirst[i] ? std::move(mergedOf[i]) : std::move(planes[i]));
    if (!labelled.empty()) out.labelled.push_back(std::move(labelled[i]));
  }
  return out;
}

}  // namespace xsect

// report.html's 3D view data (see view_data.h).
#include "report/run/view_data.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "geometry/meshing/mesh_decimation.h"
#include "io/base64.h"
#include "pipeline/json_values.h"

namespace xsect {

using json = nlohmann::ordered_json;

namespace {

static_assert(sizeof(float) == 4, "typed arrays are 32-bit floats");

template <typename T>
std::string base64Of(const std::vector<T>& values) {
  return base64(values.data(), values.size() * sizeof(T));
}

void pushPoint(std::vector<float>& out, const Vec3& p) {
  out.push_back(float(p.x()));
  out.push_back(float(p.y()));
  out.push_back(float(p.z()));
}

/// The label of the solid at a mesh vertex: that of the nearest of the 8 voxels around it that
/// holds one (0 when none does).
std::uint16_t labelNear(const BlockGrid<std::uint16_t>& labels, const Vec3& x) {
  const GridSpec& g = labels.grid();
  const Vec3 t = (x - g.origin) / g.voxel;
  const int i0 = int(std::floor(t.x())), j0 = int(std::floor(t.y())), k0 = int(std::floor(t.z()));
  double best = 1e300;
  std::uint16_t label = 0;
  for (int c = 0; c < 8; ++c) {
    const int i = i0 + (c & 1), j = j0 + ((c >> 1) & 1), k = k0 + ((c >> 2) & 1);
    if (i < 0 || j < 0 || k < 0 || i >= g.dims[0] || j >= g.dims[1] || k >= g.dims[2]) continue;
    const std::uint16_t l = labels.at(i, j, k);
    const double d = (Vec3(i, j, k) - t).squaredNorm();
    if (l != 0 && d < best) {
      best = d;
      label = l;
    }
  }
  return label;
}

json meshJson(const RunResults& r, const ViewBudget& budget, Vec3& lo, Vec3& hi) {
  const TriangleMesh& full = r.meshes.mesh;
  const TriangleMesh mesh = decimatedMesh(full, std::max<std::size_t>(4, budget.triangles));
  std::vector<float> positions;
  std::vector<std::uint8_t> verdict;
  std::vector<std::uint16_t> label;
  positions.reserve(mesh.vertices.size() * 3);
  for (const Eigen::Vector3f& v : mesh.vertices) {
    const Vec3 x = v.cast<double>();
    pushPoint(positions, x);
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
    const CellSampling* cell = samplingCellAt(r.sampling, x);
    verdict.push_back(std::uint8_t(cell ? cell->verdict : SamplingVerdict::undetermined));
    label.push_back(labelNear(r.meshes.voxel_label, x));
  }
  std::vector<std::uint32_t> indices;
  indices.reserve(mesh.triangles.size() * 3);
  for (const auto& t : mesh.triangles) indices.insert(indices.end(), t.begin(), t.end());
  return {{"triangles", full.triangles.size()},
          {"triangles_shown", mesh.triangles.size()},
          {"positions", base64Of(positions)},
          {"indices", base64Of(indices)},
          {"verdict", base64Of(verdict)},
          {"label", base64Of(label)}};
}

/// The observed rectangle of a plane in world coordinates (the sections' bounds, enlarged by a
/// tenth, for contours given on whole planes).
std::array<Vec3, 4> observedQuad(const CuttingPlane& p) {
  Vec2 a = p.extent.min, b = p.extent.max;
  if (p.observed_everywhere) {
    const Vec2 pad = 0.1 * (b - a) + Vec2::Constant(1e-6);
    a -= pad;
    b += pad;
  }
  return {p.plane.toWorld(a), p.plane.toWorld(Vec2(b.x(), a.y())), p.plane.toWorld(b), p.plane.toWorld(Vec2(a.x(), b.y()))};
}

}  // namespace

json viewDataJson(const RunResults& r, const ViewBudget& budget) {
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  json view;
  view["mesh"] = meshJson(r, budget, lo, hi);

  // The planes drawn: every one, or an even choice of them beyond the budget.
  const std::vector<CuttingPlane>& planes = r.inputs.planes;
  std::vector<std::size_t> drawn;
  for (std::size_t i = 0; i < planes.size(); ++i)
    if (!planes[i].is_virtual) drawn.push_back(i);
  const std::size_t total = drawn.size();
  if (drawn.size() > budget.slices) {
    std::vector<std::size_t> chosen;
    for (std::size_t q = 0; q < budget.slices; ++q) chosen.push_back(drawn[q * drawn.size() / budget.slices]);
    drawn = chosen;
  }
  const std::set<int> flaggedSlices(r.inputs.conformity.flagged_slices.begin(), r.inputs.conformity.flagged_slices.end());
  const auto sectionsOf = [&](std::size_t i) -> const std::vector<Section>& {
    return i < r.inputs.labelled.size() && !r.inputs.labelled[i].empty() ? r.inputs.labelled[i] : planes[i].sections;
  };
  std::size_t points = 0;
  for (const std::size_t i : drawn)
    for (const Section& s : sectionsOf(i)) {
      points += s.outer.size();
      for (const Ring& h : s.holes) points += h.size();
    }
  const std::size_t stride = std::max<std::size_t>(1, (points + budget.contour_points - 1) / std::max<std::size_t>(1, budget.contour_points));

  std::vector<float> quads, segments;
  std::vector<std::uint16_t> segmentLabels;
  json flagged = json::array();
  const auto addRing = [&](const Plane& plane, const Ring& ring, int label) {
    if (ring.size() < 2) return;
    std::vector<Vec3> kept;
    for (std::size_t v = 0; v < ring.size(); v += stride) kept.push_back(plane.toWorld(ring[v]));
    if (kept.size() < 3) kept = {plane.toWorld(ring.front()), plane.toWorld(ring[ring.size() / 2])};
    for (std::size_t v = 0; v < kept.size(); ++v) {
      pushPoint(segments, kept[v]);
      pushPoint(segments, kept[(v + 1) % kept.size()]);
      segmentLabels.push_back(std::uint16_t(std::clamp(label, 0, 65535)));
      lo = lo.cwiseMin(kept[v]);
      hi = hi.cwiseMax(kept[v]);
    }
  };
  // Per drawn plane, its rectangle (index into quads, or -1) and how many contour segments it
  // added: the page shows a few planes' rectangles and contours, or all.
  json planeQuads = json::array(), planeSegments = json::array();
  for (const std::size_t i : drawn) {
    const CuttingPlane& p = planes[i];
    const std::size_t segmentsBefore = segmentLabels.size();
    if (p.extent.max != p.extent.min || p.observed_everywhere) {
      if (flaggedSlices.count(p.slice)) flagged.push_back(quads.size() / 12);
      planeQuads.push_back(quads.size() / 12);
      for (const Vec3& c : observedQuad(p)) pushPoint(quads, c);
    } else {
      planeQuads.push_back(-1);
    }
    for (const Section& s : sectionsOf(i)) {
      addRing(p.plane, s.outer, s.label);
      for (const Ring& h : s.holes) addRing(p.plane, h, s.label);
    }
    planeSegments.push_back(segmentLabels.size() - segmentsBefore);
  }
  view["slices"] = {{"total", total}, {"shown", drawn.size()}, {"quads", base64Of(quads)}, {"flagged", flagged},
                    {"plane_quads", planeQuads}};
  view["contours"] = {{"segments", base64Of(segments)}, {"labels", base64Of(segmentLabels)}, {"stride", stride},
                      {"plane_segments", planeSegments}};
  json materials = json::array();
  for (const Material& m : r.meshes.materials) materials.push_back(m.label);
  if (materials.empty()) materials.push_back(1);
  view["materials"] = materials;
  if (!(lo.x() <= hi.x())) lo = hi = Vec3::Zero();  // nothing to show
  view["bounds"] = {vecJson(lo), vecJson(hi)};
  view["background"] = "#f4f5f7";
  return view;
}

}  // namespace xsect

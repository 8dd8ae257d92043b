// .csl reader (see csl_file.h).
#include "io/csl_file.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "geometry/core/polygon.h"
#include "io/contour_repair.h"
#include "geometry/core/ring_validity.h"
#include "io/contour_plane.h"
#include "io/input_error.h"
#include "io/text_file.h"
#include "io/text_tokens.h"

namespace xsect {


namespace {

/// A plane of the file as read: its equation, vertices and rings (of vertex indices until the
/// plane's frame exists), with their component numbers for messages.
struct RawPlane {
  Vec3 n;
  double d;
  std::vector<Vec3> pts;
  std::vector<Ring> outers, holes;
  std::vector<long> outerComponent, holeComponent;  // component numbers, for messages
  int line;
};

/// The planes of the file after its header, and the bounds of their vertices.
std::vector<RawPlane> readRawPlanes(Tokens& tk, const std::string& path, long nPlanes, Vec3& lo, Vec3& hi) {
  std::vector<RawPlane> raw(static_cast<std::size_t>(nPlanes));
  for (long p = 0; p < nPlanes; ++p) {
    const std::string key = "plane " + std::to_string(p + 1);
    RawPlane& r = raw[std::size_t(p)];
    r.line = tk.line();
    tk.integer(key + " index", 0);
    const long nv = tk.count(key + " vertex count", 0, 3);
    const long nc = tk.count(key + " component count", 0, 5);  // count, label, 3 indices
    for (int k = 0; k < 3; ++k) r.n[k] = tk.coordinate(key + " normal");
    r.d = tk.coordinate(key + " offset D");
    const double len = r.n.norm();
    if (len < 1e-12) throw InputError(path, key + " normal", "plane normal (A, B, C) is zero", r.line);
    r.n /= len;
    r.d /= len;
    r.pts.resize(nv);
    for (long v = 0; v < nv; ++v) {
      for (int k = 0; k < 3; ++k) r.pts[v][k] = tk.coordinate(key + " vertex " + std::to_string(v));
      lo = lo.cwiseMin(r.pts[v]);
      hi = hi.cwiseMax(r.pts[v]);
    }
    for (long c = 0; c < nc; ++c) {
      const std::string ckey = key + " component " + std::to_string(c);
      const auto& [head, hline] = tk.next(ckey);
      const bool hole = head.find('h') != std::string::npos;
      char* end = nullptr;
      const long count = std::strtol(head.c_str(), &end, 10);
      if (end == head.c_str() || count < 3 || (*end != '\0' && *end != 'h'))
        throw InputError(path, ckey, "expected a vertex count (optionally with h<parent>), got '" + head + "'", hline);
      tk.integer(ckey + " label", 0);
      if (count > long(tk.items.size() - tk.at))
        throw InputError(path, ckey, "vertex count " + std::to_string(count) + " exceeds what the file holds", hline);
      std::vector<long> idx(count);
      for (long q = 0; q < count; ++q) {
        idx[q] = tk.integer(ckey + " vertex index", 0);
        if (idx[q] >= nv)
          throw InputError(path, ckey, "vertex index " + std::to_string(idx[q]) + " out of range", hline);
      }
      (hole ? r.holeComponent : r.outerComponent).push_back(c);
      (hole ? r.holes : r.outers).emplace_back();
      Ring& ring = (hole ? r.holes : r.outers).back();
      for (long q : idx) ring.emplace_back(double(q), 0.0);  // keep indices until the frame exists
    }
  }
  if (tk.at != tk.items.size())
    throw InputError(path, "", "unexpected content after the last plane", tk.items[tk.at].second);
  return raw;
}

/// The rings of plane `cp` (of RawPlane r) in the plane's coordinates, cleaned: without area
/// (tolerance: 1e-12 of the data's extent squared) dropped, with a warning; crossing themselves:
/// refused without repair (even when their lobes net no area), else measured by the area of their
/// lobes (a symmetric figure eight nets zero).
std::vector<Ring> cleanRings(std::vector<Ring> rings, const std::vector<long>& components, const RawPlane& r,
                             const CuttingPlane& cp, double tinyArea, bool repair, const std::string& path,
                             std::vector<std::string>* warnings) {
  for (Ring& ring : rings)
    for (auto& q : ring) q = cp.plane.toPlane(r.pts[std::size_t(q.x())]);
  std::vector<Ring> kept;
  for (std::size_t k = 0; k < rings.size(); ++k) {
    Ring ring = withoutRepeatedVertices(rings[k]);
    const std::string where = cp.name + " component " + std::to_string(components[k]);
    const bool simple = ring.size() >= 3 && ringIsSimple(ring);
    if (!repair && ring.size() >= 3 && !simple)
      throw InputError(path, where,
                       "the contour crosses itself (a self-intersecting ring); input.repair_contours: true "
                       "makes it simple",
                       r.line);
    const double area = simple || !repair || ring.size() < 3 ? std::abs(signedArea(ring))
                                                              : repairedOrRefused({ring}, {}, path, where, r.line).area_after;
    if (ring.size() < 3 || area <= tinyArea) {
      if (warnings)
        warnings->push_back(path + ": " + where + " has no area (a point or a segment): dropped");
      continue;
    }
    kept.push_back(std::move(ring));
  }
  return kept;
}

}  // namespace

std::vector<CuttingPlane> readCslFile(const std::string& path, std::vector<std::string>* warnings, bool repair) {
  Tokens tk = readTokens(path);
  if (tk.next("header").first != "CSLC") throw InputError(path, "header", "expected 'CSLC'", 1);
  const long nPlanes = tk.count("plane count", 1, 7);  // index, counts, A B C D
  tk.integer("label count", 0);
  Vec3 lo = Vec3::Constant(1e300), hi = -lo;
  std::vector<RawPlane> raw = readRawPlanes(tk, path, nPlanes, lo, hi);
  if (tk.at != tk.items.size())
    throw InputError(path, "", "unexpected content after the last plane", tk.items[tk.at].second);

  std::vector<CuttingPlane> planes(nPlanes);
  const double tinyArea = 1e-12 * std::max((hi - lo).squaredNorm(), 1e-300);
  for (long p = 0; p < nPlanes; ++p) {
    RawPlane& r = raw[std::size_t(p)];
    CuttingPlane& cp = planes[p];
    cp.slice = int(p);
    cp.name = "plane " + std::to_string(p + 1);
    cp.plane = contourPlane(r.n, r.d, r.pts, lo, hi, path, cp.name, r.line);
    r.outers = cleanRings(std::move(r.outers), r.outerComponent, r, cp, tinyArea, repair, path, warnings);
    r.holes = cleanRings(std::move(r.holes), r.holeComponent, r, cp, tinyArea, repair, path, warnings);
    if (repair) {
      RingRepair fixed = repairedOrRefused(r.outers, r.holes, path, cp.name, r.line);
      if (fixed.changed && warnings) warnings->push_back(repairWarning(path + ": " + cp.name, fixed));
      r.outers = std::move(fixed.outers);
      r.holes = std::move(fixed.holes);
    }
    cp.sections = sectionsFromRings(std::move(r.outers), std::move(r.holes));
    cp.observed_everywhere = true;  // a contour file gives all of O ∩ P on each plane
    cp.extent = sectionBounds(cp.sections);
  }
  return planes;
}

void writeCslFile(const std::string& path, const std::vector<CuttingPlane>& planes) {
  std::ostringstream os;
  os.precision(17);
  os << "CSLC\n" << planes.size() << " 2\n\n";
  for (std::size_t p = 0; p < planes.size(); ++p) {
    const Plane& pl = planes[p].plane;
    std::vector<const Ring*> rings;
    std::vector<bool> hole;
    for (const Section& s : planes[p].sections) {
      rings.push_back(&s.outer);
      hole.push_back(false);
      for (const Ring& h : s.holes) rings.push_back(&h), hole.push_back(true);
    }
    std::size_t vertices = 0;
    for (const Ring* r : rings) vertices += r->size();
    os << p + 1 << " " << vertices << " " << rings.size() << " " << pl.normal.x() << " " << pl.normal.y() << " "
       << pl.normal.z() << " " << -pl.normal.dot(pl.origin) << "\n\n";
    for (const Ring* r : rings)
      for (const Vec2& q : *r) {
        const Vec3 x = pl.toWorld(q);
        os << x.x() << " " << x.y() << " " << x.z() << "\n";
      }
    os << "\n";
    std::size_t first = 0;
    for (std::size_t k = 0; k < rings.size(); ++k) {
      os << rings[k]->size() << (hole[k] ? "h" : "") << " 1";
      for (std::size_t q = 0; q < rings[k]->size(); ++q) os << " " << first + q;
      os << "\n";
      first += rings[k]->size();
    }
    os << "\n";
  }
  writeTextFile(path, os.str());
}

}  // namespace xsect

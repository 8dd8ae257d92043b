// @brief Baseline for the benchmark only (issue 4): CGAL's Poisson surface reconstruction run on
// the contour points of the very sections `xsect run` reconstructs from.
//
// Usage: xsect_poisson_baseline CONFIG.yaml --out MESH.ply [--json STATS.json] [--set key=value]...
//
// The run configuration is read as `xsect run` reads it (readRunConfig, --set overrides), the
// slices are segmented by the same code (sectionsFromSlices; or `input.csl` read directly): the
// input's contours as a user without xsect would hand them to Poisson, before xsect's conform stage
// (no pose smoothing, no enforcement). (Given freehand-400's smoothed poses instead, CGAL 5.5's
// Poisson meshes no surface at all: its surface mesher finds no facet and
// facets_in_complex_2_to_triangle_mesh dereferences an empty set; measured 2026-11-22.) Every
// section contour (outer rings and holes) is resampled by arc length at the configuration's
// `reconstruction.voxel_size_mm` (the step nearest to it that divides the ring's perimeter evenly):
// the points a user would hand to Poisson, about as dense as the voxel grid xsect evaluates, and
// independent of how finely the segmentation traced the contour. Each point carries the normal a
// user can know from a planar contour: in the plane, perpendicular to the contour, out of the solid.
// Rings are in the plane's (u, v) frame, outer rings counter-clockwise and holes clockwise
// (geometry/core/types.h), so an edge direction (dx, dy) has outward normal (dy, -dx); the normal at a
// vertex is the normalised sum of its two edges' normals, and a sample's normal interpolates its
// edge's two vertex normals linearly (a smooth normal field, not one that jumps at every pixel step
// of the traced contour).
//
// Poisson: the standard user path of CGAL 5.5, `compute_average_spacing` (6 neighbours) then
// `poisson_surface_reconstruction_delaunay` with its default criteria (angle 20 degrees, radius 30
// and distance 0.375 average spacings), Epick kernel, into a Surface_mesh. The mesh is turned
// outward (positive signed volume) and written with writeMesh. "poisson_s" times the average
// spacing and the reconstruction (implicit function, solver, surface meshing), not loading,
// segmentation or sampling, which have their own keys in the --json statistics.
//
// Exit codes: 0 success; 2 invalid input or configuration (InputError); 1 Poisson failed or any
// other failure.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/compute_average_spacing.h>
#include <CGAL/poisson_surface_reconstruction.h>
#include <CGAL/property_map.h>
#include <CGAL/Random.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "geometry/core/types.h"
#include "io/csl_file.h"
#include "io/input_error.h"
#include "io/mesh_io.h"
#include "io/run_config.h"
#include "io/slices_file.h"
#include "pipeline/load_sections.h"
#include "pipeline/voxel_size_choice.h"

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Vector = Kernel::Vector_3;
using PointWithNormal = std::pair<Point, Vector>;
using Mesh = CGAL::Surface_mesh<Point>;

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Samples one closed ring (plane coordinates, mm) every ~step mm by arc length, with in-plane
/// outward normals (see the file comment), appending world points and normals to out.
void sampleRing(const xsect::Ring& ring, const xsect::Plane& plane, double step,
                std::vector<PointWithNormal>& out) {
  const std::size_t n = ring.size();
  if (n < 3) return;
  std::vector<xsect::Vec2> edgeNormal(n);  // edge i: ring[i] -> ring[i+1]
  std::vector<double> edgeLength(n);
  double perimeter = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const xsect::Vec2 d = ring[(i + 1) % n] - ring[i];
    edgeLength[i] = d.norm();
    perimeter += edgeLength[i];
    edgeNormal[i] = edgeLength[i] > 0 ? xsect::Vec2(xsect::Vec2(d.y(), -d.x()) / edgeLength[i])
                                      : xsect::Vec2(xsect::Vec2::Zero());
  }
  if (!(perimeter > 0)) return;
  std::vector<xsect::Vec2> vertexNormal(n);
  for (std::size_t i = 0; i < n; ++i) {
    const xsect::Vec2 s = edgeNormal[(i + n - 1) % n] + edgeNormal[i];
    vertexNormal[i] = s.norm() > 1e-12 ? xsect::Vec2(s.normalized()) : edgeNormal[i];
  }
  const std::size_t count = std::max<std::size_t>(3, std::size_t(std::ceil(perimeter / step - 1e-9)));
  const double h = perimeter / double(count);
  std::size_t edge = 0;
  double edgeStart = 0;  // arc length at ring[edge]
  for (std::size_t k = 0; k < count; ++k) {
    const double s = h * double(k);
    while (edge + 1 < n && edgeStart + edgeLength[edge] <= s) edgeStart += edgeLength[edge++];
    const double t = edgeLength[edge] > 0 ? std::min(1.0, (s - edgeStart) / edgeLength[edge]) : 0.0;
    const xsect::Vec2 p = ring[edge] + t * (ring[(edge + 1) % n] - ring[edge]);
    xsect::Vec2 m = (1 - t) * vertexNormal[edge] + t * vertexNormal[(edge + 1) % n];
    if (m.norm() < 1e-12) m = edgeNormal[edge];
    if (m.norm() < 1e-12) continue;
    m.normalize();
    const xsect::Vec3 w = plane.toWorld(p);
    const xsect::Vec3 nw = m.x() * plane.u + m.y() * plane.v;
    out.emplace_back(Point(w.x(), w.y(), w.z()), Vector(nw.x(), nw.y(), nw.z()));
  }
}

struct Options {
  std::string config, out, json;
  std::vector<std::string> overrides;
};

Options parseArgs(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](const char* name) -> std::string {
      if (i + 1 >= argc) throw xsect::InputError("", name, "a value is required");
      return argv[++i];
    };
    if (a == "--out") o.out = value("--out");
    else if (a == "--json") o.json = value("--json");
    else if (a == "--set") o.overrides.push_back(value("--set"));
    else if (a == "--quiet" || a == "-q") continue;
    else if (!a.empty() && a[0] == '-') throw xsect::InputError("", a, "unknown option");
    else if (o.config.empty()) o.config = a;
    else throw xsect::InputError("", a, "unexpected argument (one CONFIG.yaml)");
  }
  if (o.config.empty()) throw xsect::InputError("", "CONFIG.yaml", "a run configuration is required");
  if (o.out.empty()) throw xsect::InputError("", "--out", "an output mesh path is required");
  return o;
}

/// Writes through a temporary beside the destination, renamed into place: complete or absent.
void writeMeshAtomically(const std::string& path, const xsect::TriangleMesh& mesh) {
  const auto dot = path.find_last_of('.');
  const std::string ext = dot == std::string::npos ? std::string() : path.substr(dot);
  const std::string tmp = path + ".partial" + ext;
  xsect::writeMesh(tmp, mesh);
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw std::runtime_error("cannot rename " + tmp + " to " + path);
  }
}

/// The Poisson surface as xsect's TriangleMesh (indices compacted), turned outward; its boundary
/// edges, whether it was turned, and 6 x its signed volume before.
xsect::TriangleMesh outwardMesh(const Mesh& mesh, std::size_t* boundaryEdges, bool* flipped, double* volume6) {
  xsect::TriangleMesh out;
  std::vector<std::uint32_t> index(mesh.num_vertices(), 0);
  for (auto v : mesh.vertices()) {
    index[v.idx()] = std::uint32_t(out.vertices.size());
    const Point& p = mesh.point(v);
    out.vertices.emplace_back(float(p.x()), float(p.y()), float(p.z()));
  }
  *volume6 = 0;
  *boundaryEdges = 0;
  for (auto h : mesh.halfedges())
    if (mesh.is_border(h)) ++*boundaryEdges;
  for (auto f : mesh.faces()) {
    std::array<std::uint32_t, 3> t{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      if (k < 3) t[k] = index[v.idx()];
      ++k;
    }
    if (k != 3) continue;
    out.triangles.push_back(t);
    const Eigen::Vector3d a = out.vertices[t[0]].cast<double>(), b = out.vertices[t[1]].cast<double>(),
                          d = out.vertices[t[2]].cast<double>();
    *volume6 += a.dot(b.cross(d));
  }
  *flipped = *volume6 < 0;
  if (*flipped)
    for (auto& t : out.triangles) std::swap(t[1], t[2]);
  return out;
}

int run(const Options& o) {
  using clock = std::chrono::steady_clock;
  const auto tLoad = clock::now();
  const xsect::RunConfig c = xsect::readRunConfig(o.config, o.overrides);
  std::vector<xsect::CuttingPlane> planes;
  if (c.input_kind == xsect::InputKind::slices) {
    const auto slices = xsect::readSlicesFile(c.input_path);
    planes = xsect::sectionsFromSlices(slices, c.input_path, c.segmentation, c.path, {}).planes;
  } else if (c.input_kind == xsect::InputKind::csl) {
    planes = xsect::readCslFile(c.input_path);
  } else {
    throw xsect::InputError(c.path, std::string("input.") + xsect::nameOf(xsect::kInputKinds, c.input_kind),
                            "this input kind is not available to the baseline (slices | csl)");
  }
  const double loadSeconds = secondsSince(tLoad);
  xsect::RunConfig resolved = c;  // voxel_size_mm: auto resolved as `xsect run` does
  const double step = xsect::chooseVoxelSize(resolved, planes).voxel_mm;

  const auto tSample = clock::now();
  std::vector<PointWithNormal> points;
  int sections = 0;
  for (const auto& p : planes) {
    for (const auto& s : p.sections) {
      ++sections;
      sampleRing(s.outer, p.plane, step, points);
      for (const auto& h : s.holes) sampleRing(h, p.plane, step, points);
    }
  }
  const double samplingSeconds = secondsSince(tSample);
  if (points.size() < 10)
    throw xsect::InputError(c.input_path, "",
                            "too few contour points for Poisson (" + std::to_string(points.size()) +
                                "; check segmentation settings)");

  // The surface mesher seeds its search with random points on a sphere drawn from CGAL's default
  // generator, seeded with the time: fix the seed. The mesh still varies a little from run to run
  // (random-200: 4702-4826 triangles, Hausdorff 0.83-0.88 mm, mean distance within 0.001 mm)
  // because CGAL's refinement orders some elements by memory address, which depends on the heap
  // the threaded segmentation leaves; with one thread and ASLR off (`setarch -R taskset -c 0`)
  // the output is byte-identical.
  CGAL::get_default_random() = CGAL::Random(0);
  const auto tPoisson = clock::now();
  const double spacing = CGAL::compute_average_spacing<CGAL::Sequential_tag>(
      points, 6, CGAL::parameters::point_map(CGAL::First_of_pair_property_map<PointWithNormal>()));
  const double spacingSeconds = secondsSince(tPoisson);
  Mesh mesh;
  const bool ok = CGAL::poisson_surface_reconstruction_delaunay(
      points.begin(), points.end(), CGAL::First_of_pair_property_map<PointWithNormal>(),
      CGAL::Second_of_pair_property_map<PointWithNormal>(), mesh, spacing);
  const double poissonSeconds = secondsSince(tPoisson);
  if (!ok || mesh.number_of_faces() == 0) {
    std::cerr << "xsect_poisson_baseline: failure: CGAL Poisson reconstruction failed on "
              << points.size() << " points\n";
    return 1;
  }

  std::size_t boundaryEdges = 0;
  bool flipped = false;
  double volume6 = 0;  // 6 x signed volume
  const xsect::TriangleMesh out = outwardMesh(mesh, &boundaryEdges, &flipped, &volume6);
  writeMeshAtomically(o.out, out);

  std::cerr << "xsect_poisson_baseline: " << points.size() << " points from " << sections
            << " sections, average spacing " << spacing << " mm, Poisson " << poissonSeconds
            << " s, " << out.triangles.size() << " triangles"
            << (boundaryEdges ? ", " + std::to_string(boundaryEdges) + " boundary edges" : "")
            << (flipped ? " (orientation flipped outward)" : "") << "\n";
  if (!o.json.empty()) {
    std::ofstream js(o.json + ".partial");
    js << std::setprecision(17) << "{\n"
       << "  \"points\": " << points.size() << ",\n"
       << "  \"sections\": " << sections << ",\n"
       << "  \"planes\": " << planes.size() << ",\n"
       << "  \"sample_step_mm\": " << step << ",\n"
       << "  \"spacing_mm\": " << spacing << ",\n"
       << "  \"load_s\": " << loadSeconds << ",\n"
       << "  \"sampling_s\": " << samplingSeconds << ",\n"
       << "  \"average_spacing_s\": " << spacingSeconds << ",\n"
       << "  \"poisson_s\": " << poissonSeconds << ",\n"
       << "  \"vertices\": " << out.vertices.size() << ",\n"
       << "  \"triangles\": " << out.triangles.size() << ",\n"
       << "  \"boundary_edges\": " << boundaryEdges << ",\n"
       << "  \"closed\": " << (boundaryEdges == 0 ? "true" : "false") << ",\n"
       << "  \"orientation_flipped\": " << (flipped ? "true" : "false") << ",\n"
       << "  \"volume_mm3\": " << std::abs(volume6) / 6.0 << "\n"
       << "}\n";
    js.close();
    if (!js || std::rename((o.json + ".partial").c_str(), o.json.c_str()) != 0)
      throw std::runtime_error("cannot write " + o.json);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(parseArgs(argc, argv));
  } catch (const xsect::InputError& e) {
    std::cerr << "xsect_poisson_baseline: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "xsect_poisson_baseline: failure: " << e.what() << "\n";
    return 1;
  }
}

// `xsect eval` (docs/commands.md): accuracy of a reconstructed mesh against a
// phantom's analytic truth (truth.yaml) or a reference mesh, and optionally its conformity with
// the input sections (slices.yaml). Prints the headline numbers (evalHeadline) and,
// with --json, writes one JSON object, atomically, with:
//   hausdorff_mm, mean_distance_mm                    symmetric surface distances, mm
//   mesh_to_truth_{max,mean}_mm, truth_to_mesh_{max,mean}_mm   one-sided ("truth" = the reference
//                                                     mesh when --reference is given)
//   surface_samples, truth_surface_samples            points each side was measured at
//   truth_distance_exact                              (truth only) the truth's SDF is exact; the
//                                                     vessel tree's is not, and mesh->truth is then
//                                                     measured to numerically found nearest points
//   dice, iou, voxel_mm, grid_dims                    overlap of the two solids on a voxel grid
//   betti, watertight, surfaces, mesh_volume_mm3      topology of the evaluated mesh's solid
//   truth_betti                                       when known (truth, or watertight reference)
//   separation_condition{checked, holds, ...}         (truth only) thesis Def. 19 checked on samples
//                                                     of the truth's medial axis, beside the run's
//                                                     sampling verdict (report.json next to the mesh)
//   conformity_iou_min, conformity[{slice, image, iou, section_area_mm2, section_perimeter_mm,
//                                         cut_area_mm2}]   with --slices
// Inputs are validated where they enter (InputError: exit 2).
#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <unistd.h>

#include "geometry/evaluation/mesh_distance.h"
#include "geometry/meshing/mesh_topology.h"
#include "geometry/phantoms/phantom_shape.h"
#include "geometry/evaluation/plane_cut.h"
#include "geometry/core/polygon.h"
#include "io/input_error.h"
#include "io/output_destination.h"
#include "io/text_file.h"
#include "io/mesh_io.h"
#include "io/slices_file.h"
#include "io/truth_file.h"
#include "geometry/evaluation/medial_axis_samples.h"
#include "pipeline/commands.h"
#include "pipeline/eval_metrics.h"
#include "pipeline/json_values.h"
#include "pipeline/load_sections.h"
#include "pipeline/progress.h"
#include "report/run/accuracy_block.h"

namespace xsect {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

TriangleMesh readNonEmptyMesh(const std::string& path, const std::string& option) {
  if (path.empty()) throw InputError("", option, "a mesh path is required");
  TriangleMesh m = readMesh(path);
  if (m.triangles.empty()) throw InputError(path, "", "mesh has no triangles");
  return m;
}

json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

/// The input sections of slices.yaml, segmented at a fixed grey threshold.
std::vector<CuttingPlane> loadSections(const std::string& slicesPath, double threshold,
                                       Progress* progress) {
  const std::vector<SliceRecord> slices = readSlicesFile(slicesPath);
  SegmentationParams params;
  params.method = SegmentationMethod::threshold;
  params.threshold = threshold;
  progress->stage("eval: segmenting " + std::to_string(slices.size()) + " slices");
  return sectionsFromSlices(slices, slicesPath, params, "command line", {}).planes;
}

/// Conformity of the mesh with the sections of each input slice: IoU of mesh ∩ plane with the
/// sections inside the observed image rectangle, on scan lines half a pixel apart. Planes where
/// both are empty get a null IoU; iouMin receives the smallest defined IoU (NaN if none).
json conformity(const TriangleMesh& mesh, const std::vector<CuttingPlane>& planes,
                Progress* progress, double* iouMin) {
  progress->stage("eval: conformity");
  json list = json::array();
  *iouMin = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t i = 0; i < planes.size(); ++i) {
    const CuttingPlane& cp = planes[i];
    const double resolution = cp.pixel_mm > 0 ? 0.5 * cp.pixel_mm : 0.1;
    const auto cut = cutMesh(mesh, cp.plane);
    const double iou = regionIoU(cut, cp.sections, resolution, &cp.extent);
    double area = 0.0, perimeter = 0.0;
    for (const Section& s : cp.sections) {
      area += sectionArea(s);
      perimeter += ringLength(s.outer);
      for (const Ring& h : s.holes) perimeter += ringLength(h);
    }
    list.push_back({{"slice", cp.slice}, {"image", cp.name}, {"iou", number(iou)},
                    {"section_area_mm2", area}, {"section_perimeter_mm", perimeter}, {"cut_area_mm2", cutArea(cut, resolution)}});
    if (std::isfinite(iou) && !(iou >= *iouMin)) *iouMin = iou;
    progress->update(double(i + 1) / double(planes.size()));
  }
  return list;
}

/// Surface distances between the mesh and the truth (a phantom's signed distance) or the reference
/// mesh; sets the union of their bounds (lo, hi) and the truth's inside test (which may read
/// referenceQuery, built here), and the truth's keys of `out`.
SurfaceDistances compareSurfaces(const TriangleMesh& mesh, const MeshDistance& meshQuery,
                                 const std::optional<PhantomShape>& truth, const std::optional<TriangleMesh>& reference,
                                 std::optional<MeshDistance>& referenceQuery, Vec3* lo, Vec3* hi,
                                 InsideFn* truthInside, json& out) {
  const SamplingParams sampling;
  meshBounds(mesh, lo, hi);
  SurfaceDistances dist;
  if (truth) {
    const PhantomShape& shape = *truth;
    const SignedDistanceFn sdf = [&shape](const Vec3& x) { return signedDistance(shape, x); };
    Vec3 tlo, thi;
    bounds(shape, &tlo, &thi);
    const Vec3 pad = 0.05 * (thi - tlo) + Vec3::Constant(1e-3);
    // The vessel tree's sdf is a lower bound only: mesh -> truth uses numerically found nearest
    // boundary points (about 11 µs each; the Fig. 1.11 shapes' searches cost 10x more).
    SignedDistanceFn exact;
    if (!hasExactDistance(shape) && shape.kind == ShapeKind::vessel_tree)
      exact = [&shape](const Vec3& x) { return (x - closestBoundaryPoint(shape, x)).norm(); };
    dist = distancesToImplicit(mesh, meshQuery, sdf, tlo - pad, thi + pad, sampling, exact);
    *lo = lo->cwiseMin(tlo);
    *hi = hi->cwiseMax(thi);
    *truthInside = [&shape](const PointRows& rows) {
      std::vector<std::uint8_t> in(rows.size());
      tbb::parallel_for(std::size_t(0), rows.size(),
                        [&](std::size_t i) { in[i] = signedDistance(shape, rows.at(i)) < 0; });
      return in;
    };
    out["truth_betti"] = bettiNumbers(shape);
    out["truth_distance_exact"] = hasExactDistance(shape);
  } else {
    referenceQuery.emplace(*reference);
    dist = distancesToMesh(mesh, meshQuery, *reference, *referenceQuery, sampling);
    Vec3 rlo, rhi;
    meshBounds(*reference, &rlo, &rhi);
    *lo = lo->cwiseMin(rlo);
    *hi = hi->cwiseMax(rhi);
    *truthInside = [&referenceQuery](const PointRows& rows) { return referenceQuery->insideRows(rows); };
    const MeshTopology refTopo = meshTopology(*reference);
    if (refTopo.watertight) out["truth_betti"] = refTopo.betti;
  }
  return dist;
}

/// The Separation Condition itself (thesis Def. 19), from samples of the truth's medial axis
/// (geometry/evaluation/medial_axis_samples.h) tested against the mesh's solid, beside the sampling
/// verdict of the run that made the mesh (its report.json, when it sits beside the mesh).
json separationCondition(const PhantomShape& shape, const MeshDistance& meshQuery, const Vec3& lo, const Vec3& hi,
                         const std::string& meshPath) {
  json s;
  if (!hasExactDistance(shape)) {
    s["checked"] = false;
    s["why"] = "the truth's signed distance is not exact (its medial axis cannot be read from it)";
    return s;
  }
  const double h = (hi - lo).norm() / 80;
  const MedialAxisSamples m = medialAxisSamples([&shape](const Vec3& x) { return signedDistance(shape, x); }, lo, hi,
                                                h, 0.9, 2 * h);
  const std::vector<std::uint8_t> inI = meshQuery.inside(m.interior), inE = meshQuery.inside(m.exterior);
  const auto count = [](const std::vector<std::uint8_t>& v, std::uint8_t x) {
    return std::int64_t(std::count(v.begin(), v.end(), x));
  };
  const std::int64_t missed = count(inI, 0), crossed = count(inE, 1);
  s["checked"] = true;
  s["holds"] = missed == 0 && crossed == 0;
  s["spacing_mm"] = h;
  s["interior_medial_samples"] = m.interior.size();
  s["interior_samples_outside_reconstruction"] = missed;
  s["exterior_medial_samples"] = m.exterior.size();
  s["exterior_samples_inside_reconstruction"] = crossed;
  const std::filesystem::path report = std::filesystem::path(meshPath).parent_path() / "report.json";
  if (std::filesystem::exists(report)) {
    try {
      std::ifstream f(report);
      const json r = json::parse(f);
      if (r.contains("sampling")) {
        s["sampling_verdict"] = r["sampling"]["verdict"];
        s["sampling_conditions"] = r["sampling"]["conditions"];
      }
    } catch (const std::exception&) {
      s["sampling_verdict"] = nullptr;  // a report of another kind: nothing to compare
    }
  }
  return s;
}

/// Three or four plain lines of what `out` measured: the solid's topology against the truth's,
/// the distances and the overlap, the conformity with the sections when measured.
std::string evalHeadline(const json& out) {
  const auto triple = [](const json& b) {
    return std::to_string(b[0].get<int>()) + " " + std::to_string(b[1].get<int>()) + " " +
           std::to_string(b[2].get<int>());
  };
  std::ostringstream s;
  s << "topology: " << triple(out["betti"]);
  if (out.contains("truth_betti"))
    s << " (truth " << triple(out["truth_betti"]) << ": " << (out["betti"] == out["truth_betti"] ? "right" : "WRONG")
      << ")";
  s << (out["watertight"].get<bool>() ? ", watertight" : ", NOT watertight (the topology and Dice are unreliable)")
    << "\n";
  s << "distance to the " << (out.contains("truth") ? "truth" : "reference") << ": Hausdorff "
    << fixedText(out["hausdorff_mm"].get<double>(), 3) << " mm, mean " << fixedText(out["mean_distance_mm"].get<double>(), 3)
    << " mm\n";
  s << "overlap: Dice " << fixedText(out["dice"].get<double>(), 4) << " on " << fixedText(out["voxel_mm"].get<double>(), 3)
    << " mm voxels\n";
  if (out.contains("conformity_iou_min")) {
    s << "conformity with the slices: ";
    if (out["conformity_iou_min"].is_null()) s << "no slice holds a section\n";
    else s << "IoU at least " << fixedText(out["conformity_iou_min"].get<double>(), 4) << " over "
           << out["conformity"].size() << " slices\n";
  }
  return s.str();
}

}  // namespace

int evalCommand(const EvalOptions& options) {
  if (!std::isfinite(options.voxel_mm) || options.voxel_mm < 0)
    throw InputError("", "--voxel", "must be a finite voxel size >= 0 mm (0 = automatic)");
  if (options.truth.empty() == options.reference.empty())
    throw InputError("", "--truth/--reference", "exactly one of them is required");
  // What eval reads may not be what it writes: the mesh, the truth or reference, and with --slices
  // the listing, its images and their fields of view.
  std::vector<std::string> inputs{options.mesh, options.truth, options.reference, options.slices};
  if (!options.slices.empty())
    for (const SliceRecord& s : readSlicesFile(options.slices)) {
      inputs.push_back(s.image_resolved);
      if (s.fov_resolved) inputs.push_back(*s.fov_resolved);
    }
  if (!options.json.empty()) checkOutputFile(options.json, {inputs, "command line", "--json"});
  Progress progress(options.quiet);

  // Read every input before any long computation.
  progress.stage("eval: reading inputs");
  const TriangleMesh mesh = readNonEmptyMesh(options.mesh, "--mesh");
  std::optional<PhantomShape> truth;
  std::optional<TriangleMesh> reference;
  if (!options.truth.empty()) truth = readTruthFile(options.truth);
  else reference = readNonEmptyMesh(options.reference, "--reference");
  std::vector<CuttingPlane> planes;
  if (!options.slices.empty()) planes = loadSections(options.slices, options.threshold, &progress);

  json out;
  out["mesh"] = options.mesh;
  if (truth) out["truth"] = options.truth;
  else out["reference"] = options.reference;

  // Topology of the evaluated solid.
  progress.stage("eval: topology");
  const MeshTopology topo = meshTopology(mesh);
  out["betti"] = topo.betti;
  out["watertight"] = topo.watertight;
  out["surfaces"] = topo.surfaces;
  out["mesh_volume_mm3"] = topo.volume_mm3;
  if (!topo.watertight)
    progress.note("eval: warning: the mesh is not watertight; betti, dice and iou are unreliable");

  // Surface distances.
  progress.stage("eval: surface distances");
  const MeshDistance meshQuery(mesh);
  Vec3 lo, hi;
  InsideFn truthInside;
  std::optional<MeshDistance> referenceQuery;
  const SurfaceDistances dist =
      compareSurfaces(mesh, meshQuery, truth, reference, referenceQuery, &lo, &hi, &truthInside, out);
  out["hausdorff_mm"] = dist.hausdorffMm();
  out["mean_distance_mm"] = dist.meanMm();
  out["mesh_to_truth_max_mm"] = dist.mesh_to_truth.max_mm;
  out["mesh_to_truth_mean_mm"] = dist.mesh_to_truth.mean_mm;
  out["truth_to_mesh_max_mm"] = dist.truth_to_mesh.max_mm;
  out["truth_to_mesh_mean_mm"] = dist.truth_to_mesh.mean_mm;
  out["surface_samples"] = dist.mesh_to_truth.points;
  out["truth_surface_samples"] = dist.truth_to_mesh.points;

  // Volume overlap.
  const GridSpec grid = overlapGrid(lo, hi, options.voxel_mm);
  if (options.voxel_mm > 0 && grid.voxel > options.voxel_mm)
    progress.note("eval: note: voxel enlarged to " + std::to_string(grid.voxel) +
                  " mm to keep the grid under 8M voxels");
  progress.stage("eval: dice on " + std::to_string(grid.dims[0]) + "x" +
                 std::to_string(grid.dims[1]) + "x" + std::to_string(grid.dims[2]) + " voxels");
  const InsideFn meshInside = [&meshQuery](const PointRows& rows) { return meshQuery.insideRows(rows); };
  const VolumeOverlap overlap = volumeOverlap(meshInside, truthInside, grid);
  out["dice"] = overlap.dice();
  out["iou"] = overlap.iou();
  out["voxel_mm"] = grid.voxel;
  out["grid_dims"] = grid.dims;

  if (truth) {
    progress.stage("eval: separation condition");
    out["separation_condition"] = separationCondition(*truth, meshQuery, lo, hi, options.mesh);
  }

  if (!options.slices.empty()) {
    double iouMin = 0;
    out["conformity"] = conformity(mesh, planes, &progress, &iouMin);
    out["conformity_iou_min"] = number(iouMin);
  }
  progress.finish();

  if (!options.json.empty()) writeTextFileAtomically(options.json, out.dump(2) + "\n");
  // The run's page beside the mesh, when there is one, shows these figures too (issue 21).
  const bool paged = addAccuracyToReportPage(options.mesh, out);
  std::cout << evalHeadline(out);
  if (!options.json.empty()) std::cout << "json: " << options.json << "\n";
  if (paged) std::cout << "report: " << (fs::path(options.mesh).parent_path() / "report.html").string() << "\n";
  return 0;
}

}  // namespace xsect

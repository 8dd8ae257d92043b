// Stage 7: meshes, materials, and their check (see mesh_stage.h).
#include "pipeline/mesh_stage.h"

#include <algorithm>
#include <stdexcept>

#include "geometry/meshing/volume_mesher.h"
#include "geometry/reconstruction/voxel_labels.h"
#include "geometry/reconstruction/well_composed_labels.h"
#include "pipeline/material_sections.h"

namespace xsect {

namespace {

/// Label L's solid (its voxels in `voxelLabel`, well-composed with every other label's:
/// well_composed_labels.h, so that its mesh bounds the set voxelBetti counts) and its mesh. No
/// voxel: voxels == 0.
Material materialOf(std::uint16_t L, const std::vector<std::uint16_t>& voxelLabel, const ScalarField& field,
                    double voxel_mm) {
  Material m;
  m.label = L;
  std::vector<std::uint8_t> in_L(voxelLabel.size());
  for (std::size_t q = 0; q < in_L.size(); ++q) {
    in_L[q] = voxelLabel[q] == L;
    m.voxels += in_L[q];
  }
  if (m.voxels == 0) return m;
  ScalarField f = labelField(field, voxelLabel, L, float(0.05 * voxel_mm));
  imposeSolid(f, in_L, float(0.05 * voxel_mm));
  m.voxel_betti = voxelBetti(in_L, field.grid);
  m.mesh = meshZeroLevel(f);
  return m;
}

/// The mesh written must bound the solid report.json describes (issue 14): a difference is a
/// defect of this program, an error (exit 1, nothing written), never a warning.
void requireMeshBoundsSolid(const MeshTopology& mesh, const Betti& solid, const std::string& what) {
  if (solid[0] == 0 || mesh.betti[0] == 0)
    throw std::runtime_error(what + " is empty although the sections are not (the solid has " +
                             std::to_string(solid[0]) + " components): nothing written");
  if (mesh.watertight && mesh.betti == solid) return;
  const auto betti = [](const Betti& b) {
    return "(" + std::to_string(b[0]) + ", " + std::to_string(b[1]) + ", " + std::to_string(b[2]) + ")";
  };
  throw std::runtime_error(what + " has Betti numbers " + betti(mesh.betti) +
                           (mesh.watertight ? "" : " and is not watertight") + " while the voxel solid it was made from has " +
                           betti(solid) + "; nothing written (a defect of xsect: please report it with the configuration)");
}

/// Method 3: the mesh is ∂R'' itself, so it must be closed and have one outer surface per
/// component of the union of the tetrahedra it bounds (issue 14, as requireMeshBoundsSolid); where
/// it opened pinches, each vertex copy may split one more piece off (tetrahedra_components.h).
void requireMeshBoundsTetrahedra(const MeshTopology& mesh, int components, std::int64_t copies,
                                 const std::string& what) {
  if (components == 0 || mesh.betti[0] == 0)
    throw std::runtime_error(what + " is empty although the sections are not (method 3's tetrahedra form " +
                             std::to_string(components) + " components): nothing written");
  if (mesh.watertight && mesh.betti[0] >= components && mesh.betti[0] <= components + copies) return;
  throw std::runtime_error(what + " has " + std::to_string(mesh.betti[0]) + " outer surfaces" +
                           (mesh.watertight ? "" : " and is not watertight") +
                           " while the union of method 3's tetrahedra it bounds has " + std::to_string(components) +
                           " components" +
                           (copies > 0 ? " (" + std::to_string(copies) + " vertex copies at opened pinches allow up to " +
                                             std::to_string(components + copies) + ")"
                                       : std::string()) +
                           "; nothing written (a defect of xsect: please report it with the configuration)");
}

std::string bettiText(const Betti& b) {
  return "(" + std::to_string(b[0]) + ", " + std::to_string(b[1]) + ", " + std::to_string(b[2]) + ")";
}

/// Several materials, from dense copies of the labels and the field (not yet by blocks): where two
/// voxels of a label meet at an edge or a vertex only, labels change until every label's voxels
/// are well-composed at once (well_composed_labels.h), so that the materials stay a partition of
/// the union and labels.nrrd (m.voxel_label, changed with them) holds what their meshes bound; then
/// each label's solid and mesh. The union changes only where it was not well-composed itself
/// (method 3's voxels by centres), and must keep the solid's Betti numbers `solid`.
void addMaterials(const std::vector<std::uint16_t>& labels, const ScalarField& field, double voxel_mm,
                  const Betti& solid, MeshStage& m) {
  std::vector<std::uint16_t> voxelLabel = denseValues(m.voxel_label);
  m.label_composition = makeLabelsWellComposed(voxelLabel, field.grid);
  if (m.label_composition.voxels_added > 0) {
    std::vector<std::uint8_t> in(voxelLabel.size());
    for (std::size_t q = 0; q < in.size(); ++q) in[q] = voxelLabel[q] != 0;
    const Betti now = voxelBetti(in, field.grid);
    if (now != solid)
      throw std::runtime_error("the materials' voxels, made well-composed (" +
                               std::to_string(m.label_composition.voxels_added) + " voxels added), have Betti numbers " +
                               bettiText(now) + " while the solid has " + bettiText(solid) +
                               "; nothing written (a defect of xsect: please report it with the configuration)");
  }
  if (m.label_composition.voxels_relabelled + m.label_composition.voxels_added > 0)
    m.voxel_label = blockValues(voxelLabel, field.grid);
  for (const std::uint16_t L : labels) {
    Material mat = materialOf(L, voxelLabel, field, voxel_mm);
    if (mat.voxels == 0) {  // a label too small for the grid (a few pixels in one slice)
      m.warnings.push_back("label " + std::to_string(L) + " has sections but no voxel at " + std::to_string(voxel_mm) +
                           " mm: no mesh for it");
      continue;
    }
    m.materials.push_back(std::move(mat));
  }
}

/// The labels of the smooth solid {field < 0}, on the smoothing's grid (the method's lattice with
/// wider margins, smooth_stage.cpp): the method's label where it has one, elsewhere the label
/// reached first from the labelled voxels through the smooth solid's face neighbours (breadth
/// first, from the voxels in index order: deterministic), `fallback` in a component holding no
/// labelled voxel; 0 outside.
BlockGrid<std::uint16_t> labelsOfSmoothSolid(const ScalarField& field, const BlockGrid<std::uint16_t>& method,
                                            std::uint16_t fallback) {
  const GridSpec& g = field.grid;
  const GridSpec& m = method.grid();
  std::array<int, 3> shift{};  // method voxel = smooth voxel - shift
  for (int a = 0; a < 3; ++a) shift[std::size_t(a)] = int(std::lround((m.origin[a] - g.origin[a]) / g.voxel));
  std::vector<std::uint16_t> dense(std::size_t(g.count()), 0);
  std::vector<std::int64_t> queue;
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        const std::int64_t v = g.index(i, j, k);
        if (!(field.values[std::size_t(v)] < 0)) continue;
        const int mi = i - shift[0], mj = j - shift[1], mk = k - shift[2];
        const bool onMethod = mi >= 0 && mj >= 0 && mk >= 0 && mi < m.dims[0] && mj < m.dims[1] && mk < m.dims[2];
        const std::uint16_t l = onMethod ? method.at(mi, mj, mk) : std::uint16_t(0);
        if (l != 0) {
          dense[std::size_t(v)] = l;
          queue.push_back(v);
        }
      }
  const std::int64_t sx = 1, sy = g.dims[0], sz = std::int64_t(g.dims[0]) * g.dims[1];
  const auto spread = [&](std::vector<std::int64_t>& q) {
    for (std::size_t at = 0; at < q.size(); ++at) {
      const std::int64_t v = q[at];
      const int i = int(v % sy), j = int((v / sy) % g.dims[1]), k = int(v / sz);
      const std::int64_t nb[6] = {i > 0 ? v - sx : -1, i + 1 < g.dims[0] ? v + sx : -1, j > 0 ? v - sy : -1,
                                  j + 1 < g.dims[1] ? v + sy : -1, k > 0 ? v - sz : -1, k + 1 < g.dims[2] ? v + sz : -1};
      for (const std::int64_t n : nb)
        if (n >= 0 && field.values[std::size_t(n)] < 0 && dense[std::size_t(n)] == 0) {
          dense[std::size_t(n)] = dense[std::size_t(v)];
          q.push_back(n);
        }
    }
  };
  spread(queue);
  for (std::int64_t v = 0; v < g.count(); ++v)
    if (field.values[std::size_t(v)] < 0 && dense[std::size_t(v)] == 0) {
      dense[std::size_t(v)] = fallback;
      std::vector<std::int64_t> one{v};
      spread(one);
    }
  return blockValues(dense, g);
}

}  // namespace

MeshStage meshStage(const RunInputs& in, const SectionScene& scene, const ReconstructStage& reconstruction,
                    const SmoothStage* smooth) {
  const RunConfig& c = in.config;
  const SampledReconstruction& rec = reconstruction.solid;
  const bool method3 = reconstruction.delaunay.has_value();
  const double voxel = rec.inside.grid().voxel;  // method 3 may refine the scene's (reconstruct_stage.h)
  MeshStage m;
  ConformalCutStats methodCut;
  // ∂R'' with open edges: its gluing failed on some plane (the jittered torus with enforced
  // conformity, seed 2: five edges where faces of two cells nearly parallel to a plane meet it).
  // R'' itself, the union of its tetrahedra, is whole: its voxelisation is meshed instead.
  // Or the grid holds no voxel set with its topology (reconstruct_stage.cpp): the solid is then the
  // voxels, made well-composed there, and the mesh is theirs (one solid, issue 49).
  m.method3_from_voxels = method3 && reconstruction.delaunay->mesh_from_voxels;
  if (m.method3_from_voxels) {
    m.voxel_mesh_critical_added = reconstruction.delaunay->voxels_added_well_composed;
    m.voxel_mesh_betti = rec.voxel_betti;
    m.method_mesh = meshZeroLevel(rec.field);
    if (c.conformal_mesh) methodCut = cutAlongSections(m.method_mesh, scene.planes, scene.fields, voxel);
    const std::string what = (smooth ? "the unsmoothed mesh" : "the mesh") + std::string(" is the voxelisation of R'' at ") +
                             std::to_string(voxel) + " mm made well-composed, not its boundary through the "
                             "contours (report.json reconstruction.delaunay.mesh_source: voxels, mesh_voxel_betti)";
    if (reconstruction.delaunay->result.stats.open_edges > 0)
      m.warnings.push_back("method 3's boundary could not be glued closed (" +
                          std::to_string(reconstruction.delaunay->result.stats.open_edges) + " open edges): " + what);
    else
      m.warnings.push_back("R'' is thinner than the voxel in places: its boundary has Betti numbers " +
                          bettiText(reconstruction.delaunay->boundary_betti) + " but no voxel set on this grid (by centres or by "
                          "cubes) has them; so that the mesh, labels.nrrd and report.json describe one solid, " + what +
                          "; a smaller reconstruction.voxel_size_mm may hold the boundary's topology");
  } else if (method3) {
    m.method_mesh = reconstruction.delaunay->result.mesh;  // ∂R'': conformal by construction, no cut
    // Pieces touching at a vertex are kept apart by copies of the vertex at one position: STL
    // stores no vertex indices, so a reader merges them back into a pinched surface.
    const bool stl = std::find(c.mesh_formats.begin(), c.mesh_formats.end(), "stl") != c.mesh_formats.end();
    if (stl && !smooth && reconstruction.delaunay->result.stats.singular_vertices > 0)
      m.warnings.push_back(std::to_string(reconstruction.delaunay->result.stats.singular_vertices) +
                          " vertices of method 3's mesh are copied where pieces touch at a point; mesh.stl keeps no "
                          "vertex indices, so readers merge the copies (the surface is then pinched there): use "
                          "mesh.ply or mesh.obj for the Betti numbers report.json states");
  } else {
    m.method_mesh = meshZeroLevel(rec.field);
    if (c.conformal_mesh) methodCut = cutAlongSections(m.method_mesh, scene.planes, scene.fields, scene.params.voxel_mm);
  }
  m.conformal_by_construction = method3 && !m.method3_from_voxels && !smooth;
  if (smooth) m.mesh = smooth->surface.mesh;
  else m.mesh = std::move(m.method_mesh);  // one copy of a mesh of millions of triangles
  m.cut = !smooth ? methodCut
                  : c.conformal_mesh ? cutAlongSections(m.mesh, scene.planes, scene.fields, scene.params.voxel_mm)
                                     : ConformalCutStats{};

  // Several materials: each voxel takes the label of the section its lift comes from (method 3:
  // of the label's own R'' holding it); one mesh per label (written when there are at least two)
  // beside the union's.
  const bool labelled = anyLabelled(in);  // segmentation labels gave per-label sections
  const std::vector<std::uint16_t> labels = materialLabels(in);
  const bool several = labels.size() >= 2;
  {
    const std::vector<std::vector<Section>> ownSections;  // empty: the planes' own sections
    m.voxel_label = voxelLabels(rec.inside, rec.section_plane, scene.planes, labelled ? in.labelled : ownSections,
                                 &scene.pieces);
  }
  // One solid (issue 49): with smoothing, mesh.* is the smooth surface, so labels.nrrd is the
  // smooth solid it bounds (its voxels, repaired and well-composed: smooth_stage.h), on its grid,
  // each voxel with the method's label there, or its nearest labelled neighbour's within it; the
  // materials are then that solid's labels.
  if (smooth)
    m.voxel_label = labelsOfSmoothSolid(smooth->field, m.voxel_label, labels.empty() ? std::uint16_t(1) : labels.front());
  // Several materials: the union's solid partitioned by the labels of the sections the voxels lift
  // from (method 3 too, issue 49: each label's own R'' overlapped the others' and was not the
  // union's), so that the materials tile the union and each mesh bounds its label's voxels.
  if (several)
    addMaterials(labels, smooth ? smooth->field : denseField(rec.field), voxel,
                 smooth ? smooth->voxel_betti : rec.voxel_betti, m);
  if (labels.size() > 64)
    m.warnings.push_back(std::to_string(labels.size()) +
                        " materials (segmentation.method: labels takes every pixel value as a "
                        "label; is the image a grey image?)");
  return m;
}

DiagnoseStage diagnoseStage(const ReconstructStage& reconstruction, const SmoothStage* smooth, const MeshStage& meshes) {
  const Betti& methodBetti = reconstruction.solid.voxel_betti;
  const bool method3 = reconstruction.delaunay.has_value();
  // The method's own mesh: bounds the repaired voxel solid (methods 1 and 2), or the tetrahedra (method 3).
  const auto requireMethodMesh = [&](const MeshTopology& t, const std::string& what) {
    if (meshes.method3_from_voxels)
      requireMeshBoundsSolid(t, meshes.voxel_mesh_betti, what);
    else if (method3)
      requireMeshBoundsTetrahedra(t, reconstruction.delaunay->components, reconstruction.delaunay->opened_copies, what);
    else requireMeshBoundsSolid(t, methodBetti, what);
  };
  DiagnoseStage d;
  d.topology = meshTopology(meshes.mesh);
  if (smooth)
    requireMeshBoundsSolid(d.topology, smooth->voxel_betti,
                           std::string("the smoothed mesh (") + nameOf(kSmoothingMethods, smooth->method) + ")");
  else
    requireMethodMesh(d.topology, "the mesh");
  d.method_topology = smooth ? meshTopology(meshes.method_mesh) : d.topology;
  if (smooth) requireMethodMesh(d.method_topology, "the unsmoothed mesh");
  // Method 3's boundary and its voxels: one solid by construction (reconstruct_stage.cpp), checked.
  if (method3 && !meshes.method3_from_voxels && d.method_topology.betti != methodBetti)
    throw std::runtime_error("method 3's mesh has Betti numbers " + bettiText(d.method_topology.betti) +
                             " while its voxels have " + bettiText(methodBetti) +
                             "; nothing written (a defect of xsect: please report it with the configuration)");
  for (const Material& m : meshes.materials) {
    d.material_topology.push_back(meshTopology(m.mesh));
    requireMeshBoundsSolid(d.material_topology.back(), m.voxel_betti, "the mesh of label " + std::to_string(m.label));
  }
  return d;
}

}  // namespace xsect

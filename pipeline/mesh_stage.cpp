// Stage 7: meshes, materials, and their check (see mesh_stage.h).
#include "pipeline/mesh_stage.h"

#include <algorithm>
#include <stdexcept>

#include "geometry/meshing/volume_mesher.h"
#include "geometry/reconstruction/voxel_labels.h"
#include "pipeline/material_sections.h"

namespace xsect {

namespace {

/// Label L's solid (made well-composed, so that its mesh bounds the set voxelBetti counts: the
/// mesh of a label may take a voxel of a neighbouring label where the two meet at a vertex or an
/// edge only; labels.nrrd keeps each voxel's own label) and its mesh. No voxel: voxels == 0.
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
  m.critical_voxels_added = makeWellComposed(in_L, field.grid);
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

/// Method 3: where a mesh's voxelisation has other Betti numbers than the mesh, the warning.
void warnVoxelBetti(const MeshTopology& mesh, const Betti& voxels, const std::string& what,
                    std::vector<std::string>* warnings) {
  if (mesh.betti == voxels) return;
  warnings->push_back("the voxelisation of method 3's solid" + (what.empty() ? std::string() : " (" + what + ")") +
                      " has Betti numbers " + bettiText(voxels) +
                      " while the mesh has " + bettiText(mesh.betti) +
                      ": parts of R'' thinner than the voxel size; labels.nrrd, the graph checks and the smoothing "
                      "read the voxels (report.json reconstruction.delaunay.voxel_betti), the mesh is R'' itself");
}

/// Method 3 with several materials: each label's own R'' (delaunay_materials.h).
void delaunayMaterialsOf(const DelaunayMaterials& dm, MeshStage& m, std::vector<std::string>* warnings) {
  m.voxel_label = dm.labels;
  for (const DelaunayMaterial& d : dm.materials) {
    if (d.mesh.triangles.empty()) {  // e.g. a label seen on one plane only
      warnings->push_back("label " + std::to_string(d.label) +
                          " has sections but method 3 joins none of them (its R'' is empty): no mesh for it");
      continue;
    }
    Material mat;
    mat.label = d.label;
    mat.mesh = d.mesh;
    mat.voxels = d.voxels;
    mat.voxel_betti = d.voxel_betti;
    mat.delaunay = d.stats;
    mat.tetrahedra_components = d.tetrahedra_components;
    mat.opened_copies = d.opened_copies;
    mat.delaunay_connections = d.connections;
    m.materials.push_back(std::move(mat));
  }
}

}  // namespace

MeshStage meshStage(const RunInputs& in, const SectionScene& scene, const ReconstructStage& reconstruction,
                    const SmoothStage* smooth, std::vector<std::string>* warnings) {
  const RunConfig& c = in.config;
  const SampledReconstruction& rec = reconstruction.solid;
  const bool method3 = reconstruction.delaunay.has_value();
  MeshStage m;
  ConformalCutStats methodCut;
  // ∂R'' with open edges: its gluing failed on some plane (the jittered torus with enforced
  // conformity, seed 2: five edges where faces of two cells nearly parallel to a plane meet it).
  // R'' itself, the union of its tetrahedra, is whole: its voxelisation is meshed instead.
  m.method3_from_voxels = method3 && reconstruction.delaunay->stats.open_edges > 0 && rec.voxels_inside > 0;
  if (m.method3_from_voxels) {
    BlockGrid<std::uint8_t> solid = rec.inside;
    m.voxel_mesh_critical_added = makeWellComposed(solid);
    BlockGrid<float> field = rec.field;
    imposeSolid(field, solid, float(0.05 * c.voxel_size_mm));
    m.voxel_mesh_betti = voxelBetti(solid);
    m.method_mesh = meshZeroLevel(field);
    if (c.conformal_mesh) methodCut = cutAlongSections(m.method_mesh, scene.planes, scene.fields, c.voxel_size_mm);
    warnings->push_back("method 3's boundary could not be glued closed (" +
                        std::to_string(reconstruction.delaunay->stats.open_edges) + " open edges): " +
                        (smooth ? "the unsmoothed mesh" : "the mesh") + " is the voxelisation of R'' at " +
                        std::to_string(c.voxel_size_mm) +
                        " mm made well-composed, not its boundary through the contours (report.json "
                        "reconstruction.delaunay.mesh_source: voxels, mesh_voxel_betti)");
  } else if (method3) {
    m.method_mesh = reconstruction.delaunay->mesh;  // ∂R'': conformal by construction, no cut
    // Pieces touching at a vertex are kept apart by copies of the vertex at one position: STL
    // stores no vertex indices, so a reader merges them back into a pinched surface.
    const bool stl = std::find(c.mesh_formats.begin(), c.mesh_formats.end(), "stl") != c.mesh_formats.end();
    if (stl && !smooth && reconstruction.delaunay->stats.singular_vertices > 0)
      warnings->push_back(std::to_string(reconstruction.delaunay->stats.singular_vertices) +
                          " vertices of method 3's mesh are copied where pieces touch at a point; mesh.stl keeps no "
                          "vertex indices, so readers merge the copies (the surface is then pinched there): use "
                          "mesh.ply or mesh.obj for the Betti numbers report.json states");
  } else {
    m.method_mesh = meshZeroLevel(rec.field);
    if (c.conformal_mesh) methodCut = cutAlongSections(m.method_mesh, scene.planes, scene.fields, c.voxel_size_mm);
  }
  m.conformal_by_construction = method3 && !m.method3_from_voxels && !smooth;
  if (smooth) m.mesh = smooth->surface.mesh;
  else m.mesh = std::move(m.method_mesh);  // one copy of a mesh of millions of triangles
  m.cut = !smooth ? methodCut
                  : c.conformal_mesh ? cutAlongSections(m.mesh, scene.planes, scene.fields, c.voxel_size_mm)
                                     : ConformalCutStats{};

  // Several materials: each voxel takes the label of the section its lift comes from (method 3:
  // of the label's own R'' holding it); one mesh per label (written when there are at least two)
  // beside the union's.
  const bool labelled = anyLabelled(in);  // segmentation labels gave per-label sections
  const std::vector<std::uint16_t> labels = materialLabels(in);
  const bool several = labels.size() >= 2;
  if (method3 && several && reconstruction.delaunay_materials) {
    delaunayMaterialsOf(*reconstruction.delaunay_materials, m, warnings);
  } else {
    const std::vector<std::vector<Section>> ownSections;  // empty: the planes' own sections
    m.voxel_label = voxelLabels(rec.inside, rec.section_plane, scene.planes, labelled ? in.labelled : ownSections,
                                 &scene.pieces);
  }
  // Several materials (methods 1 and 2): their solids and meshes from dense copies (not yet by blocks).
  const bool voxelMaterials = several && !method3;
  const ScalarField field = voxelMaterials ? denseField(rec.field) : ScalarField{};
  const std::vector<std::uint16_t> voxelLabel = voxelMaterials ? denseValues(m.voxel_label) : std::vector<std::uint16_t>{};
  if (voxelMaterials)
    for (const std::uint16_t L : labels) {
      Material mat = materialOf(L, voxelLabel, field, c.voxel_size_mm);
      if (mat.voxels == 0) {  // a label too small for the grid (a few pixels in one slice)
        warnings->push_back("label " + std::to_string(L) + " has sections but no voxel at " +
                            std::to_string(c.voxel_size_mm) + " mm: no mesh for it");
        continue;
      }
      m.materials.push_back(std::move(mat));
    }
  if (labels.size() > 64)
    warnings->push_back(std::to_string(labels.size()) +
                        " materials (segmentation.method: labels takes every pixel value as a "
                        "label; is the image a grey image?)");
  return m;
}

DiagnoseStage diagnoseStage(const ReconstructStage& reconstruction, const SmoothStage* smooth, MeshStage& meshes,
                            std::vector<std::string>* warnings) {
  const Betti& methodBetti = reconstruction.solid.voxel_betti;
  const bool method3 = reconstruction.delaunay.has_value();
  // The method's own mesh: bounds the repaired voxel solid (methods 1 and 2), or the tetrahedra (method 3).
  const auto requireMethodMesh = [&](const MeshTopology& t, const std::string& what) {
    if (meshes.method3_from_voxels)
      requireMeshBoundsSolid(t, meshes.voxel_mesh_betti, what);
    else if (method3)
      requireMeshBoundsTetrahedra(t, reconstruction.delaunay_components, reconstruction.delaunay_opened_copies, what);
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
  if (method3 && !meshes.method3_from_voxels)
    warnVoxelBetti(d.method_topology, methodBetti, meshes.materials.empty() ? "" : "all labels", warnings);
  for (Material& m : meshes.materials) {
    m.topology = meshTopology(m.mesh);
    const std::string what = "the mesh of label " + std::to_string(m.label);
    if (m.delaunay) {
      requireMeshBoundsTetrahedra(m.topology, m.tetrahedra_components, m.opened_copies, what);
      warnVoxelBetti(m.topology, m.voxel_betti, "label " + std::to_string(m.label), warnings);
    } else {
      requireMeshBoundsSolid(m.topology, m.voxel_betti, what);
    }
  }
  return d;
}

}  // namespace xsect

// Stage 7: meshes, materials, and their check (see mesh_stage.h).
#include "pipeline/mesh_stage.h"

#include <algorithm>
#include <stdexcept>

#include "geometry/meshing/volume_mesher.h"
#include "geometry/reconstruction/voxel_labels.h"

namespace xsect {

namespace {

/// The labels the sections carry (segmentation labels when any plane has them), sorted.
std::vector<std::uint16_t> labelValues(const RunInputs& in, bool anyLabelled) {
  std::vector<std::uint16_t> values;
  for (std::size_t p = 0; p < in.planes.size(); ++p)
    for (const auto& s : anyLabelled ? in.labelled[p] : in.planes[p].sections) values.push_back(std::uint16_t(s.label));
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end()), values.end());
  return values;
}

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

}  // namespace

MeshStage meshStage(const RunInputs& in, const SectionScene& scene, const ReconstructStage& reconstruction,
                    const SmoothStage* smooth, std::vector<std::string>* warnings) {
  const RunConfig& c = in.config;
  const SampledReconstruction& rec = reconstruction.solid;
  MeshStage m;
  m.method_mesh = meshZeroLevel(rec.field);
  const ConformalCutStats methodCut = c.conformal_mesh
                                          ? cutAlongSections(m.method_mesh, scene.planes, scene.fields, c.voxel_size_mm)
                                          : ConformalCutStats{};
  if (smooth) m.mesh = smooth->surface.mesh;
  else m.mesh = std::move(m.method_mesh);  // one copy of a mesh of millions of triangles
  m.cut = !smooth ? methodCut
                  : c.conformal_mesh ? cutAlongSections(m.mesh, scene.planes, scene.fields, c.voxel_size_mm)
                                     : ConformalCutStats{};

  // Several materials: each voxel takes the label of the section its lift comes from; one mesh
  // per label (written when there are at least two) beside the union's.
  bool anyLabelled = false;  // segmentation labels gave per-label sections
  for (const auto& l : in.labelled) anyLabelled = anyLabelled || !l.empty();
  const std::vector<std::vector<Section>> ownSections;  // empty: the planes' own sections
  m.voxel_label = voxelLabels(rec.inside, rec.section_plane, scene.planes, anyLabelled ? in.labelled : ownSections,
                               &scene.pieces);
  const std::vector<std::uint16_t> labels = labelValues(in, anyLabelled);
  // Several materials: their solids and meshes from dense copies (not yet by blocks).
  const ScalarField field = labels.size() >= 2 ? denseField(rec.field) : ScalarField{};
  const std::vector<std::uint16_t> voxelLabel = labels.size() >= 2 ? denseValues(m.voxel_label) : std::vector<std::uint16_t>{};
  if (labels.size() >= 2)
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

DiagnoseStage diagnoseStage(const ReconstructStage& reconstruction, const SmoothStage* smooth, MeshStage& meshes) {
  const Betti& methodBetti = reconstruction.solid.voxel_betti;
  DiagnoseStage d;
  d.topology = meshTopology(meshes.mesh);
  requireMeshBoundsSolid(d.topology, smooth ? smooth->voxel_betti : methodBetti,
                         smooth ? std::string("the smoothed mesh (") + nameOf(kSmoothingMethods, smooth->method) + ")"
                                : std::string("the mesh"));
  d.method_topology = smooth ? meshTopology(meshes.method_mesh) : d.topology;
  if (smooth) requireMeshBoundsSolid(d.method_topology, methodBetti, "the unsmoothed mesh");
  for (Material& m : meshes.materials) {
    m.topology = meshTopology(m.mesh);
    requireMeshBoundsSolid(m.topology, m.voxel_betti, "the mesh of label " + std::to_string(m.label));
  }
  return d;
}

}  // namespace xsect

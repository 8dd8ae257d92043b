// Stage 7: meshes, materials, and their check (see mesh_stage.h).
#include "pipeline/mesh_stage.h"

#include <stdexcept>

#include "geometry/meshing/volume_mesher.h"
#include "geometry/reconstruction/voxel_labels.h"
#include "geometry/reconstruction/well_composed_labels.h"
#include "pipeline/material_sections.h"
#include "pipeline/mesh_bounds.h"

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

MeshStage meshStage(const RunInputs& in, const SectionScene& scene, const Method& method,
                    const ReconstructStage& reconstruction, const SmoothStage* smooth) {
  const RunConfig& c = in.config;
  const SampledReconstruction& rec = reconstruction.solid;
  const double voxel = rec.inside.grid().voxel;  // method 3 may refine the scene's (delaunay_method.h)
  MeshStage m;
  MethodMesh own = method.mesh(c, scene, reconstruction, smooth != nullptr);
  m.method_mesh = std::move(own.mesh);
  m.warnings = std::move(own.warnings);
  const ConformalCutStats methodCut = own.cut;
  m.conformal_by_construction = own.conformal_by_construction && !smooth;
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

DiagnoseStage diagnoseStage(const Method& method, const ReconstructStage& reconstruction, const SmoothStage* smooth,
                            const MeshStage& meshes) {
  DiagnoseStage d;
  d.topology = meshTopology(meshes.mesh);
  if (smooth)
    requireMeshBoundsSolid(d.topology, smooth->voxel_betti,
                           std::string("the smoothed mesh (") + nameOf(kSmoothingMethods, smooth->method) + ")");
  // The method's own mesh bounds its solid (methods 1 and 2: the repaired voxels; method 3: its
  // tetrahedra, or its voxels where the mesh is theirs).
  d.method_topology = smooth ? meshTopology(meshes.method_mesh) : d.topology;
  method.requireMeshBoundsSolid(d.method_topology, reconstruction, smooth ? "the unsmoothed mesh" : "the mesh");
  for (const Material& m : meshes.materials) {
    d.material_topology.push_back(meshTopology(m.mesh));
    requireMeshBoundsSolid(d.material_topology.back(), m.voxel_betti, "the mesh of label " + std::to_string(m.label));
  }
  return d;
}

}  // namespace xsect

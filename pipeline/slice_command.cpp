// `xsect slice` (issue 18): cuts a closed mesh (a model organ) by planes and writes the sections as
// an input for `xsect run`: DIR/input.csl and DIR/config.yaml naming it. The planes are poses as
// in advice.yaml (a list `slices:` of `image_to_world`, with optional width and height) or the
// planes of a .csl; --planes may repeat, and the planes are taken in the order given. A plane
// cuts the whole mesh (a contour file gives all of O ∩ P on its plane). Bad meshes (unreadable,
// not closed), a plane that misses the mesh and malformed plane files are input errors (exit 2)
// naming the file and the plane; the folder appears complete or not at all.
#include <string>
#include <vector>

#include "geometry/core/plane_of_pose.h"
#include "geometry/meshing/mesh_topology.h"
#include "geometry/slicing/mesh_sections.h"
#include "io/csl_file.h"
#include "io/file_checks.h"
#include "io/input_error.h"
#include "io/mesh_io.h"
#include "io/slices_file.h"
#include "io/staged_output.h"
#include "io/text_file.h"
#include "pipeline/commands.h"
#include "pipeline/output_manifest.h"
#include "pipeline/progress.h"

namespace xsect {

namespace {

/// A plane to cut by, with where it came from (for messages).
struct NamedPlane {
  Plane plane;
  std::string file, key;
};

std::vector<NamedPlane> planesOf(const std::string& path) {
  std::vector<NamedPlane> out;
  if (lowerExtension(path) == "csl") {
    const std::vector<CuttingPlane> planes = readCslFile(path);
    for (std::size_t p = 0; p < planes.size(); ++p) out.push_back({planes[p].plane, path, planes[p].name});
    return out;
  }
  const std::vector<PoseRecord> poses = readPosesFile(path);
  for (std::size_t p = 0; p < poses.size(); ++p)
    out.push_back({planeOfPose(poses[p].image_to_world), path, "slices[" + std::to_string(p) + "]"});
  return out;
}

}  // namespace

int sliceCommand(const SliceOptions& o) {
  Progress progress(o.quiet);
  std::vector<std::string> inputs{o.mesh};
  inputs.insert(inputs.end(), o.planes.begin(), o.planes.end());
  const OutputGuard guard{inputs, "command line", "--out"};
  checkOutputDestination(o.out, guard);  // before the work: the folder may not hold the inputs
  progress.stage("read");
  const TriangleMesh mesh = readMesh(o.mesh);
  if (mesh.triangles.empty()) throw InputError(o.mesh, "mesh", "holds no triangle");
  if (!meshTopology(mesh).watertight)
    throw InputError(o.mesh, "mesh",
                     "is not closed (an edge not shared by exactly two triangles): it bounds no solid to cut");
  std::vector<NamedPlane> named;
  for (const std::string& f : o.planes) {
    std::vector<NamedPlane> more = planesOf(f);
    named.insert(named.end(), more.begin(), more.end());
  }
  if (named.empty()) throw InputError("", "--planes", "at least one plane file is required");

  progress.stage("cut", "planes");
  std::vector<CuttingPlane> planes(named.size());
  for (std::size_t p = 0; p < named.size(); ++p) {
    CuttingPlane& cp = planes[p];
    cp.plane = named[p].plane;
    cp.slice = int(p);
    cp.name = "plane " + std::to_string(p + 1);
    try {
      cp.sections = meshSections(mesh, cp.plane);
    } catch (const std::invalid_argument& e) {
      throw InputError(o.mesh, "mesh", std::string(e.what()) + " (" + named[p].file + " " + named[p].key + ")");
    }
    if (cp.sections.empty())
      throw InputError(named[p].file, named[p].key, "the plane misses the mesh " + o.mesh);
    progress.update(std::int64_t(p + 1), std::int64_t(named.size()));
  }

  progress.stage("write");
  StagedOutput out(o.out, guard);
  writeCslFile(out.file("input.csl").string(), planes);
  writeTextFile(out.file("config.yaml").string(),
                "# Made by `xsect slice` from " + o.mesh + " (" + std::to_string(planes.size()) +
                    " planes).\ninput:\n  csl: input.csl\n");
  writeTextFile(out.file(kManifestName).string(), outputManifestText(manifestHead("slice", inputs), out.dir()));
  out.commit();
  progress.finish();
  return 0;
}

}  // namespace xsect

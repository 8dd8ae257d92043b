// Plain-word warnings (see warning_advice.h). Each rule matches a phrase of the stage that emits
// the warning (pipeline/*_stage.cpp, conformity_report.cpp, load_sections.cpp, io readers).
#include "report/run/warning_advice.h"

#include "report/page/report_page.h"

namespace xsect {

namespace {

struct Rule {
  const char* phrase;
  const char* meaning;
  const char* action;
};

constexpr Rule kRules[] = {
    {"open ends:",
     "The outermost slices on some side still cut the object: no slice saw where it ends there, and the solid "
     "goes on past them until the virtual empty planes that close every reconstruction, its shape extrapolated.",
     "Nothing, if the object ends just beyond the outermost slices. If it goes on, add slices beyond its ends, "
     "or set reconstruction.end_margin_mm to how far it goes."},
    {"only one plane holds sections",
     "Only one slice saw the object: its shape across that slice is unknown and the result is that section "
     "extruded.",
     "Add slices that cross this one."},
    {"touching the edge of the image or field of view",
     "In some slices the object reaches the edge of what the probe saw; those slices say nothing about the "
     "part beyond it.",
     "Keep reconstruction.planes: observed (the default for images) so that the unseen part is not cut away; "
     "to see all of the object, widen the field of view or add a sweep over the rest."},
    {"repeats slices[", "The same image at the same pose is listed twice; it counts once.",
     "Remove the repeated entry from slices.yaml."},
    {"frames skipped",
     "Some frames of the recording had an image or tracking status other than OK and were left out.",
     "Nothing if they are few. Many skipped frames mean tracking dropouts: check the tracker's line of sight."},
    {"unknown key", "slices.yaml holds a key xsect does not know; it was ignored.",
     "Check its spelling against the slices.yaml format in docs/inputs.md."},
    {"has no area", "A contour of the input is a point or a segment; it was dropped.",
     "Check the contour file where the warning says."},
    {"observe one plane", "Several slices lie on the same plane; their sections were combined into one.",
     "Nothing if the plane was acquired twice on purpose; otherwise check these slices' poses."},
    {"disagree with the slices they cross",
     "Some slices disagree with the slices they cross far more than the others do: probable tracking or "
     "segmentation failures.",
     "Look at these slices' frames below. Correct the poses (conformity.pose_correction: rigid) or leave the "
     "slices out (conformity.drop_flagged: true)."},
    {"pose correction: slice",
     "Pose correction found slices whose disagreement is far above the others'; they were corrected against "
     "their neighbours without moving them.",
     "Look at these slices' frames below: a segmentation failure there is best fixed in the segmentation "
     "(or by removing the slice from the input); a tracking glitch is what the correction already absorbed."},
    {"no crossing constrains",
     "Some motions of some slices are not pinned by any crossing slice (all their crossings are parallel, or "
     "there are none); those motions were left uncorrected.",
     "Add slices that cross them at another angle if their poses matter."},
    {"did not converge",
     "Pose correction stopped before the corrections settled; they may be partial.",
     "Look for outlier slices (flagged above) and check the tracking; a smaller conformity.pose_sigma_mm keeps "
     "corrections smaller."},
    {"disagree by more than conformity.max_correction_mm",
     "Some pairs of slices disagree by more than conformity enforcement may correct; they were left as they were.",
     "If the disagreement is a tracking error, correct the poses first (conformity.pose_correction: rigid); "
     "otherwise raise conformity.max_correction_mm."},
    {"were not compared",
     "Edits of the sections moved contours where slices were not compared (nearly parallel slices, or no "
     "section on the line).",
     "Usually harmless; conformity.json lists the pairs."},
    {"not simple polygons", "Some sections are not simple polygons (they touch themselves) and were not edited.",
     "Check the segmentation of these slices (segmentation.open_radius_px, segmentation.close_radius_px)."},
    {"edits the union of the labels", "Conformity enforcement edits the union of the materials only.",
     "Nothing; each material keeps its segmented sections."},
    {"group the sections differently",
     "The voxel solid connects the sections differently from the thesis' connectivity graph: the voxels are "
     "too coarse where sections come close.",
     "Use a smaller reconstruction.voxel_size_mm; check the sampling verdict."},
    {"Shepard's surface joins the sections differently",
     "The smooth surface connects the sections differently from the method's graph in some cells.",
     "Compare with mesh_unsmoothed; set smoothing.method: level_set to keep the method's connectivity."},
    {"has sections but no voxel", "A material is too thin for the voxel size and has no mesh.",
     "Use a smaller reconstruction.voxel_size_mm."},
    {"has sections but method 3 joins none of them",
     "Method 3 joins sections of different planes through a cell; this material's sections face no other "
     "section of it, so it has no solid and no mesh.",
     "Add slices that cut this material again, or use reconstruction.method: nearest_plane or section_voronoi."},
    {"the voxelisation of method 3's solid",
     "Method 3's solid is a union of tetrahedra; parts of it are thinner than a voxel, so the voxel volume "
     "(labels.nrrd, the connectivity checks, the smoothing) has another topology than the mesh.",
     "Nothing if the mesh is what you need; for a faithful label volume use a smaller "
     "reconstruction.voxel_size_mm."},
    {"mesh.stl keeps no vertex indices",
     "Method 3's solid has pieces that touch at single points; its mesh keeps them apart with copies of "
     "those vertices, which an STL file cannot keep.",
     "Add ply or obj to output.mesh and read that file for the topology report.json states."},
    {"method 3's solid holds no voxel centre",
     "Method 3's solid is thinner than a voxel everywhere: the voxel outputs are empty, the mesh is not.",
     "Use a smaller reconstruction.voxel_size_mm."},
    {"materials (segmentation.method: labels",
     "Every grey value was taken as a material label: the images are probably grey images, not label maps.",
     "Use segmentation.method: otsu or threshold for grey images."},
    {"no section found in any slice", "Segmentation found nothing in any slice.",
     "Check segmentation.threshold (or use segmentation.method: otsu) and the images."},
};

}  // namespace

WarningAdvice warningAdvice(const std::string& warning) {
  for (const Rule& r : kRules)
    if (warning.find(r.phrase) != std::string::npos) return {warning, r.meaning, r.action};
  return {warning, "", ""};
}

std::string warningsHtml(const std::vector<std::string>& warnings) {
  if (warnings.empty()) return "";
  std::string html;
  for (const std::string& w : warnings) {
    const WarningAdvice a = warningAdvice(w);
    html += "<div class=\"warning\">";
    if (!a.meaning.empty()) html += "<span class=\"what\">" + htmlEscape(a.meaning) + "</span>";
    if (!a.action.empty()) html += "<span class=\"todo\"><b>What to do:</b> " + htmlEscape(a.action) + "</span>";
    html += "<span class=\"hint\">" + htmlEscape(w) + "</span></div>\n";
  }
  return html;
}

}  // namespace xsect

// report.html without a browser (issue 21; tests/test_report_browser.cpp opens it in Chromium):
// its figures are report.json's, its 3D view holds the mesh (decimated within budget, close to the
// original), the graph is Graphviz's drawing of graph.json's components or their table, the frames
// are drawn for image inputs, `xsect eval` fills its accuracy block, and nothing in it is fetched
// from the network.
#include <gtest/gtest.h>

#include <cstring>
#include <regex>

#include "geometry/meshing/mesh_decimation.h"
#include "geometry/meshing/mesh_topology.h"
#include "io/mesh_io.h"
#include "report/page/report_page.h"
#include "mesh_fixtures.h"
#include "phantom_runs.h"
#include "report/run/section_graph.h"
#include "report/run/slice_plots.h"
#include "report/run/warning_advice.h"

namespace xsect {
namespace {

using test::readJson;
using test::slurp;
namespace fs = std::filesystem;

/// The text of the element with id `id` (no nested elements).
std::string textOfId(const std::string& html, const std::string& id) {
  const std::regex re("id=\"" + id + "\"[^>]*>([^<]*)<");
  std::smatch m;
  return std::regex_search(html, m, re) ? m[1].str() : std::string("(missing)");
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

std::string joined(const nlohmann::json& a) {
  std::string s;
  for (const auto& v : a) s += (s.empty() ? "" : " ") + v.dump();
  return s;
}

/// The view's JSON block of a page.
nlohmann::json viewData(const std::string& html) {
  const std::string open = "<script type=\"application/json\" id=\"view-data\">";
  const std::size_t a = html.find(open), b = html.find("</script>", a);
  if (a == std::string::npos || b == std::string::npos) return nullptr;
  return nlohmann::json::parse(html.substr(a + open.size(), b - a - open.size()));
}

std::size_t base64Bytes(const std::string& b64) {
  std::size_t pad = 0;
  while (pad < b64.size() && b64[b64.size() - 1 - pad] == '=') ++pad;
  return b64.size() / 4 * 3 - pad;
}

/// What the checks of one run read: its folder, report.json and report.html.
struct TorusRun {
  fs::path dir;
  nlohmann::json report;
  std::string html;
};

void checkFiguresAreThoseOfReportJson(const TorusRun& run) {
  const nlohmann::json& r = run.report;
  EXPECT_EQ(textOfId(run.html, "verdict"), r["sampling"]["verdict"].get<std::string>());
  EXPECT_EQ(textOfId(run.html, "betti"), joined(r["betti"]));
  EXPECT_EQ(textOfId(run.html, "confidence"), r["topology"]["confidence"]["level"].get<std::string>());
  EXPECT_EQ(textOfId(run.html, "mesh-triangles"), r["counts"]["mesh_triangles"].dump());
  EXPECT_EQ(textOfId(run.html, "slices-used"), r["counts"]["slices_used"].dump());
}

void checkViewHoldsTheWholeMeshAndEverySlice(const TorusRun& run) {
  const nlohmann::json view = viewData(run.html);
  ASSERT_FALSE(view.is_null());
  const auto triangles = (run.report)["counts"]["mesh_triangles"].get<std::size_t>();
  const auto vertices = (run.report)["counts"]["mesh_vertices"].get<std::size_t>();
  ASSERT_LT(triangles, 150000u);  // below the view's budget: not decimated
  EXPECT_EQ(view["mesh"]["triangles_shown"].get<std::size_t>(), triangles);
  EXPECT_EQ(base64Bytes(view["mesh"]["indices"]), triangles * 3 * 4);
  EXPECT_EQ(base64Bytes(view["mesh"]["positions"]), vertices * 3 * 4);
  EXPECT_EQ(base64Bytes(view["mesh"]["verdict"]), vertices);
  EXPECT_EQ(view["slices"]["total"].get<int>(), (run.report)["counts"]["slices_used"].get<int>());
  EXPECT_EQ(base64Bytes(view["slices"]["quads"]), view["slices"]["shown"].get<std::size_t>() * 12 * 4);
  EXPECT_GT(base64Bytes(view["contours"]["segments"]), 0u);
  // Per drawn plane its rectangle and its count of contour segments, so that the page can show a
  // few planes with their own contours: every rectangle once, every segment counted once.
  const auto& planeQuads = view["slices"]["plane_quads"];
  const auto& planeSegments = view["contours"]["plane_segments"];
  ASSERT_EQ(planeQuads.size(), view["slices"]["shown"].get<std::size_t>());
  ASSERT_EQ(planeSegments.size(), planeQuads.size());
  std::size_t segments = 0;
  for (std::size_t p = 0; p < planeQuads.size(); ++p) {
    EXPECT_EQ(planeQuads[p].get<int>(), int(p));  // every torus slice has its rectangle, in order
    segments += planeSegments[p].get<std::size_t>();
  }
  EXPECT_EQ(segments * 6 * 4, base64Bytes(view["contours"]["segments"]));
  EXPECT_EQ(segments * 2, base64Bytes(view["contours"]["labels"]));
  // The view's bounds hold the torus (R = 12, r = 4 mm): about 32 mm across.
  const auto& lo = view["bounds"][0];
  const auto& hi = view["bounds"][1];
  for (int a = 0; a < 3; ++a) EXPECT_GT(hi[a].get<double>() - lo[a].get<double>(), 8.0);
}

/// The bytes of a base64 text.
std::string unbase64(const std::string& b64) {
  std::string out;
  int bits = 0;
  unsigned acc = 0;
  for (const char c : b64) {
    const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const char* p = c ? std::strchr(digits, c) : nullptr;
    if (!p) break;
    acc = (acc << 6) | unsigned(p - digits);
    if ((bits += 6) >= 8) out += char((acc >> (bits -= 8)) & 255);
  }
  return out;
}

/// Per verdict (0 satisfied, 1 violated, 2 undetermined), the mesh vertices painted with it.
std::array<int, 3> verdictCounts(const nlohmann::json& view) {
  std::array<int, 3> n{0, 0, 0};
  for (const char v : unbase64(view["mesh"]["verdict"])) ++n.at(std::size_t(std::uint8_t(v)));
  return n;
}

void checkSamplingColoursAreTheCellsVerdicts(const TorusRun& run) {
  // Violated cells and none satisfied (report.json): no vertex is painted satisfied, some violated.
  const nlohmann::json& cells = (run.report)["sampling"]["cells"];
  ASSERT_EQ(cells["satisfied"].get<int>(), 0);
  ASSERT_GT(cells["violated"].get<int>(), 0);
  const auto n = verdictCounts(viewData(run.html));
  EXPECT_EQ(n[0], 0);
  EXPECT_GT(n[1], 0);
}

TEST(ReportPage, MethodTwoGraphAndSatisfiedColours) {
  // Method 2 with a known reach: the page's graph is G' (report.json graph.components) and, with
  // no cell violated, no vertex is painted violated.
  const fs::path dir = test::phantom("report-m2", slurp(fs::path(XSECT_SOURCE_DIR) / "configs/phantoms/torus-multiaxial.yaml"));
  const nlohmann::json r = test::run(dir, "r", "--set reconstruction.method=section_voronoi --set sampling.reach_mm=3");
  const std::string html = slurp(dir / "r/report.html");
  const std::size_t g = html.find("<section id=\"graph\">");
  ASSERT_NE(g, std::string::npos);
  EXPECT_NE(html.find(std::to_string(r["graph"]["components"].get<int>()) + " connected component(s)", g), std::string::npos);
  EXPECT_NE(html.find("graph G′ (method 2)", g), std::string::npos);
  const auto n = verdictCounts(viewData(html));
  if (r["sampling"]["cells"]["violated"].get<int>() == 0) EXPECT_EQ(n[1], 0);
  if (r["sampling"]["cells"]["satisfied"].get<int>() > 0) EXPECT_GT(n[0], 0);
  fs::remove_all(dir);
}

void checkHoldsThePlotsTheGraphAndTheFrames(const TorusRun& run) {
  const std::string& h = run.html;
  const std::size_t plots = h.find("<section id=\"slice-plots\">"), graph = h.find("<section id=\"graph\">"),
                    frames = h.find("<section id=\"frames\">"), after = h.find("<section id=\"timings\">");
  ASSERT_TRUE(plots != std::string::npos && graph != std::string::npos && frames != std::string::npos && after != std::string::npos);
  EXPECT_GE(count(h.substr(plots, graph - plots), "<svg"), 1u);
  // 36 sections, one component (report.json graph.components), 177 pairs: too dense to draw
  // readably, the component is listed.
  const std::string g = h.substr(graph, frames - graph);
  EXPECT_NE(g.find("graph-fallback"), std::string::npos);
  EXPECT_NE(g.find("<td class=\"num\">" + std::to_string((run.report)["counts"]["sections"].get<int>()) + "</td>"),
            std::string::npos);
  EXPECT_NE(g.find(std::to_string((run.report)["graph"]["components"].get<int>()) + " connected component(s)"), std::string::npos);
  EXPECT_GE(count(h.substr(frames, after - frames), "<img"), 1u);
  EXPECT_NE(h.find("src=\"data:image/png;base64,"), std::string::npos);
}

void checkNothingComesFromTheNetwork(const TorusRun& run) {
  EXPECT_FALSE(std::regex_search(run.html, std::regex("(src|href)\\s*=\\s*[\"']?(https?:)?//")));
  EXPECT_EQ(run.html.find("<link"), std::string::npos);
  EXPECT_LT(run.html.size(), 10u << 20);
}

void checkWarningsSayWhatToDo(const TorusRun& run) {
  // The torus's run has no warning: the page has no warnings section (nothing to show is left out).
  EXPECT_TRUE((run.report)["warnings"].empty()) << (run.report)["warnings"];
  EXPECT_EQ(run.html.find("<section id=\"warnings\">"), std::string::npos);
  // With warnings, each says what to do.
  const std::string html = warningsHtml({"2 slice(s) disagree with the slices they cross by 3 mm or more",
                                         "label 3 has sections but no voxel at 0.5 mm: no mesh for it"});
  EXPECT_EQ(count(html, "What to do:"), 2u);
  EXPECT_TRUE(warningsHtml({}).empty());
}

TEST(ReportPage, PlotsWithNothingToShowAreLeftOut) {
  // Two slices that agree exactly (disagreement 0 everywhere): no plot, not one drawn flat at zero.
  nlohmann::ordered_json conformity;
  conformity["summary"] = {{"flagged_above_mm", 3.0}};
  conformity["slices"] = nlohmann::ordered_json::array();
  for (int i = 0; i < 2; ++i)
    conformity["slices"].push_back({{"slice", i}, {"before", {{"median_mismatch_mm", 0.0}, {"pairs", 1}}}});
  EXPECT_EQ(slicePlotsHtml(conformity), "");
  // One slice off by 0.2 mm: the plot is there.
  conformity["slices"][1]["before"]["median_mismatch_mm"] = 0.2;
  EXPECT_NE(slicePlotsHtml(conformity).find("<svg"), std::string::npos);
  // No slice measured: nothing.
  EXPECT_EQ(slicePlotsHtml(nlohmann::ordered_json::object()), "");
}

void checkEvalAddsItsFiguresToThePage(const TorusRun& run) {
  ASSERT_NE(run.html.find("No accuracy yet"), std::string::npos);
  const nlohmann::json e = test::eval(run.dir, "r");
  const std::string page = slurp(run.dir / "r/report.html");
  EXPECT_EQ(page.find("No accuracy yet"), std::string::npos);
  const std::regex re("data-key=\"hausdorff_mm\">([0-9.e+-]+) mm<");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(page, m, re));
  EXPECT_NEAR(std::stod(m[1].str()), e["hausdorff_mm"].get<double>(), 6e-3 * e["hausdorff_mm"].get<double>());  // 3 significant digits
  // The rest of the page is untouched.
  EXPECT_EQ(page.substr(0, page.find("<!--xsect-eval-begin-->")), run.html.substr(0, run.html.find("<!--xsect-eval-begin-->")));
  // A second evaluation replaces the block rather than adding another.
  test::eval(run.dir, "r");
  EXPECT_EQ(count(slurp(run.dir / "r/report.html"), "id=\"accuracy-table\""), 1u);
}

TEST(ReportPage, EvalOfAMeshWithoutAPageWritesNoPage) {
  const fs::path dir = test::freshDir("report-no-page");
  const TriangleMesh sphere = test::icosphere(10, 3);
  writeMesh((dir / "m.ply").string(), sphere);
  const auto r = test::runXsect("eval --mesh " + (dir / "m.ply").string() + " --reference " + (dir / "m.ply").string() +
                                " --json " + (dir / "e.json").string() + " --quiet");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(fs::exists(dir / "report.html"));
  fs::remove_all(dir);
}

TEST(ReportPage, AccuracyBlockIsReplacedNotDuplicated) {
  ReportPage page;
  page.title = "t <&>";
  const std::string html = reportPageHtml(page);
  EXPECT_NE(html.find("<title>t &lt;&amp;&gt;</title>"), std::string::npos);
  const std::string once = withReportPageEval(html, "<p>A</p>");
  const std::string twice = withReportPageEval(once, "<p>B</p>");
  EXPECT_EQ(count(twice, "<p>A</p>"), 0u);
  EXPECT_EQ(count(twice, "<p>B</p>"), 1u);
  EXPECT_THROW(withReportPageEval("<html></html>", "x"), std::invalid_argument);
}

TEST(ReportPage, ScriptDataCannotCloseItsScript) {
  ReportPage page;
  page.view_json = R"({"title":"</script><script>alert(1)</script>"})";
  const std::string html = reportPageHtml(page);
  const std::size_t a = html.find("id=\"view-data\">");
  ASSERT_NE(a, std::string::npos);
  const std::string block = html.substr(a, html.find("</script>", a) - a);
  EXPECT_NE(block.find("<\\/script>"), std::string::npos);
  EXPECT_NE(block.find("alert(1)<\\/script>\"}"), std::string::npos);  // the whole JSON inside its block
}

TEST(ReportPage, DecimationKeepsTheShapeWithinBudget) {
  for (const int levels : {5, 6}) {  // 20 480 and 81 920 triangles
    const TriangleMesh sphere = test::icosphere(10, levels);
    for (const std::size_t budget : {std::size_t(2000), std::size_t(8000)}) {
      const TriangleMesh d = decimatedMesh(sphere, budget);
      EXPECT_LE(d.triangles.size(), budget);
      EXPECT_GE(d.triangles.size(), budget / 4) << "far fewer triangles than the budget allows";
      double worst = 0;
      for (const auto& v : d.vertices) worst = std::max(worst, std::abs(double(v.norm()) - 10.0));
      EXPECT_LT(worst, 0.5) << "vertices stay within 5% of the radius of the sphere";
      for (const auto& t : d.triangles)
        for (const auto i : t) ASSERT_LT(i, d.vertices.size());
    }
  }
  const TriangleMesh small = test::icosphere(10, 2);
  EXPECT_EQ(decimatedMesh(small, 100000).triangles, small.triangles);  // under budget: unchanged
  EXPECT_THROW(decimatedMesh(small, 3), std::invalid_argument);
}

TEST(ReportPage, GraphComponentsAndFallback) {
  // Two components: sections 0-1-2 and 3-4; a self-loop and an out-of-range edge are ignored.
  SectionGraph g;
  g.method = "nearest_plane";
  for (int i = 0; i < 5; ++i) g.nodes.push_back({{"id", i}, {"slice", i}, {"section", 0}, {"label", 1}, {"area_mm2", 1.0}});
  for (const auto& [a, b] : std::vector<std::pair<int, int>>{{0, 1}, {1, 2}, {1, 0}, {3, 4}, {2, 2}, {4, 9}})
    g.edges.push_back({a, b, 0});
  const std::string table = sectionGraphHtml(g, 2);  // above max_nodes: the table
  EXPECT_NE(table.find("graph-fallback"), std::string::npos);
  EXPECT_NE(table.find("3 pairs joined"), std::string::npos);
  EXPECT_NE(table.find("2 connected component(s)"), std::string::npos);
  EXPECT_NE(table.find("<td class=\"num\">3</td><td>0 – 2</td>"), std::string::npos);
  EXPECT_NE(table.find("<td class=\"num\">2</td><td>3 – 4</td>"), std::string::npos);
  if (std::system("command -v dot >/dev/null 2>&1") != 0) GTEST_SKIP() << "Graphviz (dot) is not installed";
  const std::string drawn = sectionGraphHtml(g, 250);
  EXPECT_EQ(count(drawn, "class=\"node\""), 5u);
  EXPECT_EQ(count(drawn, "class=\"edge\""), 3u);
  EXPECT_EQ(drawn.find("graph-fallback"), std::string::npos);
  EXPECT_EQ(drawn.find("<?xml"), std::string::npos);  // inline SVG, no declaration
}

TEST(ReportPage, EveryWarningOfTheStagesHasAdvice) {
  // One warning of each kind the stages emit, in their words.
  for (const std::string w : {
           "open ends: slices 0, 6 hold sections beyond every other slice's, where the object is cut open",
           "only one plane holds sections (slice 0): the shape across it is unknown",
           "3 slice(s) have a section touching the edge of the image or field of view (the object is not fully in view), e.g. slice 1",
           "slices[3] (a.png) repeats slices[1] (the same image at the same pose): merged",
           "2 of 40 frames skipped (1 with an image status, 1 with a transform status other than OK): the others are reconstructed",
           "2 slice(s) disagree with the slices they cross by 3 mm or more",
           "pose correction: no crossing constrains some motions of slice 4",
           "the connectivity graph and the voxel solid group the sections differently (1 pairs joined by the graph only, 0 by the voxels only, 0 sections not located)",
           "label 3 has sections but no voxel at 0.5 mm: no mesh for it",
           "no section found in any slice"}) {
    const WarningAdvice a = warningAdvice(w);
    EXPECT_FALSE(a.meaning.empty()) << w;
    EXPECT_FALSE(a.action.empty()) << w;
  }
  EXPECT_TRUE(warningAdvice("something new").action.empty());
  EXPECT_NE(warningsHtml({"x < y"}).find("x &lt; y"), std::string::npos);
}


// One run of the torus phantom read by every check (a run per check would cost ctest a run each).
TEST(ReportPage, ThePageOfATorusRun) {
  TorusRun run;
  run.dir = test::phantom("report-page", slurp(fs::path(XSECT_SOURCE_DIR) / "configs/phantoms/torus-multiaxial.yaml"));
  run.report = test::run(run.dir, "r", "");
  run.html = slurp(run.dir / "r/report.html");
  { SCOPED_TRACE("FiguresAreThoseOfReportJson"); checkFiguresAreThoseOfReportJson(run); }
  { SCOPED_TRACE("ViewHoldsTheWholeMeshAndEverySlice"); checkViewHoldsTheWholeMeshAndEverySlice(run); }
  { SCOPED_TRACE("SamplingColoursAreTheCellsVerdicts"); checkSamplingColoursAreTheCellsVerdicts(run); }
  { SCOPED_TRACE("HoldsThePlotsTheGraphAndTheFrames"); checkHoldsThePlotsTheGraphAndTheFrames(run); }
  { SCOPED_TRACE("NothingComesFromTheNetwork"); checkNothingComesFromTheNetwork(run); }
  { SCOPED_TRACE("WarningsSayWhatToDo"); checkWarningsSayWhatToDo(run); }
  { SCOPED_TRACE("EvalAddsItsFiguresToThePage"); checkEvalAddsItsFiguresToThePage(run); }  // last: it edits the page
  fs::remove_all(run.dir);
}

}  // namespace
}  // namespace xsect

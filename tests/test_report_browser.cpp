// Real-browser acceptance of report.html (issue 21). Headless Chromium (Debian `chromium`, WebGL
// through its bundled SwiftShader) opens the report of a small phantom run offline (file://, DNS
// and proxy dead, every request recorded in a NetLog) and this proves: no uncaught error and no
// console.error (the page's data-errors counter and Chromium's console log on stderr); no request
// leaves the page and no src/href/url() points to the network; the 3D view drew something in its
// centre (screenshot: pixels there differ from the declared clear colour, which shows elsewhere in
// the canvas) and the mesh spans at least half of the view's width; the graph and the frames are
// inline and every plot shown has something to show; the verdict, Betti numbers, triangle and
// slice counts equal report.json's and the sentence under the headline is report.json's
// in_plain_words. The page is the demo's (configs/phantoms/torus-demo.yaml, scripts/demo.sh), whose
// run has no warning. A control page in the same test, whose WebGL canvas is only cleared and which
// requests the network and throws, must trip every detector. Chromium comes from
// scripts/install-deps.sh --browser; without it the test skips, saying so (it never installs
// anything). Slow steps (two Chromium runs, 5-11 s each on 2 busy cores) are marked SLOW; the whole
// test takes 15-20 s there. On failure its folder (screenshots, DOMs, logs) is kept.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "cli.h"

namespace fs = std::filesystem;
using namespace xsect::test;

namespace {

// The window a newcomer's laptop shows the page in (issue 54: the demo's report at 1400x900).
constexpr int kWindowW = 1400, kWindowH = 900;

int shell(const std::string& cmd) {
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

bool chromiumOnPath() { return shell("command -v chromium >/dev/null 2>&1") == 0; }

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct BrowserRun {
  int code = -1;
  std::string dom;   // --dump-dom: the DOM after the page's scripts ran
  std::string err;   // Chromium's log, with the page's console messages ("CONSOLE" lines)
  fs::path png;      // --screenshot of the viewport at scroll 0
  fs::path netlog;   // every URL request Chromium made (--log-net-log)
  double seconds = 0;
};

/// SLOW (3-10 s): opens `page` in headless Chromium once, dumping the DOM and taking a screenshot
/// of the 1400x900 viewport after the virtual time budget (both from the same page instance). Offline: host names resolve
/// to nothing and the proxy is a closed port; the NetLog still records each attempt.
BrowserRun openInChromium(const fs::path& page, const fs::path& work, const std::string& tag,
                          const std::string& fragment = "") {
  BrowserRun r;
  r.png = work / (tag + ".png");
  r.netlog = work / (tag + "-netlog.json");
  const fs::path dom = work / (tag + "-dom.html"), err = work / (tag + "-stderr.txt");
  const std::string cmd =
      // Not ctest's GLIBC_TUNABLES (set for xsect, CMakeLists.txt): with glibc.malloc.hugetlb=1
      // SwiftShader's Vulkan fails to initialise and the page gets no WebGL.
      "env -u GLIBC_TUNABLES timeout -k 5 120 chromium --headless --no-sandbox --disable-gpu-sandbox"
      // WebGL in software. (--use-gl=swiftshader no longer works with Chromium 156: the GPU process
      // exits, the WebGL context is lost and the canvas stays black.)
      " --enable-unsafe-swiftshader --use-angle=swiftshader"
      " --window-size=" + std::to_string(kWindowW) + "," + std::to_string(kWindowH) +
      " --force-device-scale-factor=1 --hide-scrollbars"
      " --user-data-dir=" + (work / ("profile-" + tag)).string() +
      " --no-first-run --no-default-browser-check --disable-background-networking --disable-component-update"
      " --host-resolver-rules='MAP * ~NOTFOUND' --proxy-server=127.0.0.1:9"
      " --log-net-log=" + r.netlog.string() +
      " --enable-logging=stderr --v=0"
      " --virtual-time-budget=5000"
      " --dump-dom --screenshot=" + r.png.string() +
      " 'file://" + page.string() + fragment + "' >" + dom.string() + " 2>" + err.string();
  const auto t0 = std::chrono::steady_clock::now();
  r.code = shell(cmd);
  r.seconds = secondsSince(t0);
  std::cout << "[ timing ] chromium " << tag << ": " << r.seconds << " s\n";
  r.dom = slurp(dom);
  r.err = slurp(err);
  return r;
}

/// The page's console messages that are uncaught errors (Chromium logs every console message at
/// INFO level whatever its level, so console.error itself is only seen by the page's counter).
std::vector<std::string> uncaughtErrors(const std::string& log) {
  std::vector<std::string> out;
  std::istringstream in(log);
  for (std::string line; std::getline(in, line);)
    if (line.find("CONSOLE") != std::string::npos && line.find("Uncaught") != std::string::npos) out.push_back(line);
  return out;
}

std::string consoleLines(const std::string& log) {
  std::string out;
  std::istringstream in(log);
  for (std::string line; std::getline(in, line);)
    if (line.find("CONSOLE") != std::string::npos) out += line + "\n";
  return out;
}

/// URLs the page itself requested, from Chromium's NetLog (the browser's own background requests
/// carry the initiator "not an origin"; a file:// page's carry "null").
std::vector<std::string> pageRequests(const fs::path& netlog, std::string* error) {
  std::vector<std::string> urls;
  try {
    const auto j = nlohmann::json::parse(slurp(netlog));
    const int startJob = j.at("constants").at("logEventTypes").at("URL_REQUEST_START_JOB").get<int>();
    for (const auto& e : j.at("events")) {
      if (e.value("type", -1) != startJob || !e.contains("params") || !e["params"].contains("url")) continue;
      const auto& p = e["params"];  // the job's start (its end holds only net_error)
      if (p.value("initiator", std::string()) != "not an origin") urls.push_back(p["url"].get<std::string>());
    }
  } catch (const std::exception& ex) {
    *error = std::string("unreadable NetLog ") + netlog.string() + ": " + ex.what();
  }
  return urls;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

/// src=, href= and url( values of the HTML that point to the network (http:, https:, //host).
/// three.js's code holds URLs in strings and comments; only these attribute-like forms load.
std::vector<std::string> networkReferences(const std::string& html) {
  const std::string s = lower(html);
  std::vector<std::string> found;
  auto valueAt = [&](size_t q) {  // skips blanks, an optional quote, blanks
    while (q < s.size() && std::isspace(static_cast<unsigned char>(s[q]))) ++q;
    if (q < s.size() && (s[q] == '"' || s[q] == '\'')) ++q;
    while (q < s.size() && std::isspace(static_cast<unsigned char>(s[q]))) ++q;
    return q;
  };
  auto isNetwork = [&](size_t q) {
    return s.compare(q, 7, "http://") == 0 || s.compare(q, 8, "https://") == 0 || s.compare(q, 2, "//") == 0;
  };
  for (const std::string name : {"src", "href"}) {
    for (size_t p = s.find(name); p != std::string::npos; p = s.find(name, p + 1)) {
      const char before = p > 0 ? s[p - 1] : ' ';
      const bool attributeStart = std::isspace(static_cast<unsigned char>(before)) || before == ':' ||
                                  before == '"' || before == '\'';
      if (!attributeStart) continue;
      size_t q = p + name.size();
      while (q < s.size() && std::isspace(static_cast<unsigned char>(s[q]))) ++q;
      if (q >= s.size() || s[q] != '=') continue;
      q = valueAt(q + 1);
      if (isNetwork(q)) found.push_back(html.substr(p, 80));
    }
  }
  for (size_t p = s.find("url("); p != std::string::npos; p = s.find("url(", p + 1))
    if (isNetwork(valueAt(p + 4))) found.push_back(html.substr(p, 80));
  return found;
}

/// The value of attribute `name` on <body>; "<absent>" when missing.
std::string bodyAttribute(const std::string& dom, const std::string& name) {
  const size_t b = dom.find("<body");
  if (b == std::string::npos) return "<no body>";
  const std::string tag = dom.substr(b, dom.find('>', b) - b);
  const std::string key = " " + name + "=\"";
  const size_t k = tag.find(key);
  if (k == std::string::npos) return "<absent>";
  const size_t v = k + key.size();
  return tag.substr(v, tag.find('"', v) - v);
}

/// Text of the element with id `id` (up to its first child tag), trimmed; "<absent>" when missing.
std::string textOf(const std::string& dom, const std::string& id) {
  const size_t k = dom.find("id=\"" + id + "\"");
  if (k == std::string::npos) return "<absent>";
  const size_t open = dom.find('>', k);
  std::string t = dom.substr(open + 1, dom.find('<', open) - open - 1);
  const auto notSpace = [](unsigned char c) { return !std::isspace(c); };
  t.erase(t.begin(), std::find_if(t.begin(), t.end(), notSpace));
  t.erase(std::find_if(t.rbegin(), t.rend(), notSpace).base(), t.end());
  return t;
}

/// The inside of the <section> whose id is `id` (nested sections included); empty when missing.
std::string sectionOf(const std::string& dom, const std::string& id) {
  for (size_t k = dom.find("id=\"" + id + "\""); k != std::string::npos; k = dom.find("id=\"" + id + "\"", k + 1)) {
    const size_t tag = dom.rfind('<', k);
    if (tag == std::string::npos || dom.compare(tag, 8, "<section") != 0) continue;
    const size_t start = dom.find('>', k) + 1;
    int depth = 1;
    for (size_t p = start; p < dom.size(); ++p) {
      if (dom.compare(p, 8, "<section") == 0) ++depth;
      if (dom.compare(p, 10, "</section>") == 0 && --depth == 0) return dom.substr(start, p - start);
    }
  }
  return "";
}

/// The src of every <img> in `html` ("" for an <img> without one).
std::vector<std::string> imageSources(const std::string& html) {
  std::vector<std::string> srcs;
  for (size_t p = html.find("<img"); p != std::string::npos; p = html.find("<img", p + 1)) {
    const std::string tag = html.substr(p, html.find('>', p) - p);  // serialised: '>' in values is &gt;
    const size_t k = tag.find(" src=\"");
    srcs.push_back(k == std::string::npos ? "" : tag.substr(k + 6, tag.find('"', k + 6) - k - 6));
  }
  return srcs;
}

size_t occurrences(const std::string& s, const std::string& what) {
  size_t n = 0;
  for (size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

/// What the screenshot shows of the canvas: the share of pixels of the central window (half the
/// canvas's width and height) that differ from the clear colour by more than 24 in some channel,
/// and the share of the visible canvas that is the clear colour (within 6). A canvas counts as
/// drawn when both are at least 5%: something in the centre, and the clear colour around it (a
/// black or foreign canvas, as when WebGL fails, shows no clear colour).
struct CanvasPixels {
  bool ok = false;  // rect and colour readable, central window inside the screenshot
  std::string why;
  double centreDiffers = 0, backgroundShare = 0;
  double drawnWidthShare = 0;  // the span of the canvas's columns holding drawn pixels, over its width
  bool meshVisible() const { return ok && centreDiffers >= 0.05 && backgroundShare >= 0.05; }
};

CanvasPixels measureCanvas(const fs::path& png, const std::string& rectText, const std::string& background) {
  CanvasPixels m;
  auto unreadable = [&m](const std::string& why) { m.why = why; return m; };
  const cv::Mat shot = cv::imread(png.string(), cv::IMREAD_COLOR);
  if (shot.empty()) return unreadable("no screenshot " + png.string());
  if (shot.cols != kWindowW || shot.rows != kWindowH)
    return unreadable("screenshot is " + std::to_string(shot.cols) + "x" + std::to_string(shot.rows));
  int x = 0, y = 0, w = 0, h = 0;
  unsigned rgb = 0;
  if (std::sscanf(rectText.c_str(), "%d %d %d %d", &x, &y, &w, &h) != 4 || w < 100 || h < 100)
    return unreadable("data-canvas-rect \"" + rectText + "\" is not a canvas of at least 100x100");
  if (background.size() != 7 || background[0] != '#' || std::sscanf(background.c_str() + 1, "%6x", &rgb) != 1)
    return unreadable("data-background \"" + background + "\" is not #rrggbb");
  const cv::Rect canvas(x, y, w, h), centre(x + w / 4, y + h / 4, w / 2, h / 2), all(0, 0, shot.cols, shot.rows);
  if ((centre & all) != centre) return unreadable("the canvas's centre is outside the viewport");
  const int bgB = rgb & 0xff, bgG = (rgb >> 8) & 0xff, bgR = (rgb >> 16) & 0xff;  // OpenCV: BGR
  auto distance = [&](const cv::Vec3b& c) {
    return std::max({std::abs(c[0] - bgB), std::abs(c[1] - bgG), std::abs(c[2] - bgR)});
  };
  auto share = [&](const cv::Rect& r, auto pred) {
    size_t n = 0;
    for (int j = r.y; j < r.y + r.height; ++j)
      for (int i = r.x; i < r.x + r.width; ++i) n += pred(distance(shot.at<cv::Vec3b>(j, i)));
    return double(n) / double(r.area());
  };
  m.centreDiffers = share(centre, [](int d) { return d > 24; });
  const cv::Rect visible = canvas & all;
  int first = -1, last = -1;
  for (int i = visible.x; i < visible.x + visible.width; ++i)
    for (int j = visible.y + 2; j < visible.y + visible.height - 2; ++j)  // inside the border
      if (distance(shot.at<cv::Vec3b>(j, i)) > 24) {
        if (first < 0) first = i;
        last = i;
        break;
      }
  // The border's columns (1 px each side) do not count.
  if (first >= 0 && last - first > 4) m.drawnWidthShare = double(last - first) / double(visible.width);
  m.backgroundShare = share(canvas & all, [](int d) { return d <= 6; });
  m.ok = true;
  return m;
}

/// A page that follows report.html's contract but whose WebGL canvas is only cleared; it also
/// loads an image from the network and throws after the view is "ready".
const char* kControlPage = R"(<!DOCTYPE html><html><head><meta charset="utf-8"></head>
<body style="margin:0;background:#ffffff" data-errors="0">
<canvas id="view" width="640" height="480" style="position:absolute;left:200px;top:100px"></canvas>
<img src="http://xsect-control.invalid/x.png" width="1" height="1">
<script>
var c = document.getElementById('view');
var gl = c.getContext('webgl', {preserveDrawingBuffer: true});
if (gl) { gl.clearColor(0x20 / 255, 0x40 / 255, 0x60 / 255, 1); gl.clear(gl.COLOR_BUFFER_BIT); }
requestAnimationFrame(function () {
  document.body.setAttribute('data-view-ready', gl ? '1' : '0');
  document.body.setAttribute('data-canvas-rect', '200 100 640 480');
  document.body.setAttribute('data-background', '#204060');
  setTimeout(function () { xsectControlUndefined(); }, 0);
});
</script></body></html>
)";

TEST(ReportBrowser, PhantomReportOpensOfflineDrawsTheMeshAndMatchesReportJson) {
  const fs::path dir = freshDir("browser");
  const auto t0 = std::chrono::steady_clock::now();
  // The demo's phantom (30 slices, torus) and its run: under a second each.
  auto r = runXsect("phantom " + std::string(XSECT_SOURCE_DIR) + "/configs/phantoms/torus-demo.yaml --out " +
                    (dir / "ph").string() + " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  r = runXsect("run " + (dir / "ph/config.yaml").string() + " --out " + (dir / "r").string() + " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  std::cout << "[ timing ] phantom + run: " << secondsSince(t0) << " s\n";
  const fs::path page = dir / "r/report.html";
  ASSERT_TRUE(fs::is_regular_file(page)) << "xsect run wrote no " << page;
  const auto report = nlohmann::json::parse(slurp(dir / "r/report.json"));
  EXPECT_TRUE(report.at("warnings").empty()) << "a warning on the demo's happy path: " << report.at("warnings");

  // Static: nothing in the file points to the network (checked before any browser is needed).
  const std::string html = slurp(page);
  const auto refs = networkReferences(html);
  EXPECT_TRUE(refs.empty()) << "report.html refers to the network: " << refs.front();

  if (!chromiumOnPath()) {
    fs::remove_all(dir);
    GTEST_SKIP() << "real-browser test of report.html skipped: Chromium (Debian package chromium) is not installed; "
                    "scripts/install-deps.sh --browser installs it";
  }

  // Control first: every detector below must see what is wrong with this page.
  writeFile(dir / "control/control.html", kControlPage);
  BrowserRun control = openInChromium(dir / "control/control.html", dir / "control", "control");  // SLOW
  // Under ctest --parallel 2 the control once came back without its WebGL view (the virtual time
  // budget spent before SwiftShader was up; alone it passes): one retry before calling the browser
  // unusable.
  if (control.code == 0 && bodyAttribute(control.dom, "data-view-ready") != "1")
    control = openInChromium(dir / "control/control.html", dir / "control", "control-retry");
  ASSERT_EQ(control.code, 0) << "chromium failed on the control page:\n" << control.err;
  ASSERT_EQ(bodyAttribute(control.dom, "data-view-ready"), "1") << "no WebGL in headless Chromium:\n" << control.err;
  const CanvasPixels blank = measureCanvas(control.png, bodyAttribute(control.dom, "data-canvas-rect"),
                                           bodyAttribute(control.dom, "data-background"));
  ASSERT_TRUE(blank.ok) << blank.why;
  EXPECT_FALSE(blank.meshVisible()) << "a cleared canvas passed for a drawn one: centre differs "
                                    << blank.centreDiffers;
  EXPECT_GT(blank.backgroundShare, 0.9) << "the clear colour is not where data-canvas-rect says";
  EXPECT_FALSE(uncaughtErrors(control.err).empty()) << "Chromium's log does not show uncaught errors:\n" << control.err;
  std::string netError;
  EXPECT_FALSE(pageRequests(control.netlog, &netError).empty())
      << "the NetLog does not show page requests " << netError;
  EXPECT_FALSE(networkReferences(kControlPage).empty());

  // The report.
  // #mesh-only hides the translucent slices and contours: what the canvas shows is the mesh.
  const BrowserRun run = openInChromium(page, dir / "r", "report", "#mesh-only");  // SLOW
  ASSERT_EQ(run.code, 0) << "chromium failed (exit " << run.code << ", 124 = timeout):\n" << run.err;
  EXPECT_EQ(bodyAttribute(run.dom, "data-errors"), "0") << "console:\n" << consoleLines(run.err);
  const auto uncaught = uncaughtErrors(run.err);
  EXPECT_TRUE(uncaught.empty()) << uncaught.front();
  EXPECT_EQ(bodyAttribute(run.dom, "data-view-ready"), "1") << "the 3D view never drew; console:\n"
                                                            << consoleLines(run.err);
  const auto requests = pageRequests(run.netlog, &netError);
  EXPECT_TRUE(netError.empty()) << netError;
  EXPECT_TRUE(requests.empty()) << "report.html requested " << requests.front();

  const CanvasPixels view = measureCanvas(run.png, bodyAttribute(run.dom, "data-canvas-rect"),
                                          bodyAttribute(run.dom, "data-background"));
  std::cout << "[ pixels ] canvas centre differing from the clear colour: " << view.centreDiffers
            << ", canvas showing the clear colour: " << view.backgroundShare << " (control: " << blank.centreDiffers
            << ", " << blank.backgroundShare << ")\n";
  EXPECT_TRUE(view.ok) << view.why;
  EXPECT_GE(view.centreDiffers, 0.05) << "the 3D canvas is blank in its centre (screenshot " << run.png << ")";
  EXPECT_GE(view.backgroundShare, 0.05) << "the clear colour " << bodyAttribute(run.dom, "data-background")
                                        << " shows nowhere in the canvas: it failed to draw or the rect is wrong ("
                                        << run.png << ")";

  EXPECT_GE(view.drawnWidthShare, 0.5) << "the mesh spans " << view.drawnWidthShare
                                       << " of the view's width, not half (screenshot " << run.png << ")";
  std::cout << "[ pixels ] the mesh spans " << view.drawnWidthShare << " of the view's width\n";

  // Every plot shown has a line or a point to show (plots with nothing are left out of the page).
  const std::string plots = sectionOf(run.dom, "slice-plots"), graph = sectionOf(run.dom, "graph"),
                    frames = sectionOf(run.dom, "frames");
  for (size_t p = plots.find("<svg"); p != std::string::npos; p = plots.find("<svg", p + 1)) {
    const std::string svg = plots.substr(p, plots.find("</svg>", p) - p);
    // A data line (class "line") or a data point (a dot with its tooltip); the legend's are neither.
    EXPECT_TRUE(svg.find("class=\"line\"") != std::string::npos || svg.find("</title></circle>") != std::string::npos)
        << "an empty plot: " << svg.substr(0, 200);
  }
  EXPECT_TRUE(graph.find("<svg") != std::string::npos || graph.find("graph-fallback") != std::string::npos)
      << "#graph holds neither an inline SVG nor .graph-fallback";
  const auto frameSources = imageSources(frames);
  EXPECT_GE(frameSources.size(), 1u) << "no frame in #frames";
  for (const auto& src : frameSources)
    EXPECT_EQ(src.rfind("data:image/png;base64,", 0), 0u) << "a frame is not an inline PNG: " << src.substr(0, 80);

  // The figures are report.json's.
  EXPECT_EQ(textOf(run.dom, "verdict"), report.at("sampling").at("verdict").get<std::string>());
  // The plain sentence under the headline (entities aside, the DOM's text is report.json's).
  const std::string meaning = textOf(run.dom, "verdict-meaning");
  EXPECT_GT(meaning.size(), 40u) << "no sentence under the headline";
  EXPECT_EQ(meaning.substr(0, 30), report.at("in_plain_words").get<std::string>().substr(0, 30));
  std::string betti;
  for (const auto& b : report.at("betti")) betti += (betti.empty() ? "" : " ") + std::to_string(b.get<int>());
  EXPECT_EQ(textOf(run.dom, "betti"), betti);
  const auto& counts = report.at("counts");
  EXPECT_EQ(textOf(run.dom, "mesh-triangles"), std::to_string(counts.at("mesh_triangles").get<long long>()));
  EXPECT_EQ(textOf(run.dom, "slices-used"), std::to_string(counts.at("slices_used").get<long long>()));

  std::cout << "[ timing ] whole test: " << secondsSince(t0) << " s\n";
  if (!HasFailure()) fs::remove_all(dir);  // kept on failure: screenshots, DOM, Chromium's log
}

}  // namespace

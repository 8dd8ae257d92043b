// The documentation a user reads is true of the tool (issue 54): the README's quick start, copied
// verbatim into an empty folder with images that fit its poses, runs and writes the outputs the
// README lists; docs/configuration.md lists exactly the keys a configuration accepts; every link
// between README.md and docs/ resolves inside the repository, which needs no file outside it;
// `xsect --version` says the version.
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>

#include "cli.h"
#include "io/run_config.h"

namespace fs = std::filesystem;
using namespace xsect;

namespace {

const fs::path kSource = XSECT_SOURCE_DIR;

/// The fenced block after each `<!-- quick-start: NAME -->` marker of `markdown`, by NAME.
std::map<std::string, std::string> quickStartFiles(const std::string& markdown) {
  std::map<std::string, std::string> files;
  const std::regex marker("<!-- quick-start: ([^ ]+) -->\\n```[a-z]*\\n");
  for (auto it = std::sregex_iterator(markdown.begin(), markdown.end(), marker); it != std::sregex_iterator(); ++it) {
    const std::size_t start = std::size_t(it->position(0) + it->length(0));
    const std::size_t end = markdown.find("```", start);
    if (end != std::string::npos) files[(*it)[1]] = markdown.substr(start, end - start);
  }
  return files;
}

/// The image a slice of slices.yaml shows of a sphere of radius 6 mm at the origin: 200x200 pixels
/// (the README's), 255 inside, 0 outside, pixel (i, j) at image_to_world · (i, j, 0, 1).
cv::Mat sphereImage(const YAML::Node& pose) {
  cv::Mat image(200, 200, CV_8U, cv::Scalar(0));
  for (int j = 0; j < 200; ++j)
    for (int i = 0; i < 200; ++i) {
      double world[3];
      for (int r = 0; r < 3; ++r)
        world[r] = pose[r][0].as<double>() * i + pose[r][1].as<double>() * j + pose[r][3].as<double>();
      if (world[0] * world[0] + world[1] * world[1] + world[2] * world[2] < 36) image.at<unsigned char>(j, i) = 255;
    }
  return image;
}

/// The names in backticks of README's sentence "Every run writes `a`, `b` ... into the output folder".
std::vector<std::string> outputsEveryRunWrites(const std::string& readme) {
  const std::size_t from = readme.find("Every run writes");
  const std::size_t to = readme.find("into the output folder", from);
  std::vector<std::string> names;
  if (from == std::string::npos || to == std::string::npos) return names;
  const std::string sentence = readme.substr(from, to - from);
  // File names, not keys (`output.mesh`).
  const std::regex name("`([a-z_]+\\.(ply|stl|obj|nrrd|json|dot|html|yaml|vdb))`");
  for (auto it = std::sregex_iterator(sentence.begin(), sentence.end(), name); it != std::sregex_iterator(); ++it)
    names.push_back((*it)[1]);
  return names;
}

}  // namespace

TEST(UserDocumentation, TheReadmesQuickStartRunsAsWritten) {
  const std::string readme = test::slurp(kSource / "README.md");
  const auto files = quickStartFiles(readme);
  ASSERT_EQ(files.size(), 2u) << "README.md's quick start names slices.yaml and config.yaml";
  const fs::path dir = test::freshDir("quick-start");
  for (const auto& [name, text] : files) test::writeFile(dir / name, text);  // verbatim
  // The images the poses describe: a sphere of radius 6 mm cut by each slice.
  const YAML::Node slices = YAML::LoadFile((dir / "slices.yaml").string())["slices"];
  ASSERT_GE(slices.size(), 3u);
  for (const YAML::Node& s : slices) {
    fs::create_directories((dir / s["image"].as<std::string>()).parent_path());
    ASSERT_TRUE(cv::imwrite((dir / s["image"].as<std::string>()).string(), sphereImage(s["image_to_world"])));
  }
  const auto check = test::runXsect("check " + (dir / "config.yaml").string());
  ASSERT_EQ(check.code, 0) << check.err;
  EXPECT_NE(check.out.find("valid"), std::string::npos) << check.out;
  const auto run = test::runXsect("run " + (dir / "config.yaml").string() + " --quiet");
  ASSERT_EQ(run.code, 0) << run.err;
  const std::vector<std::string> outputs = outputsEveryRunWrites(readme);
  ASSERT_GE(outputs.size(), 8u) << "README.md says which files every run writes";
  for (const std::string& o : outputs) EXPECT_TRUE(fs::is_regular_file(dir / "out" / o)) << o << " is not in out/";
  EXPECT_TRUE(fs::is_regular_file(dir / "out/mesh.stl")) << "output.mesh: [ply, stl]";
  const auto report = nlohmann::json::parse(test::slurp(dir / "out/report.json"));
  EXPECT_EQ(report["betti"], nlohmann::json::array({1, 0, 0}));
  EXPECT_TRUE(report["warnings"].empty()) << "a warning on the quick start's happy path: " << report["warnings"];
  // The README's third command: any key on the command line, another folder.
  const auto m2 = test::runXsect("run " + (dir / "config.yaml").string() +
                                 " --set reconstruction.method=section_voronoi --out " + (dir / "out-m2").string() + " --quiet");
  EXPECT_EQ(m2.code, 0) << m2.err;
  EXPECT_TRUE(fs::is_regular_file(dir / "out-m2/report.json"));
  fs::remove_all(dir);
}

TEST(UserDocumentation, TheConfigurationReferenceListsEveryKeyAndNoOther) {
  const std::string doc = test::slurp(kSource / "docs/configuration.md");
  ASSERT_FALSE(doc.empty()) << "docs/configuration.md is missing";
  std::set<std::string> documented;
  // "## `section`" headings and the reference tables' rows "| `section.key` | ...".
  const std::regex heading("\\n## `([a-z_]+)`"), row("\\n\\| `([a-z_]+(\\.[a-z0-9_]+)+)` \\|");
  for (const std::regex& re : {heading, row})
    for (auto it = std::sregex_iterator(doc.begin(), doc.end(), re); it != std::sregex_iterator(); ++it)
      documented.insert((*it)[1]);
  const std::set<std::string>& accepted = runConfigKeys();
  for (const std::string& k : accepted) EXPECT_TRUE(documented.count(k)) << "docs/configuration.md does not list " << k;
  for (const std::string& k : documented) EXPECT_TRUE(accepted.count(k)) << "docs/configuration.md lists " << k
                                                                           << ", which no configuration accepts";
}

TEST(UserDocumentation, TheReadmeIsShortAndEveryLinkStaysInTheRepository) {
  const std::string readme = test::slurp(kSource / "README.md");
  EXPECT_LE(std::count(readme.begin(), readme.end(), '\n'), 250) << "README.md is for users: details go to docs/";
  std::vector<fs::path> pages{kSource / "README.md"};
  for (const auto& e : fs::directory_iterator(kSource / "docs"))
    if (e.path().extension() == ".md") pages.push_back(e.path());
  ASSERT_GE(pages.size(), 8u);
  const std::regex link("\\]\\(([^)#]+)(#[^)]*)?\\)");
  for (const fs::path& page : pages) {
    const std::string text = test::slurp(page);
    // A user's clone holds the repository alone.
    EXPECT_EQ(text.find("../shared"), std::string::npos) << page;
    EXPECT_EQ(text.find("GUIDE.md"), std::string::npos) << page;
    for (auto it = std::sregex_iterator(text.begin(), text.end(), link); it != std::sregex_iterator(); ++it) {
      const std::string target = (*it)[1];
      if (target.rfind("http", 0) == 0) continue;
      EXPECT_TRUE(fs::exists(page.parent_path() / target)) << page.filename() << " links to " << target
                                                           << ", which the repository does not hold";
    }
  }
}

TEST(UserDocumentation, VersionIsPrinted) {
  const auto r = test::runXsect("--version");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out.rfind(std::string("xsect ") + XSECT_VERSION + "\n", 0), 0u) << r.out;
}

// Acceptance of several materials through the command line (phantom -> run): a torus split
// through its axis into two C-shaped halves, labels 1 and 2, by methods 1 and 2: each label's
// Betti numbers are the truth's, the labelled volumes are disjoint and their union is the
// one-material reconstruction of the union, voxel for voxel.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "io/label_volume_file.h"
#include "phantom_runs.h"

namespace fs = std::filesystem;
using json = nlohmann::json;
using namespace xsect;

TEST(AcceptanceMaterials, TwoTouchingSolids) {
  // A torus split through its axis into two C-shaped halves, labels 1 and 2.
  const fs::path dir = test::freshDir("labels");
  test::writeFile(dir / "spec.yaml", R"(seed: 3
shape:
  kind: torus
  params: {major_radius: 12, minor_radius: 4}
  rotation_deg: [20, 10, 0]
  label_split: {normal: [1, 0, 0]}
pattern: {kind: multiaxial, count: 10}
image: {pixel_mm: 0.25}
config: {reconstruction: {voxel_size_mm: 0.4}}
)");
  const auto r = test::runXsect("phantom " + (dir / "spec.yaml").string() + " --out " + (dir / "ph").string() + " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  const YAML::Node truth = YAML::LoadFile((dir / "ph/truth.yaml").string());
  for (const std::string method : {"nearest_plane", "section_voronoi"}) {
    SCOPED_TRACE(method);
    const std::string m = " --set reconstruction.method=" + method;
    const json labels = test::run(dir, "l-" + method, m);
    const json merged = test::run(dir, "u-" + method, m + " --set segmentation.merge_labels=true");
    EXPECT_EQ(labels["betti"], json(truth["betti"].as<std::vector<int>>()));
    ASSERT_EQ(labels["materials"].size(), 2u);
    for (const json& mat : labels["materials"]) {
      const int L = mat["label"];
      EXPECT_EQ(mat["betti"], json(truth["labels"][L]["betti"].as<std::vector<int>>())) << "label " << L;
      EXPECT_TRUE(mat["watertight"].get<bool>());
      EXPECT_TRUE(fs::exists(dir / ("l-" + method) / ("mesh_label_" + std::to_string(L) + ".ply")));
    }
    EXPECT_TRUE(merged["materials"].empty());
    // One label per voxel (disjoint by the format), the union of the labels equal to the
    // one-material solid voxel by voxel.
    const LabelVolume a = readLabelVolumeNrrd((dir / ("l-" + method) / "labels.nrrd").string());
    const LabelVolume b = readLabelVolumeNrrd((dir / ("u-" + method) / "labels.nrrd").string());
    ASSERT_EQ(a.labels.size(), b.labels.size());
    ASSERT_EQ(a.grid.dims, b.grid.dims);
    std::int64_t n1 = 0, n2 = 0, differ = 0;
    for (std::size_t q = 0; q < a.labels.size(); ++q) {
      n1 += a.labels[q] == 1;
      n2 += a.labels[q] == 2;
      EXPECT_LE(a.labels[q], 2);
      EXPECT_LE(b.labels[q], 1);
      differ += (a.labels[q] != 0) != (b.labels[q] != 0);
    }
    EXPECT_EQ(differ, 0);
    EXPECT_EQ(n1, labels["materials"][0]["voxels"].get<std::int64_t>());
    EXPECT_EQ(n2, labels["materials"][1]["voxels"].get<std::int64_t>());
    EXPECT_NEAR(double(n1) / double(n2), 1.0, 0.05);  // two halves of the same torus
  }
  fs::remove_all(dir);
}

// Dataset export of a scenario's scans: the F3Loc map and poses agree with each other, every
// scan folder reads back, the TUM RGB-D side files list every view.
#include <gtest/gtest.h>

#include "common/scratch_dir.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>
#include <vector>

#include "floorcast/core/file_io.hpp"
#include "floorcast/core/image_io.hpp"
#include "floorcast/core/scan_io.hpp"
#include "floorcast/core/trajectory_io.hpp"
#include "floorcast/scenarios/dataset_export.hpp"

namespace floorcast {
namespace {

namespace fs = std::filesystem;

std::vector<std::vector<double>> numbers_per_line(const std::string& path) {
  std::vector<std::vector<double>> out;
  std::istringstream in(read_text_file(path));
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream f(line);
    std::vector<double> v;
    double x;
    while (f >> x) v.push_back(x);
    out.push_back(v);
  }
  return out;
}

TEST(DatasetExport, F3LocMapPosesDepthsAndScanFolders) {
  const std::string yaml =
      "name: export-test\n"
      "buildings: [floorplans/buildings/two_rooms.json]\n"
      "sampling: {count: 2, seed: 4, clearance_m: 0.5}\n"
      "observation: {source: scan, sensor: mono, setting: partial, seed: 2}\n"
      "matchers: {kernel: {matcher: kernel}}\n";
  const Scenario s = parse_scenario(yaml, "export-test.yaml", FLOORCAST_SOURCE_DIR, FLOORCAST_SOURCE_DIR);
  const test::ScratchDir scratch;
  const fs::path out = scratch.path() / "export";
  DatasetExportOptions o;
  o.map_resolution_m = 0.02;
  const DatasetExportReport r = export_scenario_dataset(s, out.string(), o);
  EXPECT_EQ(r.scans, 2u);
  EXPECT_EQ(r.images, 6u);  // partial: 3 views per scan
  // F3Loc reads the cell folder's split.yaml: every building a test scene.
  EXPECT_NE(read_text_file((out / "c000" / "split.yaml").string()).find("test:\n  - two_rooms"), std::string::npos);
  const fs::path root = out / "c000" / "two_rooms";
  const cv::Mat map = read_image((root / "map.png").string());
  ASSERT_EQ(map.type(), CV_8U);
  EXPECT_GT(cv::countNonZero(map == 0), 100);    // walls
  EXPECT_GT(cv::countNonZero(map == 255), 1000);  // free space
  // map.yaml's transform and poses.txt put every camera on a free pixel of map.png; 4 frames per
  // scan (F3Loc's L = 3 sources and the reference).
  const auto poses = numbers_per_line((root / "poses.txt").string());
  ASSERT_EQ(poses.size(), 8u);
  for (const auto& p : poses) {
    ASSERT_EQ(p.size(), 3u);
    const int col = static_cast<int>(std::floor(p[0] / 0.02 + map.cols / 2.0));
    const int row = static_cast<int>(std::floor(p[1] / 0.02 + map.rows / 2.0));
    ASSERT_TRUE(col >= 0 && row >= 0 && col < map.cols && row < map.rows);
    EXPECT_EQ(map.at<std::uint8_t>(row, col), 255);
  }
  for (const auto& [file, columns] : {std::pair<const char*, std::size_t>{"depth40.txt", 40}, {"depth160.txt", 160},
                                       {"depth40_sensor.txt", 40}}) {
    const auto depths = numbers_per_line((root / file).string());
    ASSERT_EQ(depths.size(), 8u) << file;
    for (const auto& d : depths) {
      ASSERT_EQ(d.size(), columns) << file;
      for (double v : d) EXPECT_TRUE(v >= 0.0 && v < 20.0) << file << " " << v;
    }
  }
  // The sensor saw about what the plan says (mono: scale error and noise; two_rooms has no clutter).
  const auto gt = numbers_per_line((root / "depth40.txt").string());
  const auto sensed = numbers_per_line((root / "depth40_sensor.txt").string());
  std::vector<double> ratios;
  for (std::size_t i = 0; i < gt.size(); ++i)
    for (std::size_t c = 0; c < 40; ++c)
      if (sensed[i][c] > 0.0) ratios.push_back(sensed[i][c] / gt[i][c]);
  ASSERT_GT(ratios.size(), 100u);
  std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
  EXPECT_NEAR(ratios[ratios.size() / 2], 1.0, 0.25);
  for (int n = 0; n < 2; ++n)
    for (int l = 0; l < 4; ++l) {
      char grid[32], seq[32];
      std::snprintf(grid, sizeof grid, "rgb/%05d-%d.png", n, l);
      std::snprintf(seq, sizeof seq, "rgb/%05d.png", n * 4 + l);
      EXPECT_EQ(read_image((root / grid).string()).type(), CV_8UC3) << grid;
      EXPECT_EQ(read_text_file((root / grid).string()), read_text_file((root / seq).string())) << seq;
    }
  // The scenario's camera (108 deg, pitched) differs from F3Loc's: said.
  bool noted = false;
  for (const std::string& n : r.notes) noted = noted || n.find("F_W = 3/8") != std::string::npos;
  EXPECT_TRUE(noted);
  EXPECT_EQ(load_tum((root / "scans.tum").string()).size(), 2u);
  // Each scan folder reads back (with colour) and carries labels, intrinsics, TUM RGB-D lists.
  for (const char* p : {"p0000", "p0001"}) {
    const fs::path sdir = root / "scans" / p;
    ScanLoadOptions lo;
    lo.load_rgb = true;
    const Scan scan = load_scan(sdir.string(), lo);
    ASSERT_EQ(scan.views.size(), 3u);
    EXPECT_FALSE(scan.views[0].rgb.empty());
    const cv::Mat label = read_image((sdir / "view_000_label.png").string());
    EXPECT_EQ(label.type(), CV_8U);
    EXPECT_GT(cv::countNonZero(label == 0), 100);  // walls are seen
    EXPECT_EQ(numbers_per_line((sdir / "groundtruth.txt").string()).size(), 3u);
    EXPECT_EQ(numbers_per_line((sdir / "groundtruth.txt").string())[0].size(), 8u);
    const nlohmann::json intr = nlohmann::json::parse(read_text_file((sdir / "intrinsics.json").string()));
    EXPECT_EQ(intr.size(), 3u);
    EXPECT_DOUBLE_EQ(intr[0]["K"][0][0].get<double>(), scan.views[0].intrinsics.fx_px);
    EXPECT_TRUE(fs::exists(sdir / "truth.json"));
    EXPECT_TRUE(fs::exists(sdir / "rgb.txt"));
    // Ground-truth depth beside the sensor's: same size, 16-bit, close to it where both see.
    const cv::Mat d_gt = read_image((sdir / "view_000_depth_gt.png").string());
    const cv::Mat d_sensor = read_image((sdir / "view_000_depth.png").string());
    EXPECT_EQ(d_gt.type(), CV_16U);
    EXPECT_EQ(d_gt.size(), d_sensor.size());
    EXPECT_GT(cv::countNonZero(d_gt), d_gt.total() / 2);
  }
  EXPECT_TRUE(fs::exists(out / "README.md"));
  fs::remove_all(out);
}

TEST(DatasetExport, PerfectObservationScenarioHasNothingToExport) {
  const std::string yaml =
      "name: perfect\nbuildings: [floorplans/buildings/two_rooms.json]\nsampling: {count: 1}\n"
      "matchers: {kernel: {matcher: kernel}}\n";
  const Scenario s = parse_scenario(yaml, "perfect.yaml", FLOORCAST_SOURCE_DIR, FLOORCAST_SOURCE_DIR);
  const test::ScratchDir scratch;
  EXPECT_THROW(export_scenario_dataset(s, scratch.file("export"), {}), InputError);
}

}  // namespace
}  // namespace floorcast

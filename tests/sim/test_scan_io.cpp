// Scan folders: round trip and validation.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <functional>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "floorcast/floorplans/io.hpp"
#include "floorcast/sim/scan_io.hpp"
#include "floorcast/sim/scan_sim.hpp"
#include "sim_test_util.hpp"

namespace floorcast {
namespace {

namespace fs = std::filesystem;

class ScanIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("floorcast_scan_io_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static Scan make_scan(const std::string& preset) {
    static const RayScene scene(extrude_plan(test::feature_plan()));
    ScanParams p = scan_preset(preset);
    p.geometry.width_px /= 4;
    p.geometry.height_px /= 4;
    p.seed = 1234567890123ULL;
    p.setting = ScanSetting::kPartial;
    p.center_view = 1;
    return simulate_scan(scene, {2.0, 2.2, 0.7}, p);
  }

  void expect_error(const std::string& fragment) {
    try {
      (void)load_scan(dir_.string());
      FAIL() << "expected an error containing: " << fragment;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  }

  void edit_json(const std::function<void(nlohmann::json&)>& edit) {
    const std::string path = (dir_ / "scan.json").string();
    nlohmann::json j = nlohmann::json::parse(read_text_file(path));
    edit(j);
    write_text_file_atomic(path, j.dump(2));
  }

  fs::path dir_;
};

TEST_F(ScanIo, RoundTripLidarAndMono) {
  for (const char* preset : {"lidar", "mono"}) {
    const Scan s = make_scan(preset);
    save_scan(dir_.string(), s);
    const Scan l = load_scan(dir_.string());
    ASSERT_EQ(l.views.size(), s.views.size());
    EXPECT_EQ(l.sensor, s.sensor);
    EXPECT_EQ(l.setting, "partial");
    EXPECT_EQ(l.params.seed, 1234567890123ULL);
    EXPECT_EQ(l.params.center_view, 1);
    EXPECT_EQ(l.params.sensor.kind, s.params.sensor.kind);
    EXPECT_EQ(l.params.sensor.max_range_m, s.params.sensor.max_range_m);
    EXPECT_EQ(l.params.sensor.mono.scale_sigma_ln, s.params.sensor.mono.scale_sigma_ln);
    EXPECT_EQ(l.params.sensor.lidar.sigma_quad_per_m, s.params.sensor.lidar.sigma_quad_per_m);
    EXPECT_EQ(l.params.geometry.width_px, s.params.geometry.width_px);
    EXPECT_EQ(l.truth.T_world_scan.yaw_rad, s.truth.T_world_scan.yaw_rad);
    EXPECT_EQ(l.truth.view_depth_scale, s.truth.view_depth_scale);
    for (std::size_t k = 0; k < s.views.size(); ++k) {
      const DepthView& a = s.views[k];
      const DepthView& b = l.views[k];
      EXPECT_EQ(a.view_index, b.view_index);
      EXPECT_EQ(a.intrinsics.fx_px, b.intrinsics.fx_px);
      EXPECT_EQ(a.intrinsics.cy_px, b.intrinsics.cy_px);
      EXPECT_TRUE(a.T_scan_camera.matrix() == b.T_scan_camera.matrix());
      EXPECT_TRUE(s.truth.T_scan_camera_true[k].matrix() == l.truth.T_scan_camera_true[k].matrix());
      ASSERT_EQ(b.depth_m.type(), CV_32F);
      cv::Mat diff;
      cv::absdiff(a.depth_m, b.depth_m, diff);
      double max_diff = 0.0;
      cv::minMaxLoc(diff, nullptr, &max_diff);
      EXPECT_LE(max_diff, 0.0005 + 1e-6);
      EXPECT_EQ(cv::countNonZero(a.depth_m > 0), cv::countNonZero(b.depth_m > 0));
      EXPECT_EQ(cv::countNonZero(a.glass_mask != b.glass_mask), 0);
      EXPECT_EQ(a.confidence.empty(), b.confidence.empty());
      if (!a.confidence.empty()) {
        EXPECT_EQ(cv::countNonZero(a.confidence != b.confidence), 0);
      }
    }
    fs::remove_all(dir_);
  }
}

TEST_F(ScanIo, DepthIsMillimetrePng) {
  const Scan s = make_scan("perfect");
  save_scan(dir_.string(), s);
  const cv::Mat mm = cv::imread((dir_ / "view_000_depth.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(mm.type(), CV_16U);
  const float d = s.views[0].depth_m.at<float>(10, 10);
  EXPECT_EQ(mm.at<std::uint16_t>(10, 10), static_cast<std::uint16_t>(std::lround(d * 1000.0)));
}

TEST_F(ScanIo, ErrorsNameFileElementAndReason) {
  expect_error("no such directory");
  fs::create_directories(dir_);
  expect_error("scan.json: missing");
  save_scan(dir_.string(), make_scan("lidar"));
  edit_json([](nlohmann::json& j) { j["views"][1]["intrinsics"]["fx_px"] = -3.0; });
  expect_error("views[1].intrinsics.fx_px");
  save_scan(dir_.string(), make_scan("lidar"));
  edit_json([](nlohmann::json& j) { j["views"][0]["T_scan_camera"][0][0] = 2.0; });
  expect_error("not a rotation matrix");
  save_scan(dir_.string(), make_scan("lidar"));
  edit_json([](nlohmann::json& j) { j["params"]["sensor"]["lidar"]["bogus"] = 1; });
  expect_error("params.sensor.lidar.bogus: unknown key");
  save_scan(dir_.string(), make_scan("lidar"));
  edit_json([](nlohmann::json& j) { j["format_version"] = 7; });
  expect_error("format_version");
  save_scan(dir_.string(), make_scan("lidar"));
  edit_json([](nlohmann::json& j) { j["views"][0]["depth"] = "../elsewhere.png"; });
  expect_error("plain file name");
  save_scan(dir_.string(), make_scan("lidar"));
  fs::remove(dir_ / "view_002_glass.png");
  expect_error("view_002_glass.png: glass mask image missing");
  save_scan(dir_.string(), make_scan("lidar"));
  cv::imwrite((dir_ / "view_001_depth.png").string(), cv::Mat::zeros(5, 5, CV_16U));
  expect_error("view_001_depth.png: depth image is 5x5");
  save_scan(dir_.string(), make_scan("lidar"));
  cv::imwrite((dir_ / "view_000_depth.png").string(), cv::Mat::zeros(48, 64, CV_8U));
  expect_error("16-bit");
  save_scan(dir_.string(), make_scan("lidar"));
  write_text_file_atomic((dir_ / "scan.json").string(), "{ not json");
  expect_error("malformed JSON");
}

}  // namespace
}  // namespace floorcast

namespace floorcast {
namespace {

TEST(ScanParamsJson, OverridesChangeOnlyTheirKeysAndRefuseUnknownOnes) {
  ScanParams p = scan_preset("mono");
  const nlohmann::json before = scan_params_to_json(p);
  apply_scan_overrides(p, nlohmann::json::parse(R"({"sensor": {"mono": {"scale_sigma_ln": 0.2}}, "geometry": {"num_views": 4}})"),
                       "scenario.yaml");
  EXPECT_DOUBLE_EQ(p.sensor.mono.scale_sigma_ln, 0.2);
  EXPECT_EQ(p.geometry.num_views, 4);
  nlohmann::json after = scan_params_to_json(p);
  after["sensor"]["mono"]["scale_sigma_ln"] = before["sensor"]["mono"]["scale_sigma_ln"];
  after["geometry"]["num_views"] = before["geometry"]["num_views"];
  EXPECT_EQ(after, before);
  EXPECT_EQ(scan_params_to_json(scan_params_from_json(scan_params_to_json(p), "x")), scan_params_to_json(p));
  try {
    apply_scan_overrides(p, nlohmann::json::parse(R"({"sensor": {"mono": {"scale_sigma": 0.2}}})"), "scenario.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scenario.yaml: sensor.mono.scale_sigma: unknown scan parameter"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(apply_scan_overrides(p, nlohmann::json::parse(R"({"sensor": {"mono": {"scale_sigma_ln": -1}}})"), "s"),
               InputError);
}

}  // namespace
}  // namespace floorcast

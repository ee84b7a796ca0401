// Scan folders (core) and simulated scan folders (sim): round trip and validation.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <functional>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "floorcast/floorplans/io.hpp"
#include "floorcast/core/scan_io.hpp"
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

  static SimulatedScan make_scan(const std::string& preset) {
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

  void expect_sim_error(const std::string& fragment) {
    try {
      (void)load_simulated_scan(dir_.string());
      FAIL() << "expected an error containing: " << fragment;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  }

  void edit_json(const std::function<void(nlohmann::json&)>& edit, const char* file = "scan.json") {
    const std::string path = (dir_ / file).string();
    nlohmann::json j = nlohmann::json::parse(read_text_file(path));
    edit(j);
    write_text_file_atomic(path, j.dump(2));
  }

  fs::path dir_;
};

TEST_F(ScanIo, RoundTripLidarAndMono) {
  for (const char* preset : {"lidar", "mono"}) {
    const SimulatedScan sim = make_scan(preset);
    save_simulated_scan(dir_.string(), sim);
    const SimulatedScan lsim = load_simulated_scan(dir_.string());
    const Scan& s = sim.scan;
    const Scan& l = lsim.scan;
    ASSERT_EQ(l.views.size(), s.views.size());
    EXPECT_EQ(l.sensor, s.sensor);
    EXPECT_EQ(lsim.params.setting, ScanSetting::kPartial);
    EXPECT_EQ(lsim.params.seed, 1234567890123ULL);
    EXPECT_EQ(lsim.params.center_view, 1);
    EXPECT_EQ(lsim.params.sensor.kind, sim.params.sensor.kind);
    EXPECT_EQ(lsim.params.sensor.max_range_m, sim.params.sensor.max_range_m);
    EXPECT_EQ(lsim.params.sensor.mono.scale_sigma_ln, sim.params.sensor.mono.scale_sigma_ln);
    EXPECT_EQ(lsim.params.sensor.lidar.sigma_quad_per_m, sim.params.sensor.lidar.sigma_quad_per_m);
    EXPECT_EQ(lsim.params.geometry.width_px, sim.params.geometry.width_px);
    EXPECT_EQ(lsim.truth.T_world_scan.yaw_rad, sim.truth.T_world_scan.yaw_rad);
    EXPECT_EQ(lsim.truth.view_depth_scale, sim.truth.view_depth_scale);
    for (std::size_t k = 0; k < s.views.size(); ++k) {
      const DepthView& a = s.views[k];
      const DepthView& b = l.views[k];
      EXPECT_EQ(a.view_index, b.view_index);
      EXPECT_EQ(a.intrinsics.fx_px, b.intrinsics.fx_px);
      EXPECT_EQ(a.intrinsics.cy_px, b.intrinsics.cy_px);
      EXPECT_TRUE(a.T_scan_camera.matrix() == b.T_scan_camera.matrix());
      EXPECT_TRUE(sim.truth.T_scan_camera_true[k].matrix() == lsim.truth.T_scan_camera_true[k].matrix());
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
  const Scan s = make_scan("perfect").scan;
  save_scan(dir_.string(), s);
  const cv::Mat mm = cv::imread((dir_ / "view_000_depth.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(mm.type(), CV_16U);
  const float d = s.views[0].depth_m.at<float>(10, 10);
  EXPECT_EQ(mm.at<std::uint16_t>(10, 10), static_cast<std::uint16_t>(std::lround(d * 1000.0)));
}

TEST_F(ScanIo, ErrorsNameFileElementAndReason) {
  const Scan lidar = make_scan("lidar").scan;
  expect_error("no such directory");
  fs::create_directories(dir_);
  expect_error("scan.json: missing");
  save_scan(dir_.string(), lidar);
  edit_json([](nlohmann::json& j) { j["views"][1]["intrinsics"]["fx_px"] = -3.0; });
  expect_error("views[1].intrinsics.fx_px");
  save_scan(dir_.string(), lidar);
  edit_json([](nlohmann::json& j) { j["views"][0]["T_scan_camera"][0][0] = 2.0; });
  expect_error("not a rotation matrix");
  save_scan(dir_.string(), lidar);
  edit_json([](nlohmann::json& j) { j["format_version"] = 7; });
  expect_error("format_version");
  save_scan(dir_.string(), lidar);
  edit_json([](nlohmann::json& j) { j["views"][0]["depth"] = "../elsewhere.png"; });
  expect_error("plain file name");
  save_scan(dir_.string(), lidar);
  edit_json([](nlohmann::json& j) { j["params"] = nlohmann::json::object(); });
  expect_error("params: unknown key");
  save_scan(dir_.string(), lidar);
  fs::remove(dir_ / "view_002_glass.png");
  expect_error("view_002_glass.png: glass mask image missing");
  save_scan(dir_.string(), lidar);
  cv::imwrite((dir_ / "view_001_depth.png").string(), cv::Mat::zeros(5, 5, CV_16U));
  expect_error("view_001_depth.png: depth image is 5x5");
  save_scan(dir_.string(), lidar);
  cv::imwrite((dir_ / "view_000_depth.png").string(), cv::Mat::zeros(48, 64, CV_8U));
  expect_error("16-bit");
  save_scan(dir_.string(), lidar);
  write_text_file_atomic((dir_ / "scan.json").string(), "{ not json");
  expect_error("malformed JSON");
}

TEST_F(ScanIo, SimulationFileErrorsNameFileElementAndReason) {
  const SimulatedScan sim = make_scan("lidar");
  save_scan(dir_.string(), sim.scan);
  expect_sim_error("not a simulated scan");
  save_simulated_scan(dir_.string(), sim);
  edit_json([](nlohmann::json& j) { j["params"]["sensor"]["lidar"]["bogus"] = 1; }, "simulation.json");
  expect_sim_error("simulation.json: params.sensor.lidar.bogus: unknown key");
  save_simulated_scan(dir_.string(), sim);
  edit_json([](nlohmann::json& j) { j["ground_truth"]["view_depth_scale"] = {1.0}; }, "simulation.json");
  expect_sim_error("ground_truth.view_depth_scale");
  save_simulated_scan(dir_.string(), sim);
  edit_json([](nlohmann::json& j) { j["seed"] = 3; }, "simulation.json");
  expect_sim_error("seed: differs from params.seed");
}

// A scan folder made by anything else (a phone app, a script around a depth network) needs only
// views with intrinsics, poses and depth: no view index, masks, confidence, sensor or simulator
// fields.
TEST_F(ScanIo, SensorOnlyFolderNeedsOnlyViewsIntrinsicsAndPoses) {
  fs::create_directories(dir_);
  cv::Mat mm(4, 6, CV_16U, cv::Scalar(2500));
  mm.at<std::uint16_t>(1, 2) = 0;
  cv::imwrite((dir_ / "a.png").string(), mm);
  cv::imwrite((dir_ / "b.png").string(), mm);
  nlohmann::json j;
  j["format"] = "floorcast-scan";
  j["format_version"] = kScanFormatVersion;
  const nlohmann::json K = {{"width_px", 6}, {"height_px", 4}, {"fx_px", 5.0}, {"fy_px", 5.0}, {"cx_px", 3.0}, {"cy_px", 2.0}};
  const nlohmann::json I = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
  j["views"] = {{{"intrinsics", K}, {"T_scan_camera", I}, {"depth", "a.png"}},
                {{"intrinsics", K}, {"T_scan_camera", I}, {"depth", "b.png"}}};
  write_text_file_atomic((dir_ / "scan.json").string(), j.dump(2));
  const Scan s = load_scan(dir_.string());
  ASSERT_EQ(s.views.size(), 2u);
  EXPECT_EQ(s.views[1].view_index, 1);
  EXPECT_TRUE(s.views[0].glass_mask.empty());
  EXPECT_TRUE(s.views[0].confidence.empty());
  EXPECT_FLOAT_EQ(s.views[0].depth_m.at<float>(0, 0), 2.5f);
  EXPECT_EQ(s.views[0].depth_m.at<float>(1, 2), 0.0f);
}

// Wave-1 folders (scan.json version 1 with the simulator's fields inside) still load.
TEST_F(ScanIo, FoldersFromBeforeTheNetworkShapedMonoModelLoadAsTheFormerModel) {
  const SimulatedScan sim = make_scan("mono");
  save_simulated_scan(dir_.string(), sim);
  EXPECT_EQ(load_simulated_scan(dir_.string()).truth.view_depth_shift_m, sim.truth.view_depth_shift_m);
  EXPECT_EQ(load_simulated_scan(dir_.string()).truth.view_floor_masked, sim.truth.view_floor_masked);
  EXPECT_EQ(load_simulated_scan(dir_.string()).truth.scan_depth_scale, sim.truth.scan_depth_scale);
  // A current file must list every key of the model.
  edit_json([](nlohmann::json& j) { j["params"]["sensor"]["mono"].erase("shift_sigma_m"); }, "simulation.json");
  expect_sim_error("params.sensor.mono.shift_sigma_m: missing");
  // The former files had none of the new keys: they were off.
  edit_json(
      [](nlohmann::json& j) {
        for (const char* k : {"model", "scan_scale_mean_ln", "scan_scale_sigma_ln", "compression_knee_m",
                              "compression_ceiling_m", "edge_bleed_px", "textureless_prob", "textureless_sigma_ln",
                              "no_ground_prob"}) {
          j["params"]["sensor"]["mono"].erase(k);
        }
        for (const char* k : {"scan_depth_scale", "view_depth_shift_m", "view_floor_masked"}) j["ground_truth"].erase(k);
      },
      "simulation.json");
  const SimulatedScan old = load_simulated_scan(dir_.string());
  EXPECT_EQ(old.params.sensor.mono.model, "per_view_lognormal");
  EXPECT_EQ(old.params.sensor.mono.scan_scale_sigma_ln, 0.0);
  EXPECT_EQ(old.params.sensor.mono.shift_sigma_m, 0.0);
  EXPECT_EQ(old.params.sensor.mono.edge_bleed_px, 0);
  EXPECT_EQ(old.params.sensor.mono.textureless_prob, 0.0);
  EXPECT_EQ(old.params.sensor.mono.no_ground_prob, 0.0);
  EXPECT_EQ(old.truth.scan_depth_scale, 1.0);
  EXPECT_EQ(old.truth.view_depth_shift_m, std::vector<double>(sim.scan.views.size(), 0.0));
  EXPECT_EQ(old.truth.view_floor_masked, std::vector<bool>(sim.scan.views.size(), false));
}

TEST_F(ScanIo, VersionOneFoldersStillLoad) {
  const SimulatedScan sim = make_scan("lidar");
  save_simulated_scan(dir_.string(), sim);
  nlohmann::json scan = nlohmann::json::parse(read_text_file((dir_ / "scan.json").string()));
  const nlohmann::json simj = nlohmann::json::parse(read_text_file((dir_ / "simulation.json").string()));
  scan["format_version"] = 1;
  for (const char* k : {"setting", "seed", "ground_truth", "params"}) scan[k] = simj[k];
  write_text_file_atomic((dir_ / "scan.json").string(), scan.dump(2));
  fs::remove(dir_ / "simulation.json");
  EXPECT_EQ(load_scan(dir_.string()).views.size(), sim.scan.views.size());
  const SimulatedScan back = load_simulated_scan(dir_.string());
  EXPECT_EQ(back.params.seed, sim.params.seed);
  EXPECT_EQ(back.truth.view_depth_scale, sim.truth.view_depth_scale);
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

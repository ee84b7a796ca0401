// External matchers: run-time registration, the external program protocol (match/external.hpp)
// with well-behaved and misbehaving programs, and the checks on what they return.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "floorcast/core/depth_io.hpp"
#include "floorcast/core/file_io.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/match/external.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "match_test_plans.hpp"

namespace floorcast {
namespace {

namespace fs = std::filesystem;

std::string folder(const std::string& name) {
  const fs::path p = fs::path(FLOORCAST_TEST_OUT) / "external" / name;
  fs::create_directories(p);
  return p.string();
}

/// A shell script standing in for a user's program; `body` runs with $out = the output folder.
std::string script(const std::string& name, const std::string& body) {
  const std::string path = folder("scripts") + "/" + name + ".sh";
  std::ofstream f(path);
  f << "#!/bin/sh\nout=$(sed -n 's/.*\"output_dir\": \"\\(.*\\)\".*/\\1/p' \"$1\")\n" << body << "\n";
  f.close();
  fs::permissions(path, fs::perms::owner_all);
  return path;
}

std::unique_ptr<Matcher> program(const std::string& script_path, double timeout_s = 20.0) {
  return make_matcher("external", test::asymmetric_floor(),
                      {{"command", {"sh", script_path}}, {"timeout_s", timeout_s}, {"resolution_m", 0.25}, {"yaw_bins", 8}});
}

Observation2D observation() { return PerfectObserver(test::asymmetric_floor()).observe({3.23, 1.61, 0.31}); }

std::string error_of(const Matcher& m) {
  try {
    (void)m.match(observation(), MatchRequest::modes(3));
  } catch (const ExternalMethodError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ExternalProgram, TopKPosesBecomeModesAndASparsePosterior) {
  const auto m = program(script("poses", "printf '{\"poses\": [{\"x_m\": 3.2, \"y_m\": 1.6, \"yaw_deg\": 18, \"score\": 0.5},"
                                          " {\"x_m\": 9.0, \"y_m\": 6.0, \"yaw_deg\": 90, \"score\": 0.9}]}' > $out/top_k.json"));
  EXPECT_EQ(m->name(), "external");
  EXPECT_EQ(m->parameters()["command"][0], "sh");
  MatchResult r = m->match(observation(), MatchRequest::modes(5));
  ASSERT_EQ(r.modes.size(), 2u);
  EXPECT_DOUBLE_EQ(r.modes[0].score, 0.9);  // sorted by score
  EXPECT_DOUBLE_EQ(r.modes[1].x_m, 3.2);
  EXPECT_NEAR(r.modes[1].yaw_rad, deg_to_rad(18.0), 1e-12);
  EXPECT_TRUE(r.posterior.scores.empty());
  r = m->match(observation(), MatchRequest{});
  ASSERT_EQ(r.posterior.num_slices(), 8);
  ASSERT_NO_THROW(r.posterior.check());
  EXPECT_NEAR(r.posterior.total(), 1.4, 1e-6);  // each pose's score in one cell
  const PoseHypothesis best = r.posterior.argmax();
  EXPECT_NEAR(best.x_m, 9.0, 0.125 + 1e-9);
  EXPECT_NEAR(best.yaw_rad, kPi / 2, 1e-9);  // slice 2 of 8 (45 deg steps)
  // Only the best K.
  EXPECT_EQ(m->match(observation(), MatchRequest::modes(1)).modes.size(), 1u);
}

TEST(ExternalProgram, PosteriorOnItsOwnGrid) {
  // A 3 x 4 grid with two orientations, prepared as a file the program copies.
  const std::string dir = folder("own_grid");
  std::vector<float> v(2 * 3 * 4, 0.0f);
  v[1 * 12 + 2 * 4 + 3] = 2.0f;  // yaw 1, row 2, column 3
  write_npy(dir + "/p.npy", {2, 3, 4}, v);
  write_text_file_atomic(dir + "/grid.json", R"({"origin_x_m": 1.0, "origin_y_m": 2.0, "resolution_m": 0.5,
    "width_px": 4, "height_px": 3, "yaw_deg": [0, 90]})");
  const auto m = program(script("own_grid", "cp " + dir + "/p.npy $out/posterior.npy; cp " + dir + "/grid.json $out/"));
  const MatchResult r = m->match(observation(), MatchRequest::modes(3));
  ASSERT_EQ(r.modes.size(), 1u);
  EXPECT_DOUBLE_EQ(r.modes[0].x_m, 1.0 + 3.5 * 0.5);
  EXPECT_DOUBLE_EQ(r.modes[0].y_m, 2.0 + 2.5 * 0.5);
  EXPECT_NEAR(r.modes[0].yaw_rad, kPi / 2, 1e-12);
  EXPECT_EQ(r.grid.width_px, 4);
}

TEST(ExternalProgram, MisbehavingProgramsGiveClearErrors) {
  EXPECT_NE(error_of(*program(script("crash", "echo 'model.pt: no such file' >&2; exit 3"))).find(
                "exited with status 3; its standard error ends:\nmodel.pt: no such file"),
            std::string::npos);
  EXPECT_NE(error_of(*program(script("segv", "kill -SEGV $$"))).find("killed by signal 11"), std::string::npos);
  EXPECT_NE(error_of(*program(script("hang", "sleep 30"), 0.5)).find("did not finish within 0.5 s and was killed"),
            std::string::npos);
  EXPECT_NE(error_of(*program(script("silent", "exit 0"))).find("wrote neither posterior.npy nor top_k.json"),
            std::string::npos);
  // A posterior of the wrong shape for the shared grid (8 yaws x the plan's grid at 0.25 m).
  const std::string dir = folder("shape");
  write_npy(dir + "/p.npy", {8, 3, 4}, std::vector<float>(96, 1.0f));
  const std::string shape = error_of(*program(script("shape", "cp " + dir + "/p.npy $out/posterior.npy")));
  EXPECT_NE(shape.find("posterior.npy has shape (8, 3, 4), the grid (yaw, y, x) is (8, "), std::string::npos) << shape;
  // Negative and non-finite scores, malformed poses.
  write_npy(dir + "/g.npy", {1, 1, 2}, {0.5f, -1.0f});
  write_text_file_atomic(dir + "/grid.json", R"({"origin_x_m": 0, "origin_y_m": 0, "resolution_m": 1, "width_px": 2, "height_px": 1, "yaw_deg": [0]})");
  EXPECT_NE(error_of(*program(script("negative", "cp " + dir + "/g.npy $out/posterior.npy; cp " + dir + "/grid.json $out/")))
                .find("negative score"),
            std::string::npos);
  EXPECT_NE(error_of(*program(script("badpose", "echo '{\"poses\": [{\"x_m\": 1}]}' > $out/top_k.json"))).find("\"y_m\" must be a number"),
            std::string::npos);
  EXPECT_NE(error_of(*program(script("badjson", "echo '{\"poses\": [' > $out/top_k.json"))).find("top_k.json"),
            std::string::npos);
  // The message names the program.
  EXPECT_NE(error_of(*program(script("named", "exit 1"))).find("external matcher `sh "), std::string::npos);
}

TEST(ExternalProgram, ParametersAreCheckedWhereTheyAreWritten) {
  EXPECT_THROW(make_matcher_config("external"), ParameterError);  // no command
  try {
    make_matcher_config("external", {{"command", {"x"}}, {"timeout", 0}});
  } catch (const ParameterError& e) {
    EXPECT_EQ(e.key(), "timeout");
  }
  EXPECT_THROW(make_matcher_config("external", {{"command", "python3 x.py"}}), ParameterError);  // a list
  EXPECT_THROW(make_matcher_config("external", {{"command", {"x"}}, {"params", 3}}), ParameterError);
  const auto c = make_matcher_config("external", {{"command", {"prog"}}, {"params", {{"sigma", 0.3}}}});
  EXPECT_EQ(c->parameters()["params"]["sigma"], 0.3);
  EXPECT_EQ(c->parameters()["timeout_s"], 60.0);
}

TEST(ExternalOutput, ChecksShapesAndValues) {
  PosteriorGrid g;
  g.grid.width_px = 3;
  g.grid.height_px = 2;
  g.grid.resolution_m_per_px = 1.0;
  g.yaw_rad = {0.0, kPi};
  ExternalMatchOutput out;
  out.has_posterior = true;
  out.grid = g;
  out.scores = {cv::Mat::zeros(2, 3, CV_32F), cv::Mat::zeros(2, 3, CV_32F)};
  out.scores[1].at<float>(1, 2) = 4.0f;
  MatchResult r = finish_external_output(out, g, MatchRequest{}, "t");
  ASSERT_EQ(r.modes.size(), 1u);
  EXPECT_EQ(r.modes[0].slice, 1);
  EXPECT_EQ(r.posterior.num_slices(), 2);
  out.scores.pop_back();
  EXPECT_THROW(finish_external_output(out, g, MatchRequest{}, "t"), ExternalMethodError);
  out.scores = {cv::Mat::zeros(2, 3, CV_32F), cv::Mat::zeros(3, 2, CV_32F)};
  EXPECT_THROW(finish_external_output(out, g, MatchRequest{}, "t"), ExternalMethodError);
  out.scores = {cv::Mat::zeros(2, 3, CV_32F), cv::Mat::zeros(2, 3, CV_32F)};
  out.scores[0].at<float>(0, 0) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(finish_external_output(out, g, MatchRequest{}, "t"), ExternalMethodError);
  ExternalMatchOutput poses;
  poses.poses = {{1.0, 1.0, 0.0, 0.0}};
  EXPECT_THROW(finish_external_output(poses, g, MatchRequest{}, "t"), ExternalMethodError);  // score 0
  poses.poses.clear();
  EXPECT_FALSE(finish_external_output(poses, g, MatchRequest::modes(), "t").has_pose());  // no pose: a reported state
}

TEST(Registry, RunTimeRegistration) {
  EXPECT_THROW(register_matcher("kernel", [](const nlohmann::json&, const SharedParams&) { return make_matcher_config("ray"); }),
               InputError);
  EXPECT_THROW(register_matcher("bad name", [](const nlohmann::json&, const SharedParams&) { return make_matcher_config("ray"); }),
               InputError);
  // "mine" is the ray matcher under another name, with its overrides passed on.
  register_matcher("mine", [](const nlohmann::json& o, const SharedParams& s) { return make_matcher_config("ray", o, s); });
  const auto names = matcher_names();
  EXPECT_NE(std::find(names.begin(), names.end(), "mine"), names.end());
  EXPECT_EQ(make_matcher_config("mine", {{"num_directions", 72}})->parameters()["num_directions"], 72);
  EXPECT_TRUE(unregister_matcher("mine"));
  EXPECT_FALSE(unregister_matcher("mine"));
  // Unknown: neither registered nor a module; the message says where the module was looked for.
  try {
    make_matcher_config("nosuchmatcher");
    FAIL();
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("unknown matcher \"nosuchmatcher\""), std::string::npos) << msg;
    EXPECT_NE(msg.find("floorcast_matcher_nosuchmatcher.so"), std::string::npos) << msg;
  }
}

TEST(Module, FoundByNameAndLocalises) {
  // examples/own_matchers/module, built into FLOORCAST_TEST_MODULE_DIR as floorcast_matcher_chamfer_cpp.so.
  setenv("FLOORCAST_MODULE_DIR", FLOORCAST_TEST_MODULE_DIR, 1);
  const auto config = make_matcher_config("chamfer_cpp", {{"resolution_m", 0.1}});
  EXPECT_EQ(config->name(), "chamfer_cpp");
  EXPECT_EQ(config->parameters()["resolution_m"], 0.1);
  const FloorPlan plan = test::asymmetric_floor();
  const auto m = config->build(plan);
  for (const Pose2& truth : {Pose2{3.23, 1.61, 0.31}, Pose2{10.31, 3.07, 4.4}}) {
    const MatchResult r = m->match(PerfectObserver(plan).observe(truth), MatchRequest::modes(3));
    ASSERT_TRUE(r.has_pose());
    EXPECT_LE(std::hypot(r.estimate().x_m - truth.x_m, r.estimate().y_m - truth.y_m), 0.3);
    EXPECT_LE(angle_distance_rad(r.estimate().yaw_rad, truth.yaw_rad), deg_to_rad(10.0));
  }
  // Its parameter errors name the key, as the built-in matchers' do.
  try {
    (void)make_matcher_config("chamfer_cpp", {{"sigma", 1}});
    FAIL();
  } catch (const ParameterError& e) {
    EXPECT_EQ(e.key(), "sigma");
    EXPECT_NE(std::string(e.what()).find("floorcast_matcher_chamfer_cpp"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace floorcast

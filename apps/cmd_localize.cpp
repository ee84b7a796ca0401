// `floorcast localize PLAN OBS --matcher kernel|ray`: one observation -> posterior over the plan,
// estimate.json and posterior.png.
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "cli_common.hpp"
#include "floorcast/core/image_io.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/match/matcher.hpp"
#include "floorcast/match/plan_raster.hpp"
#include "floorcast/core/observation_io.hpp"
#include "floorcast/core/scan_io.hpp"
#include "floorcast/core/math.hpp"
#include "observe_cli.hpp"

namespace floorcast::cli {
namespace {


/// What the localizer consumes: the 2D observation, plus the ground truth when the file knows it.
struct LocalizationInput {
  ObservationRecord record;
  std::string description;  ///< "observation JSON", "scan folder (observation module, mono)", ...
  /// Set when OBS was a scan folder: the observation module's diagnostics, timings, parameters.
  std::optional<nlohmann::ordered_json> observation_diagnostics;
};

/// Loads OBS: an observation JSON (`floorcast sim perfect` writes DIR/observation.json; the
/// folder itself is accepted too), or a scan folder (DIR/scan.json, `floorcast sim scan`), which
/// the observation module turns into 2D segments first.
LocalizationInput load_localization_input(const std::string& path, const ObserveCliOptions& observe) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    const fs::path obs = fs::path(path) / "observation.json";
    if (fs::exists(obs)) return {load_observation(obs.string()), "observation JSON", std::nullopt};
    if (fs::exists(fs::path(path) / "scan.json")) {
      const Scan scan = load_scan(path);
      const ObservationParams params = observation_params_from_cli(observe, &scan);
      const ObservationResult r = observe_scan(scan, params);
      return {observation_record(scan, path, r), "scan folder (observation module, " + r.diagnostics.path + ")",
              observation_diagnostics_json(params, r)};
    }
    throw InputError(path + ": folder without observation.json or scan.json");
  }
  if (!fs::exists(path, ec)) throw InputError(path + ": no such file or folder");
  return {load_observation(path), "observation JSON", std::nullopt};
}

nlohmann::ordered_json hypothesis_json(const PoseHypothesis& h) {
  nlohmann::ordered_json j;
  j["x_m"] = h.x_m;
  j["y_m"] = h.y_m;
  j["yaw_deg"] = h.yaw_rad * 180.0 / kPi;
  j["score"] = h.score;
  return j;
}

void register_localize(CLI::App& root) {
  struct Options {
    std::string plan, obs, matcher = "kernel", orientations, out;
    int rays = 0;
    int top_k = 5;
    std::vector<std::string> params;
    ObserveCliOptions observe;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = root.add_subcommand("localize", "Posterior over (x, y, yaw) for one observation; estimate.json, posterior.png");
  cmd->add_option("PLAN", o->plan, "Floor-plan JSON")->required();
  cmd->add_option("OBS", o->obs,
                 "Observation JSON (from `floorcast sim perfect`), or its folder, or a scan folder (`floorcast sim "
                 "scan`; the observation module runs first)")
      ->required();
  cmd->add_option("--matcher", o->matcher, "Layout matcher")->capture_default_str()->check(CLI::IsMember(matcher_names()));
  cmd->add_option("--orientations", o->orientations, "Kernel matcher orientation candidates: palms, palms+ (default), dense")
      ->check(CLI::IsMember({"palms", "palms+", "dense"}));
  cmd->add_option("--rays", o->rays, "Ray matcher: equiangular rays = volume directions (default 36)")
      ->check(CLI::Range(4, 3600));
  cmd->add_option("--param", o->params, "Matcher parameter override KEY=VALUE (repeatable; keys as in estimate.json)");
  cmd->add_option("--top-k", o->top_k, "Modes to report (NMS 1 m, 30 deg)")->capture_default_str()->check(CLI::Range(1, 100));
  cmd->add_option("-o,--output", o->out, "Output folder")->required();
  add_observation_options(*cmd, o->observe);
  cmd->callback([o] {
    const FloorPlan plan = load_floor_plan(o->plan);
    const LocalizationInput input = load_localization_input(o->obs, o->observe);
    nlohmann::json overrides = nlohmann::json::object();
    for (const std::string& p : o->params) add_override(overrides, p);
    if (!o->orientations.empty()) {
      if (o->matcher != "kernel") throw InputError("--orientations applies to the kernel matcher only");
      overrides["orientations"] = o->orientations;
    }
    if (o->rays > 0) {
      if (o->matcher != "ray") throw InputError("--rays applies to the ray matcher only");
      overrides["num_directions"] = o->rays;
    }
    const std::unique_ptr<Matcher> matcher = make_matcher(o->matcher, plan, overrides);
    const MatchResult result = matcher->match(input.record.observation);
    const Posterior& post = result.posterior;
    const PoseHypothesis best = post.argmax();
    const std::vector<PoseHypothesis> modes = post.top_k(o->top_k, 1.0, kPi / 6.0);

    // An empty posterior (every cell scored 0: e.g. the observation collides with the map
    // everywhere) is "no pose", never a made-up pose at the grid's first cell.
    const bool found = best.score > 0.0;
    nlohmann::ordered_json j;
    j["status"] = found ? "ok" : "no pose: empty posterior (every cell scored 0)";
    j["x_m"] = found ? nlohmann::ordered_json(best.x_m) : nlohmann::ordered_json(nullptr);
    j["y_m"] = found ? nlohmann::ordered_json(best.y_m) : nlohmann::ordered_json(nullptr);
    j["yaw_deg"] = found ? nlohmann::ordered_json(best.yaw_rad * 180.0 / kPi) : nlohmann::ordered_json(nullptr);
    j["score"] = best.score;
    nlohmann::ordered_json top = nlohmann::ordered_json::array();
    for (const PoseHypothesis& h : modes) top.push_back(hypothesis_json(h));
    j["top_k"] = top;
    if (input.record.T_world_observer) {
      const Pose2& t = *input.record.T_world_observer;
      nlohmann::ordered_json g;
      g["x_m"] = t.x_m;
      g["y_m"] = t.y_m;
      g["yaw_deg"] = t.yaw_rad * 180.0 / kPi;
      j["ground_truth"] = g;
      if (found) {
        j["position_error_m"] = std::hypot(best.x_m - t.x_m, best.y_m - t.y_m);
        j["yaw_error_deg"] = angle_distance_rad(best.yaw_rad, t.yaw_rad) * 180.0 / kPi;
      }
    }
    nlohmann::ordered_json timings;
    timings["precompute_s"] = matcher->precompute_s();
    timings["match_s"] = result.match_s;
    nlohmann::ordered_json stages;
    for (const auto& [k, v] : result.stage_s) stages[k] = v;
    timings["stages_s"] = stages;
    j["timings"] = timings;
    j["matcher"] = matcher->name();
    j["parameters"] = matcher->parameters();
    j["precompute_mb"] = matcher->precompute_bytes() / 1e6;
    j["plan"] = o->plan;
    j["observation"] = o->obs;
    j["observation_input"] = input.description;
    j["observation_segments"] = input.record.observation.segments_m.size();
    nlohmann::ordered_json grid;
    grid["origin_m"] = {post.grid.origin_x_m, post.grid.origin_y_m};
    grid["resolution_m"] = post.grid.resolution_m_per_px;
    grid["size_px"] = {post.grid.width_px, post.grid.height_px};
    grid["slices"] = post.num_slices();
    j["grid"] = grid;

    ensure_directory(o->out);
    write_json(o->out + "/estimate.json", j);
    if (input.observation_diagnostics) {  // what the observation module made of the scan
      save_observation(o->out + "/observation.json", input.record);
      write_json(o->out + "/observation.diagnostics.json", *input.observation_diagnostics);
    }
    const cv::Mat raster = rasterize_outline(blocking_outline(plan, matcher->blocking()), post.grid);
    std::optional<PoseHypothesis> truth;
    if (input.record.T_world_observer) {
      PoseHypothesis t;
      t.x_m = input.record.T_world_observer->x_m;
      t.y_m = input.record.T_world_observer->y_m;
      t.yaw_rad = input.record.T_world_observer->yaw_rad;
      truth = t;
    }
    const cv::Mat img =
        render_posterior_heatmap(post, raster, truth, found ? std::optional<PoseHypothesis>(best) : std::nullopt);
    const std::string png = o->out + "/posterior.png";
    write_png(png, img);

    if (!found) {
      std::cout << matcher->name() << ": no pose (empty posterior: every cell scored 0) -> " << o->out << "\n";
      throw CommandExit{3};
    }
    std::cout << std::fixed << std::setprecision(2) << matcher->name() << ": x " << best.x_m << " m, y " << best.y_m
              << " m, yaw " << std::setprecision(1) << best.yaw_rad * 180.0 / kPi << " deg (score "
              << std::setprecision(4) << best.score << ")";
    if (input.record.T_world_observer) {
      std::cout << std::setprecision(2) << "; error " << j["position_error_m"].get<double>() << " m, "
                << std::setprecision(1) << j["yaw_error_deg"].get<double>() << " deg";
    }
    std::cout << std::setprecision(3) << "; precompute " << matcher->precompute_s() << " s, match " << result.match_s
              << " s -> " << o->out << "\n";
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_localize);
}  // namespace floorcast::cli

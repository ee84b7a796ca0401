// `floorcast localize PLAN OBS --matcher kernel|ray|planes`: one observation -> posterior over the
// plan, estimate.json (the pose and the top-K modes, or "not localized") and posterior.png.
#include <algorithm>
#include <cmath>
#include <functional>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <tuple>

#include "cli_common.hpp"
#include "floorcast/core/file_io.hpp"
#include "floorcast/core/depth_io.hpp"
#include "floorcast/core/format.hpp"
#include "floorcast/core/image_io.hpp"
#include "floorcast/eval/trajectory_plot.hpp"
#include "floorcast/core/hash.hpp"
#include "floorcast/scenarios/run_directory.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/match/bev_matcher.hpp"
#include "floorcast/match/estimate_record.hpp"
#include "floorcast/match/matcher.hpp"
#include "floorcast/match/ray_matcher.hpp"
#include "floorcast/eval/heatmap.hpp"
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
LocalizationInput load_localization_input(const std::string& path, const ObserveCliOptions& observe,
                                          const std::function<void(ObservationParams&)>& adjust) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    const fs::path obs = fs::path(path) / "observation.json";
    if (fs::exists(obs)) return {load_observation(obs.string()), "observation JSON", std::nullopt};
    if (fs::exists(fs::path(path) / "scan.json")) {
      const Scan scan = load_scan_for_observation(path, observe);
      ObservationParams params = observation_params_from_cli(observe, &scan);
      if (adjust) adjust(params);
      const ObservationResult r = observe_scan(scan, params);
      return {observation_record(scan, path, r), "scan folder (observation module, " + r.diagnostics.path + ")",
              observation_diagnostics_json(params, r)};
    }
    throw InputError(path + ": folder without observation.json or scan.json");
  }
  if (!fs::exists(path, ec)) throw InputError(path + ": no such file or folder");
  return {load_observation(path), "observation JSON", std::nullopt};
}

/// A BEV brought as one .npy of shape (W, D, C) (a network's output for one image): C = 4
/// (wall, window, door, empty) or 2 (occupied, empty); columns left to right over a pinhole
/// camera's horizontal field of view hfov_deg centred on the observer's heading (360: W
/// equiangular columns counter-clockwise from the heading); depth bins log-spaced over
/// [min_depth_m, max_depth_m).
LocalizationInput load_bev_npy(const std::string& path, double hfov_deg, double min_depth_m, double max_depth_m) {
  const NpyArray a = read_npy(path);
  if (a.shape.size() != 3 || (a.shape[2] != 4 && a.shape[2] != 2)) {
    throw InputError(path + ": a BEV .npy must have shape (W, D, C) with C = 4 (wall, window, door, empty) or 2 "
                            "(occupied, empty)");
  }
  const BevClasses classes = a.shape[2] == 4 ? BevClasses::kSemantic : BevClasses::kOccupancy;
  // One reader of BEV files (scan folders' view BEVs): a pinhole of the given field of view.
  CameraIntrinsics K;
  K.width_px = static_cast<int>(std::max<std::size_t>(a.shape[0], 1));
  K.fx_px = 0.5 * K.width_px / std::tan(0.5 * std::min(hfov_deg, 179.0) * kPi / 180.0);
  K.cx_px = 0.5 * (K.width_px - 1);
  BevPrediction b = read_view_bev(path, K, classes, min_depth_m, max_depth_m);
  if (hfov_deg >= 360.0) b.column_azimuth_rad = full_circle_azimuths(b.num_columns());
  LocalizationInput in;
  in.record.observation.bev.push_back(std::move(b));
  in.record.observation.max_range_m = max_depth_m;
  in.record.source = "BEV " + path;
  in.description = "BEV .npy (" + std::string(bev_classes_name(classes)) + ", " + std::to_string(a.shape[0]) +
                   " columns over " + format_fixed(hfov_deg, 1) + " deg)";
  return in;
}

/// What a path holds, for telling swapped arguments apart: "plan", "observation", "scan folder",
/// "observation folder" or "" (unknown or unreadable: the loaders then say what is wrong).
std::string input_kind(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    if (fs::exists(fs::path(path) / "scan.json", ec)) return "scan folder";
    if (fs::exists(fs::path(path) / "observation.json", ec)) return "observation folder";
    return "";
  }
  if (!fs::is_regular_file(path, ec) || fs::file_size(path, ec) > (64u << 20)) return "";
  const nlohmann::json j = nlohmann::json::parse(read_text_file(path), nullptr, false);
  if (j.is_discarded() || !j.is_object()) return "";
  if (j.value("format", std::string()) == "floorcast-observation") return "observation";
  if (j.contains("walls") && j["walls"].is_array()) return "plan";
  return "";
}

/// Refuses PLAN and OBS given the wrong way round with a message saying so.
void check_argument_order(const std::string& plan, const std::string& obs) {
  const std::string p = input_kind(plan), o = input_kind(obs);
  if (!p.empty() && p != "plan") {
    throw InputError("PLAN \"" + plan + "\" is " + (p == "observation" ? "an " : "a ") + p + (o == "plan" ? " and OBS \"" + obs + "\" is a floor plan" : "") +
                     ": the order is `floorcast localize PLAN OBS` (did you swap them?)");
  }
  if (o == "plan") {
    throw InputError("OBS \"" + obs + "\" is a floor plan, not an observation or scan folder: the order is `floorcast "
                     "localize PLAN OBS`");
  }
}

/// Writes the posterior volume as `mode` asks (npy, npz-f16, top-k) slice by slice, without a
/// copy of the volume; returns the file name ("" for none).
std::string write_posterior(const std::string& dir, const std::string& mode, const Posterior& post, int cells) {
  if (mode == "none") return "";
  const std::size_t S = static_cast<std::size_t>(post.num_slices()), H = static_cast<std::size_t>(post.grid.height_px),
                    W = static_cast<std::size_t>(post.grid.width_px);
  if (mode == "npy") {
    NpyStreamWriter w(dir + "/posterior.npy", {S, H, W}, NpyDtype::kFloat32);
    for (const cv::Mat& slice : post.scores) w.append(slice);
    w.close();
    return "posterior.npy";
  }
  if (mode == "npz-f16") {
    NpzWriter z(dir + "/posterior.npz");
    z.add_slices("posterior", {S, H, W}, NpyDtype::kFloat16, post.scores);
    z.close();
    return "posterior.npz";
  }
  // top-k: the best cells of the volume (ties by index), found with a bounded heap per slice.
  struct Cell {
    float score;
    std::uint32_t s, r, c;
  };
  auto worse = [](const Cell& a, const Cell& b) {
    return a.score != b.score ? a.score > b.score : std::tie(a.s, a.r, a.c) < std::tie(b.s, b.r, b.c);
  };
  std::vector<Cell> heap;  // a min-heap under `worse`: heap.front() is the weakest kept cell
  const std::size_t K = static_cast<std::size_t>(cells);
  for (std::size_t s = 0; s < S; ++s)
    for (std::size_t r = 0; r < H; ++r) {
      const float* row = post.scores[s].ptr<float>(static_cast<int>(r));
      for (std::size_t c = 0; c < W; ++c) {
        if (!(row[c] > 0.0f)) continue;
        const Cell cell{row[c], static_cast<std::uint32_t>(s), static_cast<std::uint32_t>(r), static_cast<std::uint32_t>(c)};
        if (heap.size() < K) {
          heap.push_back(cell);
          std::push_heap(heap.begin(), heap.end(), worse);
        } else if (worse(cell, heap.front())) {
          std::pop_heap(heap.begin(), heap.end(), worse);
          heap.back() = cell;
          std::push_heap(heap.begin(), heap.end(), worse);
        }
      }
    }
  std::sort(heap.begin(), heap.end(), worse);
  const std::size_t N = heap.size();
  cv::Mat index(static_cast<int>(std::max<std::size_t>(N, 1)), 3, CV_32S, cv::Scalar(0));
  std::vector<float> x(N), y(N), yaw(N), score(N);
  for (std::size_t i = 0; i < N; ++i) {
    const Cell& c = heap[i];
    const int k = static_cast<int>(i);
    index.at<int>(k, 0) = static_cast<int>(c.s);
    index.at<int>(k, 1) = static_cast<int>(c.r);
    index.at<int>(k, 2) = static_cast<int>(c.c);
    const Vec2 p = post.grid.cell_center_m(static_cast<int>(c.r), static_cast<int>(c.c));
    x[i] = static_cast<float>(p.x());
    y[i] = static_cast<float>(p.y());
    yaw[i] = static_cast<float>(post.yaw_rad[c.s] * 180.0 / kPi);
    score[i] = c.score;
  }
  NpzWriter z(dir + "/posterior_top.npz");
  if (N > 0) z.add("index", index);
  else z.add("index", {0, 3}, {});  // no cell scored above 0: an empty (0, 3) array
  z.add("x_m", {N}, x);
  z.add("y_m", {N}, y);
  z.add("yaw_deg", {N}, yaw);
  z.add("score", {N}, score);
  z.close();
  return "posterior_top.npz";
}

void register_localize(CLI::App& root) {
  struct Options {
    std::string plan, obs, matcher = "kernel", orientations, out;
    int rays = 0;
    double bev_hfov_deg = 90.0;
    int top_k = 5;
    double range_m = SharedParams{}.range_m;
    std::string posterior = "none";
    int posterior_cells = 10000;
    std::vector<std::string> params;
    ObserveCliOptions observe;
    bool quiet = false;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = root.add_subcommand("localize",
                                  "Posterior over (x, y, yaw) for one observation: estimate.json, posterior.png, posterior.npy "
                                  "+ posterior_grid.json, observation_overlay.png");
  cmd->add_option("PLAN", o->plan, "Floor-plan JSON")->required();
  cmd->add_option("OBS", o->obs,
                 "Observation JSON (from `floorcast sim perfect`), or its folder, or a scan folder (`floorcast sim "
                 "scan`; the observation module runs first), or a BEV .npy of shape (W, D, C) for the bev matcher")
      ->required();
  cmd->add_option("--matcher", o->matcher, "Layout matcher (built in, registered, or a module floorcast_matcher_NAME.so)")->capture_default_str();
  cmd->add_option("--orientations", o->orientations, "Kernel matcher orientation candidates: palms, palms+ (default), dense")
      ->check(CLI::IsMember({"palms", "palms+", "dense"}));
  cmd->add_option("--rays", o->rays, "Ray matcher: equiangular rays = volume directions (default 36)")
      ->check(in_range(4, 3600));
  CLI::Option* matcher_param = cmd->add_option(
      "--matcher-param", o->params, "Matcher parameter override KEY=VALUE (repeatable; keys as in estimate.json's parameters)");
  add_deprecated_option(*cmd, "--param", matcher_param, o->params);
  CLI::Option* range_opt = cmd->add_option("--range", o->range_m, "Matching range, metres (the matcher's max_range_m; PALMS+ 4.4: 10)")
                               ->capture_default_str()
                               ->check(in_range(0.5, 60.0));
  cmd->add_option("--bev-hfov-deg", o->bev_hfov_deg,
                  "A BEV .npy as OBS: horizontal field of view its columns span, left to right (360: a full circle "
                  "counter-clockwise from the heading)")
      ->capture_default_str()
      ->check(in_range(1.0, 360.0));
  cmd->add_option("--top-k", o->top_k, "Modes to report (NMS 1 m, 30 deg)")->capture_default_str()->check(in_range(1, 100));
  cmd->add_option("--posterior", o->posterior,
                  "Posterior volume written: none (estimate, modes and the max-over-heading heatmap only; memory "
                  "bounded), npy (posterior.npy float32), npz-f16 (posterior.npz: float16, deflated), top-k "
                  "(posterior_top.npz: the --posterior-cells best cells)")
      ->capture_default_str()
      ->check(CLI::IsMember({"none", "npy", "npz-f16", "top-k"}));
  cmd->add_option("--posterior-cells", o->posterior_cells, "Cells kept by --posterior top-k")
      ->capture_default_str()
      ->check(in_range(1, 100000000));
  cmd->add_option("-o,--output", o->out, "Output folder")->required();
  cmd->add_flag("--quiet", o->quiet, "No progress output on stderr");
  add_observation_options(*cmd, o->observe);
  cmd->callback([o, range_opt] {
    check_argument_order(o->plan, o->obs);
    refuse_output_inside_inputs(o->out, {o->obs});
    // Every parameter is parsed, typed and checked before any work.
    nlohmann::json overrides = nlohmann::json::object();
    for (const std::string& p : o->params) add_override(overrides, p, "--matcher-param");
    if (range_opt->count() > 0 && overrides.contains("max_range_m")) {
      throw InputError("--range and --matcher-param max_range_m both set the matching range: give one");
    }
    SharedParams shared;
    shared.range_m = o->range_m;
    if (!o->orientations.empty()) {
      if (o->matcher != "kernel") throw InputError("--orientations applies to the kernel matcher only");
      overrides["orientations"] = o->orientations;
    }
    if (o->rays > 0) {
      if (o->matcher != "ray") throw InputError("--rays applies to the ray matcher only");
      overrides["num_directions"] = o->rays;
    }
    const std::shared_ptr<const MatcherConfig> matcher_config = make_matcher_config(o->matcher, overrides, shared);
    (void)observation_params_from_cli(o->observe, nullptr);  // the observation module's, checked now
    // The bev matcher's depth bins, which the BEV (predicted or brought) must share.
    const bool bev = o->matcher == "bev";
    BevMatcherParams bev_params;
    if (bev) {
      bev_params.apply_shared(shared);
      bev_params.apply_overrides(overrides);
    }
    if (std::filesystem::path(o->obs).extension() == ".npy" && !bev) {
      throw InputError(o->obs + ": a BEV .npy is an observation for the bev matcher only (--matcher bev)");
    }
    const FloorPlan plan = load_floor_plan(o->plan);
    LocalizationInput input;
    {
      const Heartbeat hb("localize: reading the observation " + o->obs, o->quiet);
      if (std::filesystem::path(o->obs).extension() == ".npy") {
        input = load_bev_npy(o->obs, o->bev_hfov_deg, bev_params.min_depth_m, bev_params.max_range_m);
      } else {
        input = load_localization_input(o->obs, o->observe, [&](ObservationParams& p) {
          if (!bev) return;
          // A scan localized with the bev matcher: its BEV (brought, else predicted) on the matcher's bins.
          p.bev.enabled = true;
          p.bev.depth_bins = bev_params.depth_bins;
          p.bev.min_depth_m = bev_params.min_depth_m;
          p.bev.max_depth_m = bev_params.max_range_m;
        });
      }
    }
    // An observation made in another building (or another version of this plan) localizes
    // against the wrong map: say so, do not refuse (a plan may have been repaired since).
    if (auto it = input.record.metadata.find("plan_hash"); it != input.record.metadata.end()) {
      warn_plan_mismatch(o->obs, it->second, o->plan, plan);
    }
    std::unique_ptr<Matcher> matcher;
    {
      const Heartbeat hb("localize: preparing the " + o->matcher + " matcher on " + o->plan, o->quiet);
      matcher = matcher_config->build(plan);
    }
    // Said, not silent: ray ranges the ray matcher cannot use (auto casts rays on the segments).
    std::vector<std::string> notes;
    const std::size_t obs_rays = input.record.observation.ray_ranges_m.size();
    if (const auto* ray = dynamic_cast<const RayMatcher*>(&matcher->unwrapped());
        ray && ray->params().ray_source == RaySource::kAuto && obs_rays > 0 &&
        static_cast<std::size_t>(ray->params().num_directions) != obs_rays) {
      notes.push_back("the observation's " + std::to_string(obs_rays) + " ray ranges do not match the " +
                      std::to_string(ray->params().num_directions) +
                      " directions of the ray matcher: rays are cast on its segments instead (ray_source auto)");
      std::cerr << "note: " << notes.back() << "\n";
    }
    // The full volume only when it is written: otherwise the modes and the max over heading (the
    // heatmap), which the matchers compute without holding every heading slice.
    MatchRequest request = MatchRequest::modes(o->top_k, 1.0, kPi / 6.0);
    request.output = o->posterior == "none" ? MatchOutput::kMaxOverYaw : MatchOutput::kPosterior;
    MatchResult result;
    {
      const Heartbeat hb("localize: matching", o->quiet);
      result = matcher->match(input.record.observation, request);
    }
    const std::vector<PoseHypothesis>& modes = result.modes;
    // No mode is "not localized", never a made-up pose at the grid's first cell: an empty
    // posterior (every cell scored 0: e.g. the observation collides with the map everywhere), a
    // matcher that rejects the observation (the plane matcher: no triplet passes), or a best
    // score below min_score. The plane matcher's modes are its refined transforms.
    const bool found = result.has_pose();
    const PoseHypothesis best = found ? modes.front() : PoseHypothesis{};
    // What the heatmap draws: the max over heading (one slice).
    Posterior post;
    post.grid = result.grid;
    post.yaw_rad = {0.0};
    post.scores = {result.posterior.num_slices() > 0 ? result.posterior.max_over_yaw() : result.max_over_yaw};
    if (post.scores.front().empty()) post.scores.front() = cv::Mat::zeros(post.grid.height_px, post.grid.width_px, CV_32F);
    const bool abstained = result.counters.count("abstained") > 0;
    double mass = 0.0;
    for (int r = 0; r < post.scores.front().rows; ++r)
      for (int c = 0; c < post.scores.front().cols; ++c) mass += post.scores.front().at<float>(r, c);
    const std::string why_not = abstained ? "the best score is below min_score"
                                : result.counters.count("bev_missing") ? "the observation has no BEV of the matcher's class set"
                                : mass > 0.0 ? "no pose passes the matcher's checks"
                                : matcher->name() == "planes" ? "no plane triplet passes the evaluation (or too few planes)"
                                                              : "empty posterior (every cell scored 0)";
    EstimateRecord est;
    est.status = found ? "ok" : "not localized (no pose): " + why_not;
    if (found) est.best = hypothesis_record(best);
    est.score = best.score;
    for (const PoseHypothesis& h : modes) est.top_k.push_back(hypothesis_record(h));
    est.counters = result.counters;
    if (input.record.T_world_observer) {
      const Pose2& t = *input.record.T_world_observer;
      est.ground_truth = HypothesisRecord{t.x_m, t.y_m, t.yaw_rad * 180.0 / kPi, 0.0};
      if (found) {
        est.position_error_m = std::hypot(best.x_m - t.x_m, best.y_m - t.y_m);
        est.yaw_error_deg = angle_distance_rad(best.yaw_rad, t.yaw_rad) * 180.0 / kPi;
      }
    }
    est.precompute_s = matcher->precompute_s();
    est.match_s = result.match_s;
    est.stages_s = result.stage_s;
    est.matcher = matcher->name();
    est.parameters = matcher->parameters();
    est.precompute_mb = matcher->precompute_bytes() / 1e6;
    est.plan = o->plan;
    est.observation = o->obs;
    est.observation_input = input.description;
    est.observation_segments = input.record.observation.segments_m.size();
    est.observation_planes = input.record.observation.planes.size();
    est.notes = notes;
    est.grid = post.grid;
    if (result.posterior.num_slices() > 0) est.slices = result.posterior.num_slices();
    est.posterior_output = o->posterior;

    ensure_directory(o->out);
    write_json(o->out + "/estimate.json", estimate_record_fields().write(est));
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
    HeatmapStyle style;
    style.title = matcher->name() + " matcher: " +
                  (!found ? std::string("not localized")
                          : truth ? "error " + format_fixed(*est.position_error_m, 2) + " m, " +
                                        format_fixed(*est.yaw_error_deg, 1) + " deg"
                                  : "estimate " + format_pose(Pose2{best.x_m, best.y_m, best.yaw_rad}));
    const cv::Mat img = render_posterior_heatmap(post, raster, truth,
                                                 found ? std::optional<PoseHypothesis>(best) : std::nullopt, style);
    // The posterior volume for numpy (yaw, y, x) as asked, with its grid, and the observation
    // drawn over the plan at the true and the estimated pose.
    {
      const std::string file = write_posterior(o->out, o->posterior, result.posterior, o->posterior_cells);
      if (!file.empty()) {
        PosteriorGridRecord g = posterior_grid_record(result.posterior, matcher->name());
        g.file = file;
        g.dtype = o->posterior == "npz-f16" ? "float16" : "float32";
        if (o->posterior == "top-k") {
          g.top_k = "posterior_top.npz holds the best cells in descending score: arrays index (N x 3: yaw slice, row, "
                    "col), x_m, y_m, yaw_deg, score";
        }
        write_json(o->out + "/posterior_grid.json", posterior_grid_record_fields().write(g));
      }

      std::vector<TrajectoryLayer> layers;
      std::vector<MarkerLayer> markers;
      auto segments_at = [&](const Pose2& T) {
        std::vector<Vec2> pts;
        for (const Segment2& sgm : input.record.observation.segments_m) {
          pts.push_back(T.transform(sgm.a_m));
          pts.push_back(T.transform(sgm.b_m));
        }
        return pts;
      };
      if (input.record.T_world_observer) {
        layers.push_back({"observation at the true pose", segments_at(*input.record.T_world_observer), cv::Scalar(0, 160, 0), 3, true});
        markers.push_back({"true pose", {input.record.T_world_observer->position_m()}, cv::Scalar(0, 160, 0), 7, true});
      }
      if (found) {
        const Pose2 e{best.x_m, best.y_m, best.yaw_rad};
        layers.push_back({"observation at the estimate", segments_at(e), cv::Scalar(0, 0, 220), 2, true});
        markers.push_back({"estimate", {e.position_m()}, cv::Scalar(0, 0, 220), 7, true});
      }
      const cv::Mat overlay = draw_plan_with_trajectories(plan, layers, markers, style.title + " - observed segments");
      write_png(o->out + "/observation_overlay.png", overlay);
    }
    const std::string png = o->out + "/posterior.png";
    write_png(png, img);

    if (!found) {
      if (result.counters.count("bev_missing")) {
        std::cout << matcher->name() << ": no pose: the observation has no BEV of the matcher's class set (scans: "
                  << "simulate with `sim scan --semantics` or bring view BEVs; perfect observations: `sim perfect "
                  << "--bev-columns 72`) -> " << o->out << "\n";
        throw CommandExit{kExitNoPose};
      }
      std::cout << matcher->name() << ": not localized (no pose: " << why_not << ") -> " << o->out << "\n";
      throw CommandExit{kExitNoPose};
    }
    std::cout << std::fixed << std::setprecision(2) << matcher->name() << ": x " << best.x_m << " m, y " << best.y_m
              << " m, yaw " << std::setprecision(1) << best.yaw_rad * 180.0 / kPi << " deg (score "
              << std::setprecision(4) << best.score << ")";
    if (input.record.T_world_observer) {
      std::cout << std::setprecision(2) << "; error " << *est.position_error_m << " m, " << std::setprecision(1)
                << *est.yaw_error_deg << " deg";
    }
    std::cout << std::setprecision(3) << "; precompute " << matcher->precompute_s() << " s, match " << result.match_s
              << " s -> " << o->out << "\n";
    for (std::size_t i = 1; i < modes.size(); ++i) {
      std::cout << "  mode " << i + 1 << ": " << std::fixed << std::setprecision(2) << "x " << modes[i].x_m << " m, y "
                << modes[i].y_m << " m, yaw " << std::setprecision(1) << modes[i].yaw_rad * 180.0 / kPi << " deg (score "
                << std::setprecision(4) << modes[i].score << ")\n";
    }
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_localize);
}  // namespace floorcast::cli

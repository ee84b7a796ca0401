// `floorcast sim scan|perfect|extrude`: simulated scans, perfect observations, 3D buildings.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli_common.hpp"
#include "floorcast/core/image_io.hpp"
#include "floorcast/core/scan_io.hpp"
#include "floorcast/eval/scan_sheet.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/sim/clutter.hpp"
#include "floorcast/sim/gl_renderer.hpp"
#include "floorcast/sim/gltf_io.hpp"
#include "floorcast/sim/mesh.hpp"
#include "floorcast/core/observation_io.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "floorcast/sim/scan_io.hpp"
#include "floorcast/sim/scan_sim.hpp"
#include "floorcast/sim/walk.hpp"
#include "floorcast/core/hash.hpp"
#include "floorcast/core/json_text.hpp"
#include "floorcast/core/math.hpp"

namespace floorcast::cli {
namespace {

constexpr const char* kPoseHelp =
    "Observer pose X,Y,YAW_DEG (metres, degrees), or 'random': a seeded pose (--seed) in the largest free region, "
    "heading uniform";

/// --pose: "X,Y,YAW_DEG", or "random" drawn with `seed` where a walker could stand (the free space
/// of the largest connected region, as `sim walk` starts).
Pose2 observer_pose(const FloorPlan& plan, const std::string& text, std::uint64_t seed) {
  if (!is_random_pose(text)) return parse_pose(text);
  WalkParams wp;
  wp.seed = seed;
  return random_start_pose(plan, wp);
}

/// Options shared by the commands that build a 3D building.
struct BuildingOptions {
  double wall_height_m = ExtrusionParams{}.wall_height_m;
  double door_height_m = ExtrusionParams{}.door_height_m;
  double clutter_density = 0.0;
  std::uint64_t clutter_seed = 0;
};

void add_building_options(CLI::App* cmd, BuildingOptions& o) {
  cmd->add_option("--wall-height", o.wall_height_m, "Wall (ceiling) height, metres")
      ->capture_default_str()
      ->check(in_range(0.5, 100.0));
  cmd->add_option("--door-height", o.door_height_m, "Door height (lintel underside), metres")
      ->capture_default_str()
      ->check(in_range(0.1, 100.0));
  cmd->add_option("--clutter", o.clutter_density, "Clutter density in [0, 1] (0 = none)")
      ->capture_default_str()
      ->check(in_range(0.0, 1.0));
}

FloorPlan plan_with_clutter(const FloorPlan& plan, const BuildingOptions& o, const std::vector<Vec2>& keep_clear) {
  if (o.clutter_density <= 0.0) return plan;
  ClutterParams cp;
  cp.density = o.clutter_density;
  cp.seed = o.clutter_seed;
  cp.keep_clear_m = keep_clear;
  return with_clutter(plan, cp);
}

ExtrusionParams extrusion(const BuildingOptions& o) {
  ExtrusionParams e;
  e.wall_height_m = o.wall_height_m;
  e.door_height_m = o.door_height_m;
  return e;
}

void register_sim(CLI::App& root) {
  CLI::App& sim = group(root, "sim", "Simulator: rotating scans, perfect observations, 3D buildings");

  // ---- sim scan ----
  struct ScanOptions {
    std::string plan, pose, sensor = "mono", setting = "full", out, depth_model, sensor_params;
    int center_view = 0;
    std::uint64_t seed = 0;
    double max_range_m = -1.0, scale_sigma = -1.0;
    bool rgb = false;
    bool doors_open = false;
    bool semantics = false;
    BuildingOptions building;
  };
  auto so = std::make_shared<ScanOptions>();
  auto* scan = sim.add_subcommand("scan", "Simulate a rotating scan and write a scan folder");
  scan->add_option("PLAN", so->plan, "Floor-plan JSON")->required();
  scan->add_option("--pose", so->pose, kPoseHelp)->required();
  scan->add_option("--sensor", so->sensor, "Preset: perfect, lidar, mono, phone")
      ->capture_default_str()
      ->check(CLI::IsMember(scan_preset_names()));
  scan->add_option("--setting", so->setting, "full, partial (3 views) or single (1 view)")
      ->capture_default_str()
      ->check(CLI::IsMember({"full", "partial", "single"}));
  scan->add_option("--center-view", so->center_view, "View the partial/single settings keep")->capture_default_str();
  scan->add_option("--seed", so->seed, "Random seed (sensor noise, clutter)")->capture_default_str();
  // Given or not is told by the option's count (no sentinel value: -1 or NaN must be refused).
  CLI::Option* max_range_opt = scan->add_option("--range", so->max_range_m, "Override the preset's maximum range, metres");
  add_deprecated_option(*scan, "--max-range", max_range_opt, so->max_range_m);
  CLI::Option* scale_sigma_opt = scan->add_option("--scale-sigma", so->scale_sigma, "Override the mono per-view log scale sigma");
  scan->add_option("--depth-model", so->depth_model,
                   "Monocular error level of a published network (mono and phone sensors; default depth_pro)")
      ->check(CLI::IsMember(mono_model_names()));
  scan->add_option("--sensor-params", so->sensor_params,
                   "JSON object of scan-parameter overrides, keys as in simulation.json's \"params\", e.g. "
                   "'{\"sensor\": {\"mono\": {\"no_ground_prob\": 0.3}}}'");
  scan->add_flag("--rgb", so->rgb,
                 "Also render every view in colour (OpenGL through OSMesa, headless) from its true camera pose: "
                 "view_NNN_rgb.png");
  scan->add_flag("--doors-open", so->doors_open,
                 "Open doors stay open as drawn (default, as `sim perfect` and the matchers' map: every door closed, "
                 "PALMS+ 4.4)");
  scan->add_flag("--semantics", so->semantics,
                 "Also annotate every view with its column semantics (view_NNN_semantics.json: per image column, the "
                 "walls, windows, doors and furniture its horizontal ray meets), the truth the BEV predictor of "
                 "`observe --bev` turns into a BEV");
  add_building_options(scan, so->building);
  scan->add_option("-o,--output", so->out, "Output scan folder")->required();
  scan->callback([so, scan, scale_sigma_opt] {
    const auto t0 = std::chrono::steady_clock::now();
    const FloorPlan given = load_floor_plan(so->plan);
    FloorPlan plan = given;
    if (!so->doors_open)
      for (Door& d : plan.doors) d.closed = true;  // the one door default: closed (see --doors-open)
    const Pose2 pose = observer_pose(given, so->pose, so->seed);
    ScanParams params = scan_preset(so->sensor);
    parse_scan_setting(so->setting, params.setting);
    params.center_view = so->center_view;
    params.seed = so->seed;
    if (scan->count("--range") + scan->count("--max-range") > 0) params.sensor.max_range_m = so->max_range_m;
    if (!so->depth_model.empty()) params.sensor.mono = mono_model_preset(so->depth_model);
    if (!so->sensor_params.empty()) {
      apply_scan_overrides(params, parse_json_text(so->sensor_params, "--sensor-params"), "--sensor-params");
    }
    if (scale_sigma_opt->count() > 0) params.sensor.mono.scale_sigma_ln = so->scale_sigma;
    validate_scan_params(params);
    BuildingOptions b = so->building;
    b.clutter_seed = so->seed;
    const FloorPlan full = plan_with_clutter(plan, b, {pose.position_m()});
    check_observer_pose(full, pose, so->plan);
    const RayScene scene(extrude_plan(full, extrusion(b)));
    const auto t1 = std::chrono::steady_clock::now();
    SimulationOptions options;
    options.column_semantics = so->semantics;
    SimulatedScan sim = simulate_scan(scene, pose, params, options);
    sim.truth.plan_hash = hex64(plan_hash(given));
    const auto t2 = std::chrono::steady_clock::now();
    double rgb_s = 0.0;
    if (so->rgb) {
      GlRenderer gl(scene.mesh(), params.geometry.width_px, params.geometry.height_px);
      rgb_s = render_scan_colour(gl, sim);
    }
    save_simulated_scan(so->out, sim);
    const Scan& s = sim.scan;
    long returns = 0, pixels = 0, glass = 0;
    for (const DepthView& v : s.views) {
      returns += cv::countNonZero(v.depth_m > 0.0f);
      glass += cv::countNonZero(v.glass_mask);
      pixels += static_cast<long>(v.depth_m.total());
    }
    std::cout << std::fixed << std::setprecision(1) << "scan: " << s.views.size() << " views ("
              << params.geometry.width_px << "x" << params.geometry.height_px << ", " << so->sensor << ", "
              << so->setting << ") at " << format_pose(pose) << ": " << 100.0 * returns / std::max(1L, pixels)
              << "% returns, " << 100.0 * glass / std::max(1L, pixels) << "% glass-affected; "
              << (full.obstacles.size() - plan.obstacles.size()) << " clutter items; scene "
              << std::chrono::duration<double, std::milli>(t1 - t0).count() << " ms, render "
              << std::chrono::duration<double, std::milli>(t2 - t1).count() << " ms";
    if (so->rgb) std::cout << ", colour " << 1e3 * rgb_s << " ms";
    std::cout << " -> " << so->out << "\n";
  });

  // ---- sim perfect ----
  struct PerfectOptions {
    std::string plan, pose, out;
    std::uint64_t seed = 0;
    int rays = PerfectObservationParams{}.num_rays;
    double range_m = PerfectObservationParams{}.max_range_m;
    int bev_columns = PerfectObservationParams{}.bev_columns;
    bool doors_open = false;
  };
  auto po = std::make_shared<PerfectOptions>();
  auto* perfect = sim.add_subcommand("perfect", "Exact 2D observation (visible wall segments, ray ranges) as JSON");
  perfect->add_option("PLAN", po->plan, "Floor-plan JSON")->required();
  perfect->add_option("--pose", po->pose, kPoseHelp)->required();
  perfect->add_option("--seed", po->seed, "Seed of --pose random")->capture_default_str();
  perfect->add_option("--rays", po->rays, "Equiangular rays (F3Loc: 36 or 180; 0 = none)")
      ->capture_default_str()
      ->check(in_range(0, 100000));
  perfect->add_option("--range", po->range_m, "Maximum range, metres")->capture_default_str()->check(in_range(0.01, 1e4));
  perfect->add_option("--bev-columns", po->bev_columns,
                      "Perfect bird's-eye views (semantic and occupancy, for the bev matcher) on this many equiangular "
                      "columns (72: 5 deg; 0 = none)")
      ->capture_default_str()
      ->check(in_range(0, 3600));
  perfect->add_flag("--doors-open", po->doors_open,
                    "Open doors stay open as drawn (default, as `sim scan` and the matchers' map: every door closed, "
                    "PALMS+ 4.4)");
  perfect->add_option("-o,--output", po->out, "Output folder (writes observation.json)")->required();
  perfect->callback([po] {
    const FloorPlan plan = load_floor_plan(po->plan);
    const Pose2 pose = observer_pose(plan, po->pose, po->seed);
    check_observer_pose(plan, pose, po->plan);
    PerfectObservationParams params;
    params.num_rays = po->rays;
    params.max_range_m = po->range_m;
    params.bev_columns = po->bev_columns;
    params.blocking.open_doors_block = !po->doors_open;
    const PerfectObserver observer(plan, params);
    ObservationRecord rec;
    rec.observation = observer.observe(pose);
    for (const LabeledSegment& s : observer.visible_world_segments(pose.position_m())) rec.segment_labels.push_back(s.label);
    if (rec.segment_labels.size() != rec.observation.segments_m.size()) rec.segment_labels.clear();
    rec.source = "perfect";
    rec.T_world_observer = pose;
    rec.metadata["plan"] = po->plan;
    rec.metadata["plan_hash"] = hex64(plan_hash(plan));
    rec.metadata["doors_closed"] = params.blocking.open_doors_block ? "true" : "false";
    rec.metadata["cut_height_m"] = std::to_string(params.blocking.cut_height_m);
    ensure_directory(po->out);
    const std::string path = po->out + "/observation.json";
    save_observation(path, rec);
    std::cout << "perfect: " << rec.observation.segments_m.size() << " visible segments, "
              << rec.observation.ray_ranges_m.size() << " rays"
              << (params.bev_columns > 0 ? ", BEV of " + std::to_string(params.bev_columns) + " columns" : std::string())
              << " within " << params.max_range_m << " m at "
              << format_pose(pose) << " -> " << path << "\n";
  });

  // ---- sim preview ----
  struct PreviewOptions {
    std::string scan_dir, out;
    int columns = ScanSheetStyle{}.columns;
    int tile_width = ScanSheetStyle{}.tile_width_px;
  };
  auto pv = std::make_shared<PreviewOptions>();
  auto* preview = sim.add_subcommand("preview", "Contact sheet of a scan folder: every view's colour image and depth map (PNG)");
  preview->add_option("SCAN_DIR", pv->scan_dir, "Scan folder")->required()->check(CLI::ExistingDirectory);
  preview->add_option("--columns", pv->columns, "Views per row")->capture_default_str()->check(in_range(1, 64));
  preview->add_option("--tile-width", pv->tile_width, "Width of each view in the sheet, pixels")
      ->capture_default_str()
      ->check(in_range(32, 2048));
  preview->add_option("-o,--output", pv->out, "Output PNG (- for standard output)")->required();
  preview->callback([pv] {
    ScanLoadOptions lo;
    lo.require_depth = false;
    lo.load_rgb = true;
    const Scan scan = load_scan(pv->scan_dir, lo);
    prepare_output_file(pv->out);
    ScanSheetStyle style;
    style.columns = pv->columns;
    style.tile_width_px = pv->tile_width;
    const DepthView& v0 = scan.views.front();
    const std::string title = std::filesystem::path(pv->scan_dir).filename().string() + ": " +
                              (scan.sensor.empty() ? std::string("scan") : scan.sensor) + ", " +
                              std::to_string(scan.views.size()) + " views, " + std::to_string(v0.intrinsics.width_px) +
                              "x" + std::to_string(v0.intrinsics.height_px);
    const cv::Mat sheet = draw_scan_contact_sheet(scan, title, style);
    write_png(pv->out, sheet);
    message_stream(pv->out) << "preview: " << scan.views.size() << " views -> " << pv->out << " (" << sheet.cols << "x" << sheet.rows << " px)\n";
  });

  // ---- sim extrude ----
  struct ExtrudeOptions {
    std::string plan, out;
    std::uint64_t seed = 0;
    BuildingOptions building;
  };
  auto eo = std::make_shared<ExtrudeOptions>();
  auto* ex = sim.add_subcommand("extrude", "Extrude a plan into a labelled 3D mesh (glTF 2.0 binary)");
  ex->add_option("PLAN", eo->plan, "Floor-plan JSON")->required();
  add_building_options(ex, eo->building);
  ex->add_option("--seed", eo->seed, "Clutter seed")->capture_default_str();
  ex->add_option("-o,--output", eo->out, "Output .glb file (- for standard output)")->required();
  ex->callback([eo] {
    if (eo->out != "-" && std::filesystem::path(eo->out).extension() != ".glb") {
      throw InputError(eo->out + ": output must be a .glb file");
    }
    const FloorPlan plan = load_floor_plan(eo->plan);
    prepare_output_file(eo->out);
    BuildingOptions b = eo->building;
    b.clutter_seed = eo->seed;
    const FloorPlan full = plan_with_clutter(plan, b, {});
    const Mesh mesh = extrude_plan(full, extrusion(b));
    const nlohmann::json meta{{"plan", eo->plan},
                              {"plan_hash", hex64(plan_hash(plan))},
                              {"wall_height_m", b.wall_height_m},
                              {"door_height_m", b.door_height_m},
                              {"clutter_density", b.clutter_density},
                              {"seed", eo->seed},
                              {"frame", "vertices: floorcast world (x, y plan metres, z up); root node rotates to y up"}};
    save_mesh_glb(eo->out, mesh, meta);
    std::ostream& msg = message_stream(eo->out);
    msg << "extrude: " << mesh.num_triangles() << " triangles (";
    for (int l = 0; l < kNumMeshLabels; ++l) {
      msg << (l ? ", " : "") << mesh_label_name(static_cast<MeshLabel>(l)) << " "
                << mesh.count(static_cast<MeshLabel>(l));
    }
    msg << "), " << (full.obstacles.size() - plan.obstacles.size()) << " clutter items -> " << eo->out << "\n";
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_sim);
}  // namespace floorcast::cli

// `floorcast observe SCAN_DIR -o DIR`: the observation module on a scan folder.
#include <array>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli_common.hpp"
#include "floorcast/core/json_text.hpp"
#include "floorcast/scenarios/run_directory.hpp"
#include "floorcast/observe/observation_module.hpp"
#include "floorcast/core/observation_io.hpp"
#include "floorcast/core/depth_io.hpp"
#include "floorcast/core/format.hpp"
#include "floorcast/core/ply_io.hpp"
#include "floorcast/eval/plot.hpp"
#include "floorcast/core/scan_io.hpp"
#include "floorcast/sim/scan_io.hpp"
#include "observe_cli.hpp"

namespace floorcast::cli {

namespace {
constexpr double kCloudVoxelM = 0.02;  // PLY clouds are voxelised: a scan has millions of pixels
}  // namespace

void add_observation_options(CLI::App& cmd, ObserveCliOptions& o) {
  cmd.add_option("--path", o.path, "Observation path: mono (PALMS+ depth -> Hough) or lidar (PALMS vertical planes)")
      ->check(CLI::IsMember({"mono", "lidar"}));
  cmd.add_option("--scale-alignment", o.scale_alignment, "Mono scale alignment (PALMS+ Table 4): full, ground or none")
      ->check(CLI::IsMember({"full", "ground", "none"}));
  cmd.add_option("--extractor", o.extractor, "LiDAR plane extractor: voxelplane (default) or pcl (normals + region growing)")
      ->check(CLI::IsMember({"pcl", "voxelplane"}));
  cmd.add_flag("--mask-glass", o.mask_glass, "Drop glass-affected pixels (the PALMS+* setting)");
  cmd.add_option("--observe-params", o.params_file,
                 "JSON file of observation-module parameter overrides (keys as in the diagnostics' \"params\")");
  cmd.add_option("--depth-dir", o.depth_dir,
                 "Bring your own depth: one depth map per view made elsewhere (a depth network run offline) replaces "
                 "the scan's depth; .npy/.tif/.exr in metres or 16-bit .png in millimetres, named after the view's "
                 "colour image (view_000_rgb.npy), view_000.EXT or view_000_depth.EXT; `track`: one such folder per "
                 "observation, DIR/observations/step_NNNN as in the walk folder, or DIR/step_NNNN")
      ->check(CLI::ExistingDirectory);
  cmd.add_option("--depth-kind", o.depth_kind, "What the --depth-dir maps measure: z (depth along the optical axis) or range (distance from the camera)")
      ->capture_default_str()
      ->check(CLI::IsMember({"z", "range"}));
  cmd.add_option("--bev", o.bev,
                 "Also make the semantic bird's-eye view for the bev matcher: the views' own BEV files, else the "
                 "simulated predictor with this error preset on the views' column semantics (`sim scan --semantics`)")
      ->check(CLI::IsMember(bev_predictor_presets()));
  cmd.add_option("--depth-unit", o.depth_unit_m, "Metres per unit of 16-bit --depth-dir maps (PNG, TIFF, NPY uint16)")
      ->capture_default_str()
      ->check(in_range(1e-6, 1.0));
}

Scan load_scan_for_observation(const std::string& scan_dir, const ObserveCliOptions& o) {
  ScanLoadOptions lo;
  lo.require_depth = o.depth_dir.empty();
  Scan scan = load_scan(scan_dir, lo);
  if (o.depth_dir.empty()) return scan;
  DepthFileOptions df;
  df.kind = parse_depth_kind(o.depth_kind);
  df.integer_unit_m = o.depth_unit_m;
  const DepthDirectoryReport report = load_depth_directory(scan, o.depth_dir, df);
  for (const std::string& r : report.repairs) std::cerr << "floorcast: repaired: " << r << "\n";
  scan.sensor += (scan.sensor.empty() ? "" : ", ") + std::string("depth from ") + o.depth_dir;
  return scan;
}

ObservationParams observation_params_from_cli(const ObserveCliOptions& o, const Scan* scan) {
  ObservationParams p;
  bool path_in_file = false;
  if (!o.params_file.empty()) {
    const nlohmann::json j = read_json_file(o.params_file);
    path_in_file = j.is_object() && j.contains("path");
    try {
      apply_overrides(p, j);
    } catch (const InputError& e) {
      throw InputError(o.params_file + ": " + e.what());
    }
  }
  if (!o.path.empty()) {
    p.path = parse_observation_path(o.path);
  } else if (!path_in_file && scan && scan->sensor == "lidar") {
    p.path = ObservationPath::kLidar;  // default path follows the scan's sensor
  }
  if (!o.scale_alignment.empty()) p.scale.mode = parse_scale_alignment(o.scale_alignment);
  if (!o.extractor.empty()) p.lidar.extractor = parse_plane_extractor(o.extractor);
  if (o.mask_glass) {
    p.back_projection.mask_glass = true;
    p.lidar.back_projection.mask_glass = true;
  }
  if (!o.bev.empty()) {
    p.bev.enabled = true;
    p.bev.preset = o.bev;
    p.bev.error = bev_error_preset(o.bev);
  }
  return p;
}

ObservationRecord observation_record(const Scan& scan, const std::string& scan_dir, const ObservationResult& r) {
  ObservationRecord rec;
  rec.observation = r.observation;
  rec.source = "observation module (" + r.diagnostics.path + ")";
  rec.metadata["scan"] = scan_dir;
  rec.metadata["sensor"] = scan.sensor;
  // Simulated scans carry their ground truth beside the sensor data; recorded scans do not.
  if (const std::optional<SimulationRecord> sim = load_simulation_record(scan_dir, scan.views.size())) {
    rec.T_world_observer = sim->truth.T_world_scan;
    rec.metadata["setting"] = scan_setting_name(sim->params.setting);
    if (!sim->truth.plan_hash.empty()) rec.metadata["plan_hash"] = sim->truth.plan_hash;
  }
  rec.metadata["path"] = r.diagnostics.path;
  rec.metadata["scale_alignment"] = r.diagnostics.scale_alignment;
  std::ostringstream scales;
  scales << std::setprecision(6);
  for (std::size_t k = 0; k < r.diagnostics.view_scales.size(); ++k) {
    scales << (k ? "," : "") << r.diagnostics.view_scales[k];
  }
  rec.metadata["view_scales"] = scales.str();
  if (r.diagnostics.ground.found) {
    std::ostringstream g;
    g << std::setprecision(6) << r.diagnostics.ground.height_m;
    rec.metadata["ground_height_m"] = g.str();
  }
  return rec;
}

nlohmann::ordered_json observation_diagnostics_json(const ObservationParams& params, const ObservationResult& r) {
  nlohmann::ordered_json j;
  j["diagnostics"] = to_json(r.diagnostics);
  nlohmann::ordered_json t;
  for (const auto& [k, v] : r.stage_s) t[k] = v;
  t["total"] = r.total_s;
  j["timings_s"] = t;
  j["params"] = to_json(params);
  return j;
}

void write_observation_clouds(const std::string& dir, const Scan& scan, const ObservationParams& params,
                              const ObservationResult& r) {
  ensure_directory(dir);
  const bool lidar = params.path == ObservationPath::kLidar;
  const BackProjectionResult bp =
      back_project_scan(scan, lidar ? params.lidar.back_projection : params.back_projection);
  const ObservationDiagnostics& d = r.diagnostics;
  PlyCloud raw, scaled;
  PointCloud3f scaled_all;
  for (const ViewCloud& v : bp.views) {
    const cv::Scalar c = series_colour(static_cast<std::size_t>(v.view_index));
    const std::array<std::uint8_t, 3> rgb{static_cast<std::uint8_t>(c[2]), static_cast<std::uint8_t>(c[1]),
                                          static_cast<std::uint8_t>(c[0])};
    for (const Eigen::Vector3f& p : voxel_downsample(view_points_scan(v, 1.0), kCloudVoxelM)) {
      raw.points_m.push_back(p);
      raw.colours_rgb.push_back(rgb);
    }
    // The final scale of this view, when the module kept it (mono: relative x global; LiDAR: 1).
    double scale = lidar ? 1.0 : -1.0;
    for (std::size_t i = 0; i < d.views_used.size() && i < d.view_scales.size(); ++i)
      if (d.views_used[i] == v.view_index) scale = d.view_scales[i];
    if (scale <= 0.0) continue;
    const PointCloud3f pts = view_points_scan(v, scale);
    scaled_all.insert(scaled_all.end(), pts.begin(), pts.end());
    for (const Eigen::Vector3f& p : voxel_downsample(pts, kCloudVoxelM)) {
      scaled.points_m.push_back(p);
      scaled.colours_rgb.push_back(rgb);
    }
  }
  PlyCloud slice;
  const double half = d.band_half_height_m > 0.0 ? d.band_half_height_m : params.slice.band_half_heights_m.front();
  const double range = lidar ? params.lidar.max_range_m : params.slice.max_range_m;
  for (const Eigen::Vector2d& q : slice_points(voxel_downsample(scaled_all, 0.01), half, range)) {
    slice.points_m.emplace_back(static_cast<float>(q.x()), static_cast<float>(q.y()), 0.0f);
    slice.colours_rgb.push_back({40, 40, 40});
  }
  const std::vector<std::string> frame = {"floorcast observation-module cloud", "frame: scan (x heading, y left, z up, origin camera centre), metres"};
  auto comments = [&frame](const std::string& what) {
    std::vector<std::string> c = frame;
    c.push_back(what);
    return c;
  };
  write_ply(dir + "/back_projected.ply", raw, comments("back-projected depth at scale 1, coloured by view, voxel 0.02 m"));
  write_ply(dir + "/scaled.ply", scaled, comments("each kept view at its final scale (scale alignment), voxel 0.02 m"));
  write_ply(dir + "/slice.ply", slice, comments("band +-" + format_general(half, 3) + " m around camera height projected to z = 0 (observer frame)"));
}

namespace {

void register_observe(CLI::App& root) {
  struct Options {
    std::string scan_dir, out;
    ObserveCliOptions obs;
    std::string clouds;
    bool quiet = false;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = root.add_subcommand(
      "observe", "Observation module: scan folder -> observed wall segments (observation JSON + diagnostics)");
  cmd->add_option("SCAN_DIR", o->scan_dir, "Scan folder (floorcast sim scan -o DIR)")->required();
  add_observation_options(*cmd, o->obs);
  cmd->add_option("--clouds", o->clouds,
                  "Folder for the module's point clouds as PLY (Open3D, CloudCompare): back_projected.ply, scaled.ply, "
                  "slice.ply");
  cmd->add_option("-o,--output", o->out,
                  "Output folder: observation.json (what `localize` takes) and observation.diagnostics.json (scales, "
                  "ground, point counts, timings, parameters). A path ending in .json is the deprecated spelling: the "
                  "observation file itself, diagnostics next to it as <name>.diagnostics.json")
      ->required();
  cmd->callback([o] {
    refuse_output_inside_inputs(o->out, {o->scan_dir});
    const Scan scan = load_scan_for_observation(o->scan_dir, o->obs);
    const ObservationParams params = observation_params_from_cli(o->obs, &scan);
    const ObservationResult r = observe_scan(scan, params);
    namespace fs = std::filesystem;
    fs::path obs_path, diag;
    if (fs::path(o->out).extension() == ".json") {  // the old grammar: -o names the observation file
      deprecation_note("observe -o FILE.json", "observe -o DIR (writes DIR/observation.json)");
      obs_path = o->out;
      if (obs_path.has_parent_path()) ensure_directory(obs_path.parent_path().string());
      diag = obs_path;
      diag.replace_extension(".diagnostics.json");
    } else {
      ensure_directory(o->out);
      obs_path = fs::path(o->out) / "observation.json";
      diag = fs::path(o->out) / "observation.diagnostics.json";
    }
    save_observation(obs_path.string(), observation_record(scan, o->scan_dir, r));
    write_json(diag.string(), observation_diagnostics_json(params, r));
    if (!o->clouds.empty()) write_observation_clouds(o->clouds, scan, params, r);
    const ObservationDiagnostics& d = r.diagnostics;
    std::cout << std::fixed << std::setprecision(3) << "observe (" << d.path;
    if (params.path == ObservationPath::kMono) std::cout << ", scale " << d.scale_alignment;
    std::cout << "): " << r.observation.segments_m.size() << " segments from " << d.views_used.size() << "/"
              << d.views_total << " views, " << d.points_back_projected << " points, " << r.total_s << " s\n";
    if (params.path == ObservationPath::kMono) {
      std::cout << "  view scales:";
      for (double s : d.view_scales) std::cout << " " << s;
      std::cout << "\n  ground: " << (d.ground.found ? std::to_string(d.ground.height_m) + " m" : "not found (" + d.ground.reason + ")")
                << ", global scale " << d.global_scale << ", band +-" << d.band_half_height_m << " m, "
                << d.points_in_slice << " points in slice\n";
    } else {
      std::cout << "  planes: " << d.planes_total << " (" << d.wall_planes << " walls)\n";
    }
    if (params.bev.enabled) {
      std::cout << "  BEV: " << r.observation.bev.size() << " (" << d.bev_columns << " columns from "
                << d.bev_views_used.size() << " views" << (d.bev_views_brought.empty() ? ", predictor " + params.bev.preset : ", brought")
                << ")\n";
    }
    for (const std::string& w : d.warnings) std::cout << "  warning: " << w << "\n";
    std::cout << "  -> " << obs_path.string() << ", " << diag.string() << "\n";
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_observe);
}  // namespace floorcast::cli

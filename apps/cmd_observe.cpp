// `floorcast observe SCAN_DIR -o OBS.json`: the observation module on a scan folder.
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli_common.hpp"
#include "floorcast/observe/observation_module.hpp"
#include "floorcast/core/observation_io.hpp"
#include "floorcast/core/scan_io.hpp"
#include "floorcast/sim/scan_io.hpp"
#include "observe_cli.hpp"

namespace floorcast::cli {

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
}

ObservationParams observation_params_from_cli(const ObserveCliOptions& o, const Scan* scan) {
  ObservationParams p;
  bool path_in_file = false;
  if (!o.params_file.empty()) {
    std::ifstream in(o.params_file);
    if (!in) throw InputError(o.params_file + ": cannot open");
    nlohmann::json j;
    try {
      in >> j;
    } catch (const std::exception& e) {
      throw InputError(o.params_file + ": not valid JSON: " + e.what());
    }
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

namespace {

void register_observe(CLI::App& root) {
  struct Options {
    std::string scan_dir, out;
    ObserveCliOptions obs;
    bool quiet = false;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = root.add_subcommand(
      "observe", "Observation module: scan folder -> observed wall segments (observation JSON + diagnostics)");
  cmd->add_option("SCAN_DIR", o->scan_dir, "Scan folder (floorcast sim scan -o DIR)")->required();
  add_observation_options(*cmd, o->obs);
  cmd->add_option("-o,--output", o->out,
                  "Observation JSON to write; diagnostics (scales, ground, point counts, timings, parameters) "
                  "go next to it as <name>.diagnostics.json")
      ->required();
  cmd->callback([o] {
    const Scan scan = load_scan(o->scan_dir);
    const ObservationParams params = observation_params_from_cli(o->obs, &scan);
    const ObservationResult r = observe_scan(scan, params);
    const std::filesystem::path out(o->out);
    if (out.has_parent_path()) ensure_directory(out.parent_path().string());
    save_observation(o->out, observation_record(scan, o->scan_dir, r));
    std::filesystem::path diag = out;
    diag.replace_extension(".diagnostics.json");
    write_json(diag.string(), observation_diagnostics_json(params, r));
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
    for (const std::string& w : d.warnings) std::cout << "  warning: " << w << "\n";
    std::cout << "  -> " << o->out << ", " << diag.string() << "\n";
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_observe);
}  // namespace floorcast::cli

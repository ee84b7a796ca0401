// `floorcast export SCENARIO.yaml -o DIR`: a scenario's scans as a dataset (per scan RGB, depth,
// intrinsics, TUM poses, masks, truth; F3Loc-style map.png + poses per building).
#include <chrono>
#include <iostream>
#include <memory>

#include "cli_common.hpp"
#include "floorcast/scenarios/dataset_export.hpp"

namespace floorcast::cli {
namespace {

void register_export(CLI::App& root) {
  struct Options {
    std::string scenario, out;
    bool no_rgb = false;
    std::vector<std::string> cells;
    double map_resolution_m = DatasetExportOptions{}.map_resolution_m;
    std::string camera = DatasetExportOptions{}.camera;
    bool quiet = false;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = root.add_subcommand(
      "export", "Export a scenario's scans as a dataset: RGB, sensor and ground-truth depth, intrinsics, TUM poses, masks, "
      "truth; an F3Loc dataset folder per cell (split.yaml, map.png, poses.txt, depth40/160.txt, rgb/NNNNN-l.png)");
  cmd->add_option("SCENARIO", o->scenario, "Scenario YAML file (its cells with observation.source: scan)")->required();
  cmd->add_flag("--no-rgb", o->no_rgb, "Skip the colour views (no OpenGL)");
  cmd->add_option("--cell", o->cells, "Export only this cell id (repeatable; default: every scan cell)");
  cmd->add_option("--map-resolution", o->map_resolution_m, "Metres per pixel of map.png (F3Loc: 0.01)")
      ->capture_default_str()
      ->check(in_range(0.001, 1.0));
  cmd->add_option("--camera", o->camera,
                  "Camera of the exported scans: scenario (as the scenario says; a note where F3Loc's differs) or f3loc "
                  "(F3Loc's hard-coded focal length / width 3/8, 106.26 deg across, no pitch)")
      ->capture_default_str()
      ->check(CLI::IsMember({"scenario", "f3loc"}));
  cmd->add_flag("--quiet", o->quiet, "No progress output");
  cmd->add_option("-o,--output", o->out, "Output folder")->required();
  cmd->callback([o] {
    const Scenario scenario = load_scenario(o->scenario, data_dir());
    DatasetExportOptions options;
    options.rgb = !o->no_rgb;
    options.cells = o->cells;
    options.map_resolution_m = o->map_resolution_m;
    options.camera = o->camera;
    ProgressMeter meter("scans", o->quiet);
    const auto t0 = std::chrono::steady_clock::now();
    const DatasetExportReport r = export_scenario_dataset(scenario, o->out, options, [&](std::size_t done, std::size_t total) {
      meter.update(done, total, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    });
    for (const std::string& n : r.notes) std::cerr << "note: " << n << "\n";
    std::cout << "export: " << r.scans << " scans" << (r.walk_scans ? " (+" + std::to_string(r.walk_scans) + " along walks)" : "")
              << ", " << r.images << " images -> " << o->out << " (layout in "
              << o->out << "/README.md)\n";
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_export);
}  // namespace floorcast::cli

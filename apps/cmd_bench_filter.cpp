// `floorcast bench filter`: tracker throughput (bench/filter_bench.hpp) on the shipped office and
// campus buildings, or given plans.
#include <algorithm>
#include <iomanip>
#include <iostream>
#include <memory>

#include "cli_common.hpp"
#include "floorcast/bench/filter_bench.hpp"
#include "floorcast/floorplans/io.hpp"

namespace floorcast::cli {
namespace {

void register_bench_filter(CLI::App& root) {
  struct Options {
    std::vector<std::string> plans;
    FilterBenchParams params;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  CLI::App& bench = group(root, "bench", "Benchmarks (medians over repeats, same-run ratios)");
  auto* cmd = bench.add_subcommand("filter", "Particle-filter steps/s (2000 particles, wall checks) and histogram-filter ms/step");
  cmd->add_option("--plan", o->plans,
                  "Plans (default: the shipped office and campus; a large real level: out/realplans/spbstu_main_L0.json "
                  "after scripts/import_realplans.sh)");
  cmd->add_option("--steps", o->params.steps, "Steps per repeat")->capture_default_str()->check(in_range(1, 100000));
  cmd->add_option("--repeats", o->params.repeats, "Repeats (the median is reported)")->capture_default_str()->check(in_range(1, 1000));
  cmd->add_option("--particles", o->params.particles, "Particles")->capture_default_str()->check(in_range(1, 10000000));
  cmd->add_option("--sequential-steps", o->params.sequential_steps, "Steps of the sequential histogram-filter walk")
      ->capture_default_str()
      ->check(in_range(10, 100000));
  cmd->add_option("--drop-mass", o->params.drop_mass,
                  "The sparse histogram filter's drop_mass in the sequential comparison (default: the tracker's default)")
      ->check(in_range(0.0, 0.1));
  cmd->add_flag("!--no-sequential", o->params.sequential,
                "Skip the sequential comparisons (measurement update: full posterior vs point queries; dense vs sparse histogram filter)");
  cmd->add_flag("!--no-particle-filter", o->params.particle_filter, "Skip the particle-filter throughput");
  cmd->add_flag("!--no-histogram-filter", o->params.histogram_filter, "Skip the histogram-filter throughput (uniform belief)");
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->callback([o] {
    std::vector<std::string> plans = o->plans;
    if (plans.empty()) {
      plans = {data_dir() + "/floorplans/buildings/office.json", data_dir() + "/floorplans/buildings/campus.json"};
    }
    nlohmann::ordered_json all = nlohmann::ordered_json::object();
    for (const std::string& path : plans) {
      const FloorPlan plan = load_floor_plan(path);
      const FilterBenchResult r = bench_filter(plan, o->params);
      all[plan.name] = to_json(r);
      if (!o->json) {
        // Only what was measured (a skipped part is not printed as zeros).
        std::cout << std::fixed << std::setprecision(1) << plan.name << ":";
        if (o->params.particle_filter) {
          std::cout << " particle filter " << r.pf_steps_per_s << " steps/s (" << o->params.particles << " particles, "
                    << std::setprecision(2) << r.pf_cpu_ms_per_step << " CPU-ms/step)" << (o->params.histogram_filter ? ";" : "");
        }
        if (o->params.histogram_filter) {
          std::cout << std::setprecision(1) << " histogram filter " << r.hf_ms_per_step << " ms/step (" << std::setprecision(2)
                    << r.hf_cpu_ms_per_step << " CPU-ms), " << std::setprecision(0) << r.hf_state_mb << " MB for " << r.grid_cells
                    << " cells x 36 directions; hist_mr " << std::setprecision(1) << r.hf_mr_ms_per_step << " ms/step ("
                    << std::setprecision(2) << r.hf_mr_cpu_ms_per_step << " CPU-ms)";
        }
        std::cout << "\n";
        if (o->params.sequential) {
          std::cout << std::setprecision(3) << "  particle-filter update (kernel, matching included): full posterior "
                    << r.pf_update_full_cpu_s << " CPU-s, point queries " << r.pf_update_points_cpu_s << " CPU-s ("
                    << std::setprecision(1) << r.pf_update_full_cpu_s / std::max(r.pf_update_points_cpu_s, 1e-9) << "x)\n"
                    << "  histogram filter, sequential (ray, observation every 10 steps): dense " << r.hf_seq_dense_ms
                    << " ms/step (" << r.hf_seq_dense_cpu_ms << " CPU-ms), sparse " << r.hf_seq_sparse_ms << " ms/step ("
                    << r.hf_seq_sparse_cpu_ms << " CPU-ms, second half " << r.hf_seq_sparse_late_cpu_ms << "; "
                    << std::setprecision(2) << 100.0 * r.hf_seq_live_share << "% of the cells live at the end, " << 100.0 * r.hf_seq_nonzero_share << "% non-zero)\n"
                    << "    sparse vs dense: estimates at most " << r.hf_seq_position_diff_m << " m and " << r.hf_seq_yaw_diff_deg
                    << " deg apart; dropped mass " << std::setprecision(6) << r.hf_seq_dropped_mass
                    << ", total variation at the end " << r.hf_seq_total_variation << "\n"
                    << std::setprecision(1) << "  hist_mr (coarse over the plan, fine window), same walk: " << r.hf_seq_mr_cpu_ms
                    << " CPU-ms/step (second half " << r.hf_seq_mr_late_cpu_ms << "); against dense where it converged ("
                    << r.hf_seq_dense_converged_steps << " steps): at most " << std::setprecision(2) << r.hf_seq_mr_converged_diff_m
                    << " m apart; end errors " << r.hf_seq_dense_end_error_m << " / " << r.hf_seq_mr_end_error_m << " m (dense / hist_mr)\n"
                    << std::setprecision(1) << "  particle filter, sequential (kernel point queries every 10 steps): "
                    << r.pf_seq_steps_per_s << " steps/s (" << std::setprecision(3) << r.pf_seq_cpu_ms << " CPU-ms/step)\n";
        }
      }
    }
    if (o->json) std::cout << all.dump(2) << "\n";
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_bench_filter);
}  // namespace floorcast::cli

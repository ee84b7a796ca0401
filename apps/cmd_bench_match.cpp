// `floorcast bench match`: layout-matcher cost (bench/match_bench.hpp) on the shipped campus or
// given plans — the kernel matcher's exact branch-and-bound modes beside its full FFT posterior
// and the FFT floor, the ray matcher's modes, max-over-yaw map and posterior — and, with
// --equivalence N, the search's modes against the posterior's on N seeded observations per plan
// (bench/modes_equivalence.hpp).
#include <iomanip>
#include <iostream>
#include <memory>

#include "cli_common.hpp"
#include "floorcast/bench/match_bench.hpp"
#include "floorcast/bench/modes_equivalence.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/match/kernel_matcher.hpp"

namespace floorcast::cli {
namespace {

using Json = nlohmann::ordered_json;

void print_kernel(const KernelMatchBench& k) {
  std::cout << std::fixed << std::setprecision(4);
  std::cout << "  kernel, O = " << std::setprecision(0) << k.orientations << " x " << k.scales
            << " scales (CPU s per observation, medians; wall in brackets):\n"
            << std::setprecision(4);
  std::cout << "    exact estimate + top-K (branch and bound) " << k.modes.cpu_s << " [" << k.modes.wall_s << "]\n";
  std::cout << "    exact estimate alone                      " << k.argmax.cpu_s << " [" << k.argmax.wall_s << "]\n";
  if (k.posteriors) {
    std::cout << "    full FFT posterior                        " << k.posterior.cpu_s << " [" << k.posterior.wall_s << "]  ("
              << std::setprecision(1) << k.posterior_over_modes << "x the search)\n"
              << std::setprecision(4);
  }
  std::cout << "    FFT floor (O x S full-size r2c + c2r)     " << k.fft_floor_cpu_s << "  (" << k.fft_pair_cpu_s
            << " per pair, " << k.fft_cols << " x " << k.fft_rows << ")";
  if (k.posteriors) std::cout << std::setprecision(2) << "; posterior / floor " << k.posterior_over_floor;
  std::cout << "\n" << std::setprecision(4);
  std::cout << "    own palms+ candidates (median " << std::setprecision(0) << k.own_candidates << "): estimate + top-K "
            << std::setprecision(4) << k.modes_own_candidates.cpu_s << " CPU s\n";
  std::cout << std::setprecision(1) << "    plan precompute " << std::setprecision(3) << k.precompute_wall_s << " s, "
            << std::setprecision(1) << k.precompute_mb << " MB (search maps " << k.search_maps_mb << " MB)\n";
  if (k.posteriors) {
    const ModesEquivalenceResult& e = k.equivalence;
    std::cout << "    search vs posterior on these observations: " << e.estimates_identical << " identical estimates, "
              << e.estimates_tied << " tied, " << e.estimates_fft_order << " ordered by FFT round-off, " << e.mismatches
              << " mismatches; top-K identical " << e.top_k_identical << ", up to a tie " << e.top_k_tied << "\n";
    std::cout << std::scientific << std::setprecision(1) << "    FFT max abs error " << k.fft_max_abs_error << std::fixed << "\n";
  }
}

void print_ray(const RayMatchBench& r) {
  std::cout << std::fixed << std::setprecision(3) << "  ray, " << r.directions << " directions: precompute " << r.precompute_s
            << " s, " << std::setprecision(1) << r.volume_mb << " MB\n"
            << std::setprecision(4);
  std::cout << "    estimate + top-K, bounded " << r.modes.cpu_s << " [" << r.modes.wall_s << "] (cells scored "
            << std::setprecision(1) << 100.0 * r.cells_scored_share << "%), exhaustive " << std::setprecision(4)
            << r.modes_exhaustive.cpu_s << " [" << r.modes_exhaustive.wall_s << "], identical " << r.bounded_modes_identical
            << "; max-over-yaw map " << r.max_over_yaw.cpu_s << " [" << r.max_over_yaw.wall_s << "]";
  if (r.posteriors) {
    std::cout << "; full posterior " << r.posterior.cpu_s << " [" << r.posterior.wall_s << "], " << std::setprecision(1)
              << r.posterior_mb << " MB";
  }
  std::cout << "\n";
}

void print_bev(const BevMatchBench& b) {
  std::cout << std::fixed << std::setprecision(3) << "  bev (" << (b.semantics ? "semantic" : "occupancy") << "), "
            << b.directions << " directions, " << b.orientations << " orientations: precompute " << b.precompute_wall_s
            << " s, " << std::setprecision(1) << b.precompute_mb << " MB\n";
  for (const BevViewBench& f : b.views) {
    std::cout << std::setprecision(0) << "    " << f.fov_deg << std::setprecision(4) << " deg (" << f.columns
              << " columns): estimate + top-K, bounded " << f.modes.cpu_s << " [" << f.modes.wall_s << "] (cells scored "
              << std::setprecision(1) << 100.0 * f.cells_scored_share << "%), exhaustive " << std::setprecision(4)
              << f.modes_exhaustive.cpu_s << " [" << f.modes_exhaustive.wall_s << "], identical " << f.bounded_modes_identical;
    if (f.posteriors) {
      std::cout << "; full posterior " << f.posterior.cpu_s << " [" << f.posterior.wall_s << "], " << std::setprecision(1)
                << f.posterior_mb << " MB";
    }
    std::cout << "\n";
  }
}

void register_bench_match(CLI::App& root) {
  CLI::App& bench = group(root, "bench", "Benchmarks (medians over repeats, same-run ratios)");
  struct Options {
    std::vector<std::string> plans;
    MatchBenchParams params;
    int equivalence = 0;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = bench.add_subcommand(
      "match", "Kernel: exact branch-and-bound modes vs full FFT posterior vs FFT floor; ray: modes, max-over-yaw, posterior");
  cmd->add_option("--plan", o->plans, "Floor plans (default: floorplans/buildings/campus.json)");
  cmd->add_option("--observations", o->params.observations, "Perfect observations to match (medians)")
      ->capture_default_str()
      ->check(in_range(1, 10000));
  cmd->add_option("--seed", o->params.seed, "Seed of the observation points")->capture_default_str();
  cmd->add_option("--region", o->params.region,
                  "Where the kernel and ray observers stand: uniform, or transitional (corridors, lobbies: the "
                  "scenarios' protocol)")
      ->capture_default_str()
      ->check(CLI::IsMember({"uniform", "transitional"}));
  cmd->add_option("--orientations", o->params.kernel_orientations,
                  "Kernel orientations: candidates padded to this many (PALMS+ O = 10; 0 = its own)")
      ->capture_default_str()
      ->check(in_range(0, 720));
  cmd->add_option("--top-k", o->params.top_k, "Modes asked for")->capture_default_str()->check(in_range(1, 100));
  cmd->add_option("--rays", o->params.ray_directions, "Ray matcher direction counts (none: --rays 0)")
      ->capture_default_str()
      ->delimiter(',');
  cmd->add_option("--precompute-repeats", o->params.ray_precompute_repeats, "Ray precomputations to time (median)")
      ->capture_default_str()
      ->check(in_range(1, 100));
  cmd->add_flag("!--no-posteriors", o->params.posteriors, "Skip the full posteriors");
  cmd->add_flag("!--no-kernel", o->params.kernel, "Skip the kernel matcher");
  cmd->add_option("--ray-bits", o->params.ray_volume_bits, "Ray matcher distance volume bits (8 or 16)")
      ->capture_default_str()
      ->check(CLI::IsMember({8, 16}));
  cmd->add_option("--bev-fov", o->params.bev_fov_deg,
                  "BEV matcher: fields of view of its observations, degrees (360: full circle; none: --bev-fov 0)")
      ->capture_default_str()
      ->delimiter(',');
  cmd->add_option("--bev-resolution", o->params.bev_resolution_m, "BEV matcher grid resolution, metres")
      ->capture_default_str()
      ->check(in_range(0.02, 1.0));
  cmd->add_option("--equivalence", o->equivalence,
                  "Instead: compare the search's modes with the posterior's on N seeded observations per plan")
      ->check(in_range(0, 100000));
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->callback([o] {
    std::vector<std::string> plans = o->plans;
    if (plans.empty()) plans = {data_dir() + "/floorplans/buildings/campus.json"};
    std::vector<int> rays;
    for (int d : o->params.ray_directions) {
      if (d < 0 || d == 1 || d == 2 || d == 3 || d > 3600) throw InputError("--rays: direction counts must be 4 - 3600 (or 0 for none)");
      if (d > 0) rays.push_back(d);
    }
    o->params.ray_directions = rays;
    std::vector<double> fovs;
    for (const double f : o->params.bev_fov_deg) {
      if (f < 0.0 || f > 360.0) throw InputError("--bev-fov: fields of view must be in (0, 360] (or 0 for none)");
      if (f > 0.0) fovs.push_back(f);
    }
    o->params.bev_fov_deg = fovs;
    Json all = Json::object();
    for (const std::string& path : plans) {
      const FloorPlan plan = load_floor_plan(path);
      const std::string name = std::filesystem::path(path).stem().string();
      if (o->equivalence > 0) {
        const KernelMatcher m(plan);
        ModesEquivalenceParams ep;
        ep.observations = o->equivalence;
        ep.seed = o->params.seed;
        ep.top_k = o->params.top_k;
        const ModesEquivalenceResult r = compare_modes_with_posterior(plan, m, ep);
        all[name] = to_json(r);
        if (!o->json) {
          std::cout << std::fixed << name << ": " << r.observations << " observations, top-" << ep.top_k << ": estimates "
                    << r.estimates_identical << " identical, " << r.estimates_tied << " tied, " << r.estimates_fft_order
                    << " FFT-ordered; top-K lists " << r.top_k_identical << " identical, " << r.top_k_tied
                    << " identical up to a tie; " << r.mismatches << " mismatches; no pose " << r.no_pose
                    << std::scientific << std::setprecision(1) << "; max tie gap " << r.max_tie_gap
                    << ", max FFT-order gap " << r.max_fft_order_gap << ", search vs direct sum " << r.max_search_error
                    << ", FFT error " << r.max_fft_error << std::fixed << std::setprecision(4) << "; wall s median: search "
                    << median(r.search_s) << ", posterior " << median(r.posterior_s) << "\n";
          for (const std::string& f : r.failures) std::cout << "  MISMATCH " << f << "\n";
        }
        continue;
      }
      const MatchBenchResult r = bench_match(plan, o->params);
      all[name] = to_json(r);
      if (o->json) continue;
      std::cout << "bench match on " << name << " (";
      if (r.kernel_measured)
        std::cout << r.grid_width_px << " x " << r.grid_height_px << " cells at 0.1 m, " << r.valid_cells << " valid; ";
      std::cout << r.threads << " threads; " << r.observations << " perfect observations; top-" << r.top_k << ")\n";
      if (r.kernel_measured) print_kernel(r.kernel);
      for (const RayMatchBench& x : r.ray) print_ray(x);
      for (const BevMatchBench& b : r.bev) print_bev(b);
    }
    if (o->json) std::cout << (plans.size() == 1 ? all.begin().value() : all).dump(2) << "\n";
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_bench_match);
}  // namespace floorcast::cli

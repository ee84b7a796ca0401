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

double num(const Json& j, const char* a, const char* b = nullptr) {
  const Json& x = b ? j.at(a).at(b) : j.at(a);
  return x.get<double>();
}

void print_kernel(const Json& k) {
  std::cout << std::fixed << std::setprecision(4);
  std::cout << "  kernel, O = " << std::setprecision(0) << num(k, "orientations") << " x " << num(k, "scales")
            << " scales (CPU s per observation, medians; wall in brackets):\n"
            << std::setprecision(4);
  std::cout << "    exact estimate + top-K (branch and bound) " << num(k, "modes", "cpu_s") << " ["
            << num(k, "modes", "wall_s") << "]\n";
  std::cout << "    exact estimate alone                      " << num(k, "argmax", "cpu_s") << " ["
            << num(k, "argmax", "wall_s") << "]\n";
  if (k.contains("posterior")) {
    std::cout << "    full FFT posterior                        " << num(k, "posterior", "cpu_s") << " ["
              << num(k, "posterior", "wall_s") << "]  (" << std::setprecision(1) << num(k, "posterior_over_modes")
              << "x the search)\n"
              << std::setprecision(4);
  }
  std::cout << "    FFT floor (O x S full-size r2c + c2r)     " << num(k, "fft_floor_cpu_s") << "  ("
            << num(k, "fft_pair_cpu_s") << " per pair, " << k["fft_size"][0] << " x " << k["fft_size"][1] << ")";
  if (k.contains("posterior")) std::cout << std::setprecision(2) << "; posterior / floor " << num(k, "posterior_over_floor");
  std::cout << "\n" << std::setprecision(4);
  std::cout << "    own palms+ candidates (median " << std::setprecision(0) << num(k, "own_candidates")
            << "): estimate + top-K " << std::setprecision(4) << num(k, "modes_own_candidates", "cpu_s") << " CPU s\n";
  std::cout << std::setprecision(1) << "    plan precompute " << std::setprecision(3) << num(k, "precompute_wall_s")
            << " s, " << std::setprecision(1) << num(k, "precompute_mb") << " MB (search maps "
            << num(k, "search_maps_mb") << " MB)\n";
  if (k.contains("equivalence")) {
    const Json& e = k["equivalence"];
    std::cout << "    search vs posterior on these observations: " << e["estimates_identical"] << " identical estimates, "
              << e["estimates_tied"] << " tied, " << e["estimates_fft_order"] << " ordered by FFT round-off, "
              << e["mismatches"] << " mismatches; top-K identical " << e["top_k_identical"] << ", up to a tie "
              << e["top_k_tied"] << "\n";
    std::cout << std::scientific << std::setprecision(1) << "    FFT max abs error " << num(k, "fft_max_abs_error")
              << std::fixed << "\n";
  }
}

void print_ray(const std::string& D, const Json& r) {
  std::cout << std::fixed << std::setprecision(3) << "  ray, " << D << " directions: precompute "
            << num(r, "precompute_s") << " s, " << std::setprecision(1) << num(r, "volume_mb") << " MB\n"
            << std::setprecision(4);
  std::cout << "    estimate + top-K, bounded " << num(r, "modes", "cpu_s") << " [" << num(r, "modes", "wall_s")
            << "] (cells scored " << std::setprecision(1) << 100.0 * num(r, "search_counters", "cells_scored_share")
            << "%), exhaustive " << std::setprecision(4) << num(r, "modes_exhaustive", "cpu_s") << " ["
            << num(r, "modes_exhaustive", "wall_s") << "], identical " << r.value("bounded_modes_identical", 0)
            << "; max-over-yaw map " << num(r, "max_over_yaw", "cpu_s") << " [" << num(r, "max_over_yaw", "wall_s") << "]";
  if (r.contains("posterior")) {
    std::cout << "; full posterior " << num(r, "posterior", "cpu_s") << " [" << num(r, "posterior", "wall_s") << "], "
              << std::setprecision(1) << num(r, "posterior_mb") << " MB";
  }
  std::cout << "\n";
}

void print_bev(const std::string& variant, const Json& b) {
  std::cout << std::fixed << std::setprecision(3) << "  bev (" << variant << "), " << b["directions"] << " directions, "
            << b["orientations"] << " orientations: precompute " << num(b, "precompute_wall_s") << " s, "
            << std::setprecision(1) << num(b, "precompute_mb") << " MB\n";
  for (auto it = b.begin(); it != b.end(); ++it) {
    if (it.key().rfind("fov_", 0) != 0) continue;
    const Json& f = it.value();
    std::cout << std::setprecision(4) << "    " << it.key().substr(4) << " deg (" << f["columns"]
              << " columns): estimate + top-K, bounded " << num(f, "modes", "cpu_s") << " [" << num(f, "modes", "wall_s")
              << "] (cells scored " << std::setprecision(1) << 100.0 * num(f, "search_counters", "cells_scored_share")
              << "%), exhaustive " << std::setprecision(4) << num(f, "modes_exhaustive", "cpu_s") << " ["
              << num(f, "modes_exhaustive", "wall_s") << "], identical " << f.value("bounded_modes_identical", 0);
    if (f.contains("posterior")) {
      std::cout << "; full posterior " << num(f, "posterior", "cpu_s") << " [" << num(f, "posterior", "wall_s") << "], "
                << std::setprecision(1) << num(f, "posterior_mb") << " MB";
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
      const Json j = bench_match(plan, o->params);
      all[name] = j;
      if (o->json) continue;
      std::cout << "bench match on " << name << " (";
      if (j.contains("grid_px"))
        std::cout << j["grid_px"][0] << " x " << j["grid_px"][1] << " cells at 0.1 m, " << j["valid_cells"] << " valid; ";
      std::cout << j["threads"] << " threads; " << o->params.observations << " perfect observations; top-"
                << o->params.top_k << ")\n";
      if (j.contains("kernel")) print_kernel(j["kernel"]);
      for (const auto& [d, r] : j["ray"].items()) print_ray(d, r);
      if (j.contains("bev")) {
        for (const auto& [variant, b] : j["bev"].items()) print_bev(variant, b);
      }
    }
    if (o->json) std::cout << (plans.size() == 1 ? all.begin().value() : all).dump(2) << "\n";
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_bench_match);
}  // namespace floorcast::cli

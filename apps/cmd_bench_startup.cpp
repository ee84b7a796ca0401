// `floorcast bench startup`: what every process of a sweep pays before doing any work. Runs
// `EXE --version` (dynamic loading, static initialisation, command registration, exit) as child
// processes and reports medians of their CPU time (user + system, from wait4), wall time and peak
// resident memory; with --exe, other executables (an older build) are measured in the same run,
// interleaved, so their ratio is not skewed by the machine's load drifting. The shared libraries
// this process mapped at start (before any command ran or module was loaded) are listed too.

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <set>

#include "cli_common.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/core/types.hpp"

namespace floorcast::cli {
namespace {

/// Shared libraries mapped into this process now (paths of *.so* file mappings).
std::set<std::string> mapped_libraries() {
  std::set<std::string> libs;
  std::ifstream maps("/proc/self/maps");
  std::string line;
  while (std::getline(maps, line)) {
    const std::size_t slash = line.find('/');
    if (slash == std::string::npos) continue;
    const std::string path = line.substr(slash);
    if (path.find(".so") != std::string::npos) libs.insert(path);
  }
  return libs;
}

/// One run of `exe --version` with its output to /dev/null.
ChildCost run_once(const std::string& exe) { return run_child(exe, {"--version"}, "", "bench startup"); }

void register_bench_startup(CLI::App& root) {
  struct Options {
    std::vector<std::string> others;
    int runs = 21;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  // Read before any command runs: what the dynamic loader mapped for every floorcast process.
  static const std::set<std::string> at_start = mapped_libraries();
  CLI::App& bench = group(root, "bench", "Benchmarks (medians over repeats, same-run ratios)");
  auto* cmd = bench.add_subcommand("startup", "Process start cost of the CLI (`floorcast --version` as child processes)");
  cmd->add_option("--runs", o->runs, "Runs per executable (medians reported)")->capture_default_str()->check(in_range(1, 10000));
  cmd->add_option("--exe", o->others, "Other executables measured in the same run (e.g. an older build)")->check(CLI::ExistingFile);
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->callback([o] {
    std::vector<std::string> exes = {std::filesystem::read_symlink("/proc/self/exe").string()};
    exes.insert(exes.end(), o->others.begin(), o->others.end());
    std::vector<std::vector<ChildCost>> costs(exes.size());
    for (const std::string& e : exes) run_once(e);  // warm the page cache
    for (int r = 0; r < o->runs; ++r)
      for (std::size_t i = 0; i < exes.size(); ++i) costs[i].push_back(run_once(exes[i]));
    nlohmann::ordered_json out = nlohmann::ordered_json::object();
    out["runs"] = o->runs;
    out["libraries_mapped_at_start"] = at_start.size();
    out["libraries"] = at_start;
    nlohmann::ordered_json rows = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < exes.size(); ++i) {
      auto med = [&](double ChildCost::*field) {
        std::vector<double> v;
        for (const ChildCost& c : costs[i]) v.push_back(c.*field);
        return median(v);
      };
      nlohmann::ordered_json row;
      row["exe"] = exes[i];
      row["cpu_ms_median"] = 1e3 * med(&ChildCost::cpu_s);
      row["wall_ms_median"] = 1e3 * med(&ChildCost::wall_s);
      row["max_rss_mb_median"] = med(&ChildCost::max_rss_mb);
      rows.push_back(row);
    }
    for (std::size_t i = 1; i < rows.size(); ++i)
      rows[i]["cpu_ratio_to_first"] = rows[i]["cpu_ms_median"].get<double>() / std::max(1e-9, rows[0]["cpu_ms_median"].get<double>());
    out["executables"] = rows;
    if (o->json) {
      std::cout << out.dump(2) << "\n";
      return;
    }
    std::cout << "shared libraries mapped at start: " << at_start.size() << "\n";
    for (const auto& row : rows) {
      std::cout << std::fixed << std::setprecision(1) << row["exe"].get<std::string>() << ": "
                << row["cpu_ms_median"].get<double>() << " CPU-ms, " << row["wall_ms_median"].get<double>()
                << " ms wall, " << row["max_rss_mb_median"].get<double>() << " MB peak (median of " << o->runs << ")";
      if (row.contains("cpu_ratio_to_first")) std::cout << ", CPU x" << std::setprecision(2) << row["cpu_ratio_to_first"].get<double>() << " of the first";
      std::cout << "\n";
    }
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_bench_startup);
}  // namespace floorcast::cli

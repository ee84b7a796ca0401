// `floorcast run`, `floorcast merge`, `floorcast gate`: scenarios end to end.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>

#include "cli_common.hpp"
#include "floorcast/eval/gate.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/scenarios/run_directory.hpp"
#include "floorcast/scenarios/runner.hpp"

namespace floorcast::cli {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using OJson = nlohmann::ordered_json;

class DirectorySink : public UnitSink {
 public:
  DirectorySink(const RunDirectory& dir, const Scenario& s) : dir_(dir), scenario_(s) {}
  bool has_unit(const WorkUnit& u) const override { return dir_.has_unit(scenario_, u); }
  void write_unit(const UnitResult& r) override { dir_.write_unit(scenario_, r); }
  void write_image(const std::string& p, const cv::Mat& img) override { dir_.write_image(p, img); }

 private:
  const RunDirectory& dir_;
  const Scenario& scenario_;
};

std::string duration_text(double s) {
  if (!std::isfinite(s) || s < 0) return "--";
  char buf[32];
  const int total = static_cast<int>(std::lround(s));
  if (total >= 3600) std::snprintf(buf, sizeof buf, "%dh%02dm", total / 3600, (total / 60) % 60);
  else if (total >= 60) std::snprintf(buf, sizeof buf, "%dm%02ds", total / 60, total % 60);
  else std::snprintf(buf, sizeof buf, "%ds", total);
  return buf;
}

/// Progress bar with ETA on a terminal, plain lines (every 10% or 15 s) otherwise.
class ProgressPrinter {
 public:
  explicit ProgressPrinter(bool quiet) : quiet_(quiet), tty_(isatty(fileno(stderr)) != 0) {}
  void operator()(const RunProgress& p) {
    if (quiet_) return;
    const double eta = p.finished > 0 ? p.elapsed_s / p.finished * (p.to_run - p.finished) : NAN;
    if (tty_) {
      const int width = 30;
      const int filled = p.to_run ? static_cast<int>(width * p.finished / p.to_run) : width;
      std::fprintf(stderr, "\r[%s%s] %zu/%zu units (%zu resumed)  elapsed %s  ETA %s   ",
                   std::string(filled, '#').c_str(), std::string(width - filled, '.').c_str(), p.finished, p.to_run,
                   p.skipped, duration_text(p.elapsed_s).c_str(), duration_text(eta).c_str());
      if (p.finished == p.to_run) std::fprintf(stderr, "\n");
      std::fflush(stderr);
      return;
    }
    const int decile = p.to_run ? static_cast<int>(10 * p.finished / p.to_run) : 10;
    if (p.finished == 0 || p.finished == p.to_run || decile > last_decile_ || p.elapsed_s - last_print_s_ >= 15.0) {
      std::fprintf(stderr, "progress: %zu/%zu units (%zu resumed), elapsed %s, ETA %s\n", p.finished, p.to_run,
                   p.skipped, duration_text(p.elapsed_s).c_str(), duration_text(eta).c_str());
      last_decile_ = decile;
      last_print_s_ = p.elapsed_s;
    }
  }

 private:
  bool quiet_;
  bool tty_;
  int last_decile_ = -1;
  double last_print_s_ = 0.0;
};

/// Reference-workload times recorded in run.json (one per run invocation / shard), and their
/// median, for the summary's timing block.
OJson timing_block(const std::vector<double>& references) {
  std::vector<double> r = references;
  OJson t;
  t["reference_s"] = r.empty() ? OJson(nullptr) : OJson(median(r));
  t["reference_runs_s"] = r;
  t["reference_workload"] = "1024x1024 float DFT forward+inverse + 15x15 Gaussian blur, 1 thread (eval/timing.hpp)";
  return t;
}

std::vector<double> recorded_references(const RunDirectory& dir) {
  const Json info = dir.read_run_info();
  std::vector<double> out;
  if (info.contains("reference_s") && info["reference_s"].is_object())
    for (auto it = info["reference_s"].begin(); it != info["reference_s"].end(); ++it)
      if (it.value().is_number()) out.push_back(it.value().get<double>());
  return out;
}

void record_reference(const RunDirectory& dir, const std::string& key, double value) {
  Json info = dir.read_run_info();
  Json refs = info.value("reference_s", Json::object());
  if (!refs.is_object()) refs = Json::object();
  refs[key] = value;
  dir.update_run_info("reference_s", refs);
}

/// Builds and writes the report when every unit is present. Returns false (writing nothing) when
/// some are missing.
bool report_if_complete(const Scenario& s, const RunDirectory& dir, bool print_table) {
  const std::vector<UnitResult> units = dir.read_units(s);
  const std::size_t expected = enumerate_units(s).size();
  if (units.size() != expected) return false;
  const Report rep = build_report(s, units, timing_block(recorded_references(dir)));
  dir.write_report(rep);
  if (print_table) std::cout << rep.summary_md;
  return true;
}

/// The resolved scenario stored with a run (without the code-resolved parameter block).
Scenario stored_scenario(const RunDirectory& dir) {
  Json resolved = dir.read_resolved_config();
  resolved.erase("resolved_parameters");
  return scenario_from_resolved(resolved, (fs::path(dir.root()) / "resolved_config.json").string());
}

}  // namespace

void run_scenario(const Scenario& scenario, const std::string& out, int jobs, const std::string& shard_text, bool quiet) {
  const auto t0 = std::chrono::steady_clock::now();
  const ShardSpec shard = parse_shard(shard_text);
  auto log = [quiet](const std::string& line) {
    if (!quiet) std::cerr << "prepare: " << line << "\n";
  };
  const ScenarioRunner runner(scenario, log);
  RunDirectory dir(out);
  dir.open(scenario, runner.resolved_full());
  DirectorySink sink(dir, scenario);
  ProgressPrinter printer(quiet);
  RunOptions options;
  options.jobs = jobs;
  options.shard = shard;
  options.on_progress = [&printer](const RunProgress& p) { printer(p); };
  const RunOutcome outcome = runner.run(sink, options);
  if (outcome.executed > 0) record_reference(dir, shard_text, outcome.reference_s);
  const double total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!quiet)
    std::cerr << "ran " << outcome.executed << " units, " << outcome.skipped << " already done, in "
              << duration_text(total_s) << "\n";
  if (report_if_complete(scenario, dir, true)) {
    if (!quiet) std::cerr << "wrote " << out << "/summary.md, summary.json, observations.csv, plots/\n";
  } else {
    std::cerr << "shard " << shard_text << " finished (" << outcome.units_in_shard << " of " << outcome.units_total
              << " units); combine the shards with `floorcast merge DIR... -o OUT` for the report\n";
  }
}

namespace {

void register_run(CLI::App& root) {
  struct RunOpts {
    std::string scenario;
    std::string out;
    int jobs = 0;
    std::string shard = "0/1";
    bool quiet = false;
  };
  auto o = std::make_shared<RunOpts>();
  CLI::App* run = root.add_subcommand("run", "Run a scenario: simulate -> observe -> match -> score for every sweep cell");
  run->add_option("SCENARIO", o->scenario, "Scenario YAML file")->required();
  run->add_option("-o,--out", o->out, "Run directory (resumes if it holds a run of the same configuration)")->required();
  run->add_option("--jobs", o->jobs, "Concurrent work units (default: all cores)")->check(CLI::NonNegativeNumber);
  run->add_option("--shard", o->shard, "Run only shard I of N (0 <= I < N); combine shards with `floorcast merge`");
  run->add_flag("--quiet", o->quiet, "No progress output");
  run->callback([o] {
    const Scenario scenario = load_scenario(o->scenario, source_dir());
    run_scenario(scenario, o->out, o->jobs, o->shard, o->quiet);
  });
}

void register_merge(CLI::App& root) {
  struct MergeOpts {
    std::vector<std::string> inputs;
    std::string out;
  };
  auto o = std::make_shared<MergeOpts>();
  CLI::App* merge = root.add_subcommand("merge", "Combine shard run directories into one run and write its report");
  merge->add_option("DIRS", o->inputs, "Run directories of the shards")->required();
  merge->add_option("-o,--out", o->out, "Merged run directory")->required();
  merge->callback([o] {
    std::string hash;
    std::unique_ptr<Scenario> scenario;
    Json resolved_full;
    for (const std::string& in : o->inputs) {
      const RunDirectory dir(in);
      const Json info = dir.read_run_info();
      const std::string h = info.value("configuration_hash", std::string());
      if (hash.empty()) {
        hash = h;
        resolved_full = dir.read_resolved_config();
        scenario = std::make_unique<Scenario>(stored_scenario(dir));
      } else if (h != hash) {
        throw InputError(in + ": configuration hash " + h + " differs from " + o->inputs.front() + " (" + hash +
                         "); only shards of one scenario run can be merged");
      }
    }
    RunDirectory out(o->out);
    out.open(*scenario, OJson(resolved_full));
    DirectorySink sink(out, *scenario);
    std::size_t copied = 0;
    for (const std::string& in : o->inputs) {
      const RunDirectory dir(in);
      for (const UnitResult& u : dir.read_units(*scenario)) {
        if (out.has_unit(*scenario, u.unit)) {
          const Json existing = Json::parse(read_text_file(out.unit_path(*scenario, u.unit)));
          if (strip_timings(OJson(existing)).dump() != strip_timings(unit_to_json(u)).dump())
            throw InputError(in + ": unit " + u.unit.id + " differs from the copy already merged; the shards disagree");
          continue;
        }
        out.write_unit(*scenario, u);
        ++copied;
      }
      const Json info = dir.read_run_info();
      if (info.contains("reference_s") && info["reference_s"].is_object())
        for (auto it = info["reference_s"].begin(); it != info["reference_s"].end(); ++it)
          if (it.value().is_number()) record_reference(out, in + " " + it.key(), it.value().get<double>());
      const fs::path heat = fs::path(in) / "heatmaps";
      if (fs::is_directory(heat)) {
        fs::create_directories(fs::path(o->out) / "heatmaps");
        for (const auto& e : fs::directory_iterator(heat))
          fs::copy_file(e.path(), fs::path(o->out) / "heatmaps" / e.path().filename(), fs::copy_options::overwrite_existing);
      }
    }
    std::cerr << "merged " << copied << " units from " << o->inputs.size() << " directories into " << o->out << "\n";
    if (!report_if_complete(*scenario, out, true)) {
      const std::size_t have = out.read_units(*scenario).size(), want = enumerate_units(*scenario).size();
      throw InputError(o->out + ": " + std::to_string(want - have) + " of " + std::to_string(want) +
                       " work units are missing (a shard was not run or not given); no report written");
    }
  });
}

void register_gate(CLI::App& root) {
  struct GateOpts {
    std::string summary;
    std::string baseline;
  };
  auto o = std::make_shared<GateOpts>();
  CLI::App* gate = root.add_subcommand("gate", "Check a run's summary.json against a stored baseline (CI gate)");
  gate->add_option("SUMMARY", o->summary, "summary.json of a run")->required();
  gate->add_option("--baseline", o->baseline, "Baseline JSON (results/baselines/NAME.json)")->required();
  gate->callback([o] {
    auto parse = [](const std::string& path) {
      try {
        return Json::parse(read_text_file(path));
      } catch (const Json::exception& e) {
        throw InputError(path + ": malformed JSON: " + e.what());
      }
    };
    const Json summary = parse(o->summary);
    if (!summary.value("complete", false)) throw InputError(o->summary + ": not a complete run summary");
    const GateOutcome g = evaluate_gate(summary, parse(o->baseline), o->baseline);
    for (const std::string& line : g.passes) std::cout << line << "\n";
    for (const std::string& line : g.failures) std::cout << "FAIL: " << line << "\n";
    if (!g.passed) {
      std::cerr << "floorcast gate: " << g.failures.size() << " check(s) failed against " << o->baseline << "\n";
      throw CommandExit{1};
    }
    std::cout << "gate passed (" << g.passes.size() << " checks)\n";
  });
}

void register_compare_runs(CLI::App& root) {
  struct Opts {
    std::string a, b;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* cmd = root.add_subcommand(
      "compare-runs", "Check that two run directories hold the same results (timings excluded); exit 1 if not");
  cmd->add_option("RUN_A", o->a, "Run directory")->required();
  cmd->add_option("RUN_B", o->b, "Run directory")->required();
  cmd->callback([o] {
    const RunDirectory a(o->a), b(o->b);
    const std::string ha = a.read_run_info().value("configuration_hash", std::string());
    const std::string hb = b.read_run_info().value("configuration_hash", std::string());
    if (ha != hb) {
      std::cout << "different configurations: " << ha << " vs " << hb << "\n";
      throw CommandExit{1};
    }
    const Scenario s = stored_scenario(a);
    std::map<std::string, std::string> units_a, units_b;
    for (const UnitResult& u : a.read_units(s)) units_a[u.unit.id] = strip_timings(unit_to_json(u)).dump();
    for (const UnitResult& u : b.read_units(s)) units_b[u.unit.id] = strip_timings(unit_to_json(u)).dump();
    std::size_t differ = 0;
    for (const WorkUnit& w : enumerate_units(s)) {
      const bool in_a = units_a.count(w.id), in_b = units_b.count(w.id);
      if (!in_a || !in_b) {
        std::cout << w.id << ": only in " << (in_a ? o->a : in_b ? o->b : std::string("neither")) << "\n";
        ++differ;
      } else if (units_a[w.id] != units_b[w.id]) {
        std::cout << w.id << ": results differ\n";
        ++differ;
      }
    }
    if (differ > 0) {
      std::cout << differ << " of " << enumerate_units(s).size() << " units differ\n";
      throw CommandExit{1};
    }
    std::cout << "identical: " << units_a.size() << " units (timings excluded)\n";
  });
}

void register_scenario_commands(CLI::App& root) {
  register_run(root);
  register_merge(root);
  register_gate(root);
  register_compare_runs(root);
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_scenario_commands);
}  // namespace floorcast::cli

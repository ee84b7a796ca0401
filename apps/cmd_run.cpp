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
#include "floorcast/core/json_text.hpp"
#include "floorcast/eval/gate.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/core/file_io.hpp"
#include "floorcast/scenarios/report_html.hpp"
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
  void write_file(const std::string& p, const std::string& bytes) override { dir_.write_file(p, bytes); }

 private:
  const RunDirectory& dir_;
  const Scenario& scenario_;
};

/// Units of a scenario run: progress with ETA (cli::ProgressMeter).
class ProgressPrinter {
 public:
  explicit ProgressPrinter(bool quiet) : meter_("units", quiet) {}
  void operator()(const RunProgress& p) {
    meter_.update(p.finished, p.to_run, p.elapsed_s, "(" + std::to_string(p.skipped) + " resumed)");
  }

 private:
  ProgressMeter meter_;
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

/// The resolved scenario stored with a run.
Scenario stored_scenario(const RunDirectory& dir) { return dir.stored_scenario(); }

}  // namespace

void run_scenario(const Scenario& scenario, const std::string& out, int jobs, const std::string& shard_text, bool quiet,
                  bool print_summary) {
  const auto t0 = std::chrono::steady_clock::now();
  const ShardSpec shard = parse_shard(shard_text);
  auto log = [quiet](const std::string& line) {
    if (!quiet) std::cerr << "prepare: " << line << "\n";
  };
  // The output folder is taken (locked, proven writable, stray temporaries of a killed run
  // removed) before any work starts.
  RunDirectory dir(out);
  const std::size_t stray = dir.acquire();
  if (stray > 0 && !quiet) std::cerr << out << ": removed " << stray << " stray temporary file(s) of an interrupted run\n";
  const ScenarioRunner runner(scenario, log);
  dir.open(scenario, runner.resolved_full());
  // The plans as the run uses them (generated buildings included), for figures and reports.
  for (std::size_t b = 0; b < scenario.buildings.size(); ++b) {
    const std::string rel = "plans/" + scenario.buildings[b].label + ".json";
    if (!fs::exists(fs::path(out) / rel)) dir.write_file(rel, floor_plan_to_json(runner.building_plan(static_cast<int>(b))));
  }
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
  if (report_if_complete(scenario, dir, print_summary)) {
    if (!quiet) std::cerr << "wrote " << out << "/summary.md, summary.json, observations.csv, plots/\n";
  } else if (!quiet) {
    std::cerr << "shard " << shard_text << " finished (" << outcome.units_in_shard << " of " << outcome.units_total
              << " units); combine the shards with `floorcast merge DIR... -o OUT` for the report\n";
  }
}

void write_html_report(const std::string& run_dir) {
  HtmlReportOptions options;
  options.generator = std::string("floorcast ") + FLOORCAST_VERSION;
  write_text_file_atomic((fs::path(run_dir) / "report.html").string(), render_run_report_html(RunDirectory(run_dir), options));
}

void merge_runs(const std::vector<std::string>& inputs, const std::string& out_dir, bool quiet) {
  std::string hash;
  std::unique_ptr<Scenario> scenario;
  Json resolved_full;
  for (const std::string& in : inputs) {
    const RunDirectory dir(in);
    const Json info = dir.read_run_info();
    const std::string h = info.value("configuration_hash", std::string());
    if (hash.empty()) {
      hash = h;
      resolved_full = dir.read_resolved_config();
      scenario = std::make_unique<Scenario>(stored_scenario(dir));
    } else if (h != hash) {
      throw InputError(in + ": configuration hash " + h + " differs from " + inputs.front() + " (" + hash +
                       "); only shards of one scenario run can be merged");
    }
  }
  // Merging into one of the inputs (a merged folder merged again) adds only what is missing and
  // checks the rest for equality; an output strictly inside an input folder is refused.
  {
    std::error_code ec;
    const auto canon = [&](const std::string& p) { return fs::weakly_canonical(fs::absolute(p, ec), ec); };
    std::vector<std::string> others;
    for (const std::string& in : inputs) {
      if (canon(in) != canon(out_dir)) others.push_back(in);
    }
    refuse_output_inside_inputs(out_dir, others);
  }
  RunDirectory out(out_dir);
  out.open(*scenario, OJson(resolved_full));
  DirectorySink sink(out, *scenario);
  std::size_t copied = 0;
  for (const std::string& in : inputs) {
    const RunDirectory dir(in);
    for (const UnitResult& u : dir.read_units(*scenario)) {
      if (out.has_unit(*scenario, u.unit)) {
        // Compare values, not text: the copy on disk may list keys in another order (a merged
        // folder merged again, a unit written by another version).
        const std::string path = out.unit_path(*scenario, u.unit);
        const UnitResult existing = unit_from_json(read_json_file(path), path);
        if (Json(strip_timings(unit_to_json(existing))) != Json(strip_timings(unit_to_json(u))))
          throw InputError(in + ": unit " + u.unit.id + " differs from the copy already merged; the shards disagree");
        continue;
      }
      out.write_unit(*scenario, u);
      ++copied;
    }
    // Merging the output folder into itself (again): its units are there, nothing else to copy.
    std::error_code same_ec;
    if (fs::equivalent(fs::path(in), fs::path(out_dir), same_ec)) continue;
    const Json info = dir.read_run_info();
    if (info.contains("reference_s") && info["reference_s"].is_object())
      for (auto it = info["reference_s"].begin(); it != info["reference_s"].end(); ++it)
        if (it.value().is_number()) record_reference(out, in + " " + it.key(), it.value().get<double>());
    for (const char* sub : {"heatmaps", "plans"}) {
      const fs::path from = fs::path(in) / sub;
      if (!fs::is_directory(from)) continue;
      fs::create_directories(fs::path(out_dir) / sub);
      for (const auto& e : fs::directory_iterator(from))
        fs::copy_file(e.path(), fs::path(out_dir) / sub / e.path().filename(), fs::copy_options::overwrite_existing);
    }
  }
  if (!quiet) std::cerr << "merged " << copied << " units from " << inputs.size() << " directories into " << out_dir << "\n";
  if (!report_if_complete(*scenario, out, !quiet)) {
    const std::size_t have = out.read_units(*scenario).size(), want = enumerate_units(*scenario).size();
    throw InputError(out_dir + ": " + std::to_string(want - have) + " of " + std::to_string(want) +
                     " work units are missing (a shard was not run or not given); no report written");
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
    bool html = false;
  };
  auto o = std::make_shared<RunOpts>();
  CLI::App* run = root.add_subcommand("run", "Run a scenario: simulate -> observe -> match -> score for every sweep cell");
  run->add_option("SCENARIO", o->scenario, "Scenario YAML file")->required();
  run->add_option("-o,--output", o->out, "Run directory (resumes if it holds a run of the same configuration)")->required();
  run->add_option("--jobs", o->jobs, "Concurrent work units (default: all cores)")->check(CLI::NonNegativeNumber);
  run->add_option("--shard", o->shard, "Run only shard I of N (0 <= I < N); combine shards with `floorcast merge`");
  run->add_flag("--quiet", o->quiet, "No progress output");
  run->add_flag("--html", o->html, "Also write DIR/report.html (as `floorcast report`) when the run is complete");
  run->callback([o] {
    const Scenario scenario = load_scenario(o->scenario, source_dir());
    run_scenario(scenario, o->out, o->jobs, o->shard, o->quiet);
    if (o->html && fs::is_regular_file(fs::path(o->out) / "summary.json")) {
      write_html_report(o->out);
      if (!o->quiet) std::cerr << "wrote " << o->out << "/report.html\n";
    }
  });
}

void register_merge(CLI::App& root) {
  struct MergeOpts {
    std::vector<std::string> inputs;
    std::string out;
    bool html = false;
  };
  auto o = std::make_shared<MergeOpts>();
  CLI::App* merge = root.add_subcommand(
      "merge", "Combine shard run directories into one run: its units, summary.md, summary.json, observations.csv and "
               "plots/ (the HTML page: --html, or `floorcast report`)");
  merge->add_option("DIRS", o->inputs, "Run directories of the shards")->required();
  merge->add_option("-o,--output", o->out, "Merged run directory")->required();
  merge->add_flag("--html", o->html, "Also write DIR/report.html (as `floorcast report`)");
  merge->callback([o] {
    merge_runs(o->inputs, o->out, false);
    if (o->html) {
      write_html_report(o->out);
      std::cerr << "wrote " << o->out << "/report.html\n";
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
    auto parse = [](const std::string& path) { return read_json_file(path); };
    const Json summary = parse(o->summary);
    if (!summary.is_object()) throw InputError(o->summary + ": not a run summary (expected a JSON object)");
    if (!summary.contains("complete") || summary["complete"] != true) throw InputError(o->summary + ": not a complete run summary");
    const Json baseline = parse(o->baseline);
    const GateOutcome g = evaluate_gate(summary, baseline, o->baseline);
    for (const std::string& line : g.passes) std::cout << line << "\n";
    for (const std::string& line : g.failures) std::cout << "FAIL: " << line << "\n";
    if (!g.passed) {
      std::cerr << "floorcast gate: " << g.failures.size() << " check(s) failed against " << o->baseline << "\n";
      throw CommandExit{kExitCheckFailed};
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
      throw CommandExit{kExitCheckFailed};
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
      throw CommandExit{kExitCheckFailed};
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

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
#include "floorcast/scenarios/driver.hpp"
#include "floorcast/scenarios/report_html.hpp"

namespace floorcast::cli {
namespace {
namespace fs = std::filesystem;
using Json = nlohmann::json;
}  // namespace

void run_scenario(const Scenario& scenario, const std::string& out, int jobs, const std::string& shard_text, bool quiet,
                  bool print_summary) {
  ProgressMeter meter("units", quiet);
  RunRequest request;
  request.jobs = jobs;
  request.shard = shard_text;
  request.on_prepare = [quiet](const std::string& line) {
    if (!quiet) std::cerr << "prepare: " << line << "\n";
  };
  request.on_folder_taken = [&out, quiet](std::size_t stray) {
    if (stray > 0 && !quiet) std::cerr << out << ": removed " << stray << " stray temporary file(s) of an interrupted run\n";
  };
  request.on_progress = [&meter](const RunProgress& p) {
    meter.update(p.finished, p.to_run, p.elapsed_s, "(" + std::to_string(p.skipped) + " resumed)");
  };
  const RunSummary summary = floorcast::run_scenario(scenario, out, request);
  if (!quiet)
    std::cerr << "ran " << summary.outcome.executed << " units, " << summary.outcome.skipped << " already done, in "
              << duration_text(summary.total_s) << "\n";
  if (summary.summary_md) {
    if (print_summary) std::cout << *summary.summary_md;
    if (!quiet) std::cerr << "wrote " << out << "/summary.md, summary.json, observations.csv, plots/\n";
  } else if (!quiet) {
    std::cerr << "shard " << shard_text << " finished (" << summary.outcome.units_in_shard << " of "
              << summary.outcome.units_total
              << " units); combine the shards with `floorcast merge DIR... -o OUT` for the report\n";
  }
}

void write_html_report(const std::string& run_dir) {
  HtmlReportOptions options;
  options.generator = std::string("floorcast ") + FLOORCAST_VERSION;
  write_text_file_atomic((fs::path(run_dir) / "report.html").string(), render_run_report_html(RunDirectory(run_dir), options));
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
  run->add_option("--jobs", o->jobs, "Concurrent work units (default: all cores)")->check(in_range(0, 4096));
  run->add_option("--shard", o->shard, "Run only shard I of N (0 <= I < N); combine shards with `floorcast merge`");
  run->add_flag("--quiet", o->quiet, "No progress output");
  run->add_flag("--html", o->html, "Also write DIR/report.html (as `floorcast report`) when the run is complete");
  run->callback([o] {
    const Scenario scenario = load_scenario(o->scenario, data_dir());
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
    const MergeSummary m = merge_runs(o->inputs, o->out);
    std::cerr << "merged " << m.copied << " units from " << o->inputs.size() << " directories into " << o->out << "\n";
    std::cout << m.summary_md;
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
    std::string a, b, json;
    bool any_configuration = false;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* cmd = root.add_subcommand(
      "compare-runs",
      "Check that two run directories hold the same results (timings excluded); exit 1 if not. When they differ "
      "(another configuration, a changed method), compare their methods on the units both hold: McNemar's exact test "
      "and paired bootstrap intervals");
  cmd->add_option("RUN_A", o->a, "Run directory")->required();
  cmd->add_option("RUN_B", o->b, "Run directory")->required();
  cmd->add_flag("--any-configuration", o->any_configuration,
                "Compare the units even when the configuration hashes differ (runs of one scenario by two versions "
                "of floorcast)");
  cmd->add_option("--json", o->json, "Also write the paired comparisons as JSON to this file");
  cmd->callback([o] {
    const RunComparison c = compare_runs(o->a, o->b, o->any_configuration);
    // Paired comparisons of the two runs' methods on their shared units (printed when they differ).
    auto paired = [&] {
      std::cout << "\nA = " << o->a << ", B = " << o->b << "\n\n"
                << cross_run_comparisons_md(c.paired, RunDirectory(o->a).stored_scenario());
      if (c.paired.empty()) std::cout << "no units in common (same unit id and true pose): nothing to compare pairwise\n";
      if (!o->json.empty()) write_json(o->json, cross_run_comparisons_json(c.paired, o->a, o->b));
    };
    if (!c.same_configuration && o->any_configuration) {
      std::cout << "configurations differ (" << c.hash_a << " vs " << c.hash_b << "); comparing the units by id\n";
    }
    if (!c.same_configuration && !o->any_configuration) {
      std::cout << "different configurations: " << c.hash_a << " vs " << c.hash_b << "\n";
      paired();
      throw CommandExit{kExitCheckFailed};
    }
    for (const std::string& line : c.differences) std::cout << line << "\n";
    if (!c.differences.empty()) {
      std::cout << c.differences.size() << " of " << c.units << " units differ\n";
      paired();
      throw CommandExit{kExitCheckFailed};
    }
    std::cout << "identical: " << c.identical << " units (timings excluded)\n";
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

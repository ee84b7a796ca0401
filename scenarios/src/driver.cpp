#include "floorcast/scenarios/driver.hpp"

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>

#include "floorcast/core/json_text.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/scenarios/report.hpp"
#include "floorcast/scenarios/run_directory.hpp"

namespace floorcast {
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

std::map<std::string, double> recorded_references(const RunDirectory& dir) {
  const Json info = dir.read_run_info();
  std::map<std::string, double> out;
  if (info.contains("reference_s") && info["reference_s"].is_object())
    for (auto it = info["reference_s"].begin(); it != info["reference_s"].end(); ++it)
      if (it.value().is_number()) out[it.key()] = it.value().get<double>();
  return out;
}

void record_reference(const RunDirectory& dir, const std::string& key, double value) {
  Json info = dir.read_run_info();
  Json refs = info.value("reference_s", Json::object());
  if (!refs.is_object()) refs = Json::object();
  refs[key] = value;
  dir.update_run_info("reference_s", refs);
}

/// Builds and writes the report when every unit is present; nullopt (writing nothing) when some
/// are missing.
std::optional<std::string> report_if_complete(const Scenario& s, const RunDirectory& dir) {
  const std::vector<UnitResult> units = dir.read_units(s);
  const std::size_t expected = enumerate_units(s).size();
  if (units.size() != expected) return std::nullopt;
  std::vector<double> refs;
  for (const auto& [key, value] : recorded_references(dir)) refs.push_back(value);
  const Report rep = build_report(s, units, timing_block(refs));
  dir.write_report(rep);
  return rep.summary_md;
}

}  // namespace

RunSummary run_scenario(const Scenario& scenario, const std::string& out, const RunRequest& request) {
  const auto t0 = std::chrono::steady_clock::now();
  const ShardSpec shard = parse_shard(request.shard);
  RunSummary summary;
  // The output folder is taken (locked, proven writable, stray temporaries of a killed run
  // removed) before any work starts.
  RunDirectory dir(out);
  summary.stray_removed = dir.acquire();
  if (request.on_folder_taken) request.on_folder_taken(summary.stray_removed);
  const ScenarioRunner runner(scenario, request.on_prepare);
  dir.open(scenario, runner.resolved_full());
  // The plans as the run uses them (generated buildings included), for figures and reports.
  for (std::size_t b = 0; b < scenario.buildings.size(); ++b) {
    const std::string rel = "plans/" + scenario.buildings[b].label + ".json";
    if (!fs::exists(fs::path(out) / rel)) dir.write_file(rel, floor_plan_to_json(runner.building_plan(static_cast<int>(b))));
  }
  DirectorySink sink(dir, scenario);
  RunOptions options;
  options.jobs = request.jobs;
  options.shard = shard;
  options.on_progress = request.on_progress;
  summary.outcome = runner.run(sink, options);
  if (summary.outcome.executed > 0) record_reference(dir, request.shard, summary.outcome.reference_s);
  summary.total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  summary.summary_md = report_if_complete(scenario, dir);
  return summary;
}

MergeSummary merge_runs(const std::vector<std::string>& inputs, const std::string& out_dir) {
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
      scenario = std::make_unique<Scenario>(dir.stored_scenario());
    } else if (h != hash) {
      throw InputError(in + ": configuration hash " + h + " differs from " + inputs.front() + " (" + hash +
                       "); only shards of one scenario run can be merged");
    }
  }
  if (!scenario) throw InputError("merge: no run directories given");
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
  MergeSummary summary;
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
      ++summary.copied;
    }
    // Merging the output folder into itself (again): its units are there, nothing else to copy.
    std::error_code same_ec;
    if (fs::equivalent(fs::path(in), fs::path(out_dir), same_ec)) continue;
    for (const auto& [key, value] : recorded_references(dir)) record_reference(out, in + " " + key, value);
    for (const char* sub : {"heatmaps", "plans"}) {
      const fs::path from = fs::path(in) / sub;
      if (!fs::is_directory(from)) continue;
      fs::create_directories(fs::path(out_dir) / sub);
      for (const auto& e : fs::directory_iterator(from))
        fs::copy_file(e.path(), fs::path(out_dir) / sub / e.path().filename(), fs::copy_options::overwrite_existing);
    }
  }
  std::optional<std::string> md = report_if_complete(*scenario, out);
  if (!md) {
    const std::size_t have = out.read_units(*scenario).size(), want = enumerate_units(*scenario).size();
    throw InputError(out_dir + ": " + std::to_string(want - have) + " of " + std::to_string(want) +
                     " work units are missing (a shard was not run or not given); no report written");
  }
  summary.summary_md = std::move(*md);
  return summary;
}

RunComparison compare_runs(const std::string& run_a, const std::string& run_b, bool any_configuration) {
  const RunDirectory a(run_a), b(run_b);
  RunComparison c;
  c.hash_a = a.read_run_info().value("configuration_hash", std::string());
  c.hash_b = b.read_run_info().value("configuration_hash", std::string());
  c.same_configuration = c.hash_a == c.hash_b;
  auto paired = [&] {
    const Scenario sa = a.stored_scenario(), sb = b.stored_scenario();
    return compare_runs_paired(sa, a.read_units(sa), "A", sb, b.read_units(sb), "B");
  };
  if (!c.same_configuration && !any_configuration) {
    c.paired = paired();
    return c;
  }
  const Scenario s = a.stored_scenario();
  std::map<std::string, std::string> units_a, units_b;
  for (const UnitResult& u : a.read_units(s)) units_a[u.unit.id] = strip_timings(unit_to_json(u)).dump();
  for (const UnitResult& u : b.read_units(s)) units_b[u.unit.id] = strip_timings(unit_to_json(u)).dump();
  const std::vector<WorkUnit> all = enumerate_units(s);
  c.units = all.size();
  for (const WorkUnit& w : all) {
    const bool in_a = units_a.count(w.id), in_b = units_b.count(w.id);
    if (!in_a || !in_b) {
      c.differences.push_back(w.id + ": only in " + (in_a ? run_a : in_b ? run_b : std::string("neither")));
    } else if (units_a[w.id] != units_b[w.id]) {
      c.differences.push_back(w.id + ": results differ");
    } else {
      ++c.identical;
    }
  }
  if (!c.identical_results()) c.paired = paired();
  return c;
}

std::string data_dir() {
  static const std::string root = [] {
    auto is_root = [](const fs::path& p) {
      std::error_code ec;
      return fs::is_regular_file(p / "scenarios" / "quickstart.yaml", ec) &&
             fs::is_directory(p / "floorplans" / "buildings", ec);
    };
    if (const char* env = std::getenv("FLOORCAST_DATA_DIR"); env && *env) return std::string(env);
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
      // Installed: <prefix>/bin/floorcast with the data in <prefix>/share/floorcast.
      const fs::path installed = exe.parent_path().parent_path() / "share" / "floorcast";
      if (is_root(installed)) return installed.string();
      // Built inside the source tree (build/bin/floorcast, or any depth below it).
      for (fs::path p = exe.parent_path(); !p.empty() && p != p.root_path(); p = p.parent_path()) {
        if (is_root(p)) return p.string();
      }
    }
    // Last resort: the working directory (a checkout run from its root).
    return fs::current_path(ec).string();
  }();
  return root;
}

}  // namespace floorcast

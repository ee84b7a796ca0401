// The experiment driver: a scenario run into a run directory (lock, resume, shards, progress,
// report), shards merged into one run, two runs compared. `floorcast run`, `merge`,
// `compare-runs`, `compare-matchers` and the Python module are thin fronts on these functions;
// they print, the driver only reports what happened (progress through a callback).
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "floorcast/scenarios/report.hpp"
#include "floorcast/scenarios/runner.hpp"
#include "floorcast/scenarios/scenario.hpp"

namespace floorcast {

struct RunRequest {
  int jobs = 0;                  ///< concurrent work units; 0 = all cores
  std::string shard = "0/1";     ///< "I/N": run only shard I of N
  /// After every finished unit (serialised).
  std::function<void(const RunProgress&)> on_progress;
  /// One line per preparation step (loading buildings, building matchers).
  std::function<void(const std::string&)> on_prepare;
  /// Once the folder is taken, before any work: how many stray temporaries of an interrupted run
  /// were removed from it.
  std::function<void(std::size_t)> on_folder_taken;
};

struct RunSummary {
  std::size_t stray_removed = 0;  ///< stray temporaries of an interrupted run removed from the folder
  RunOutcome outcome;
  double total_s = 0.0;           ///< wall seconds of the whole call
  /// Set when every unit of the scenario is present: the report was written (its Markdown here).
  std::optional<std::string> summary_md;
};

/// Runs `scenario` (or request.shard of it) into run directory `out`: the folder is taken (locked,
/// proven writable) before any work, units already there are skipped (resume), finished units are
/// written atomically, and the report is written when every unit is present. Throws InputError
/// when the folder holds another configuration's run or is locked by another process.
RunSummary run_scenario(const Scenario& scenario, const std::string& out, const RunRequest& request = {});

struct MergeSummary {
  std::size_t copied = 0;   ///< units copied into the output
  std::string summary_md;   ///< the merged report's Markdown (merge refuses incomplete sets)
};

/// Combines shard run directories of one configuration into `out` (which may be one of them)
/// and writes the report. Units present in several inputs must agree (timings excluded). Throws
/// InputError for differing configurations, disagreeing units, an output inside an input, or
/// missing units (then no report is written).
MergeSummary merge_runs(const std::vector<std::string>& inputs, const std::string& out);

struct RunComparison {
  std::string hash_a, hash_b;
  bool same_configuration = false;
  std::size_t units = 0;          ///< units of the scenario
  std::size_t identical = 0;      ///< units present in both with the same results
  /// One line per difference ("c000/apartment/p003: results differ", "...: only in DIR").
  std::vector<std::string> differences;
  /// When the runs differ (another configuration, or units whose results differ): their methods
  /// compared on the units both hold (same unit id and true pose): McNemar's exact test and paired
  /// bootstrap intervals, per cell. Empty when the runs are identical.
  std::vector<CrossRunComparison> paired;
  bool identical_results() const { return same_configuration && differences.empty(); }
};

/// Compares two run directories unit by unit, timings excluded. Runs of different configurations
/// are not compared (same_configuration false) unless `any_configuration`: then their units are
/// compared by id (runs of one scenario made by two versions of floorcast whose resolved
/// configurations differ, e.g. by a new parameter with its default).
RunComparison compare_runs(const std::string& run_a, const std::string& run_b, bool any_configuration = false);

/// Where floorcast's shipped data (floorplans/buildings, scenarios, results/baselines) is: the
/// FLOORCAST_DATA_DIR environment variable when set; else <prefix>/share/floorcast next to an
/// installed binary; else the source tree the binary was built in (found by walking up from the
/// executable); else the working directory. Nothing of the build machine is compiled in.
std::string data_dir();

}  // namespace floorcast

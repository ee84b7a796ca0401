// The on-disk layout of a scenario run (the scenarios library's io part).
//
//   DIR/run.lock                  held (flock) by the process writing the run; holds its pid
//   DIR/run.json                  run identity: scenario name, hash of the full resolved configuration
//   DIR/resolved_config.json      every parameter with its value (defaults filled in)
//   DIR/units/<cell>/<building>/<point>.json   one finished work unit (written atomically)
//   DIR/heatmaps/*.png            posterior overlays of sampled observations; *.npy + *.json the
//                                 best score over heading and its grid, truth and estimate
//   DIR/plans/<building>.json     the plan of every building as the run used it (generated ones
//                                 included), for figures
//   DIR/observations.csv, summary.json, summary.md, plots/*.png   the report
#pragma once

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "floorcast/scenarios/report.hpp"
#include "floorcast/scenarios/units.hpp"

namespace floorcast {

class RunDirectory {
 public:
  explicit RunDirectory(std::string root);
  ~RunDirectory();
  RunDirectory(const RunDirectory&) = delete;
  RunDirectory& operator=(const RunDirectory&) = delete;

  /// Takes the folder for writing, before any work starts: creates it, refuses a folder that
  /// exists, is not empty and holds no run (run.json), refuses it while another process holds it
  /// (DIR/run.lock, an exclusive flock, names the holder's pid), proves it writable (a probe file)
  /// and removes stray *.tmp files a killed run left behind. Returns how many it removed. The
  /// lock is held until this object is destroyed. Throws InputError.
  std::size_t acquire();

  /// Creates the layout and writes run.json + resolved_config.json (acquire()s first when not
  /// yet done). If DIR already holds a run with a different configuration hash, throws
  /// InputError: results are never mixed.
  void open(const Scenario& scenario, const nlohmann::ordered_json& resolved_full);

  /// run.json of an existing run directory (throws InputError if absent or invalid).
  nlohmann::json read_run_info() const;
  nlohmann::json read_resolved_config() const;

  std::string unit_path(const Scenario& scenario, const WorkUnit& unit) const;
  /// True when the unit's result is on disk and no method errored in it (unit_has_errors): a
  /// resumed run runs such units again (an external method fixed in between).
  bool has_unit(const Scenario& scenario, const WorkUnit& unit) const;
  /// Atomic (temporary file + rename): a killed run never leaves a half-written unit.
  void write_unit(const Scenario& scenario, const UnitResult& result) const;
  /// Every finished unit of the scenario present in this directory.
  std::vector<UnitResult> read_units(const Scenario& scenario) const;

  void write_image(const std::string& relative_path, const cv::Mat& image) const;
  /// Any other file under the run (atomic): heatmap data, the plans the run used.
  void write_file(const std::string& relative_path, const std::string& bytes) const;
  void write_report(const Report& report) const;
  /// Adds a key to run.json (e.g. the reference workload time of this run).
  void update_run_info(const std::string& key, const nlohmann::json& value) const;

  /// The scenario stored with the run (resolved_config.json without the code-resolved parameter
  /// block), as `merge`, `compare-runs` and `report` rebuild it.
  Scenario stored_scenario() const;

  const std::string& root() const { return root_; }

 private:
  std::string root_;
  int lock_fd_ = -1;
};

/// Refuses (InputError) an output path that equals or lies inside one of `input_dirs` (folders
/// given as inputs: scan, walk, IMDF, run directories): writing there would mix results into the
/// input data. `what` names the option ("-o").
void refuse_output_inside_inputs(const std::string& output, const std::vector<std::string>& input_dirs,
                                 const std::string& what = "-o");

/// Hex digest identifying a full resolved configuration: scenario_hash (content, never paths).
std::string configuration_hash(const nlohmann::ordered_json& resolved_full);

}  // namespace floorcast

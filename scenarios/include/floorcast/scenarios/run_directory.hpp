// The on-disk layout of a scenario run (the scenarios library's io part).
//
//   DIR/run.json                  run identity: scenario name, hash of the full resolved configuration
//   DIR/resolved_config.json      every parameter with its value (defaults filled in)
//   DIR/units/<cell>/<building>/<point>.json   one finished work unit (written atomically)
//   DIR/heatmaps/*.png            posterior overlays of sampled observations
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

  /// Creates the layout and writes run.json + resolved_config.json. If DIR already holds a run
  /// with a different configuration hash, throws InputError: results are never mixed.
  void open(const Scenario& scenario, const nlohmann::ordered_json& resolved_full);

  /// run.json of an existing run directory (throws InputError if absent or invalid).
  nlohmann::json read_run_info() const;
  nlohmann::json read_resolved_config() const;

  std::string unit_path(const Scenario& scenario, const WorkUnit& unit) const;
  bool has_unit(const Scenario& scenario, const WorkUnit& unit) const;
  /// Atomic (temporary file + rename): a killed run never leaves a half-written unit.
  void write_unit(const Scenario& scenario, const UnitResult& result) const;
  /// Every finished unit of the scenario present in this directory.
  std::vector<UnitResult> read_units(const Scenario& scenario) const;

  void write_image(const std::string& relative_path, const cv::Mat& image) const;
  void write_report(const Report& report) const;
  /// Adds a key to run.json (e.g. the reference workload time of this run).
  void update_run_info(const std::string& key, const nlohmann::json& value) const;

  /// The scenario stored with the run (resolved_config.json without the code-resolved parameter
  /// block), as `merge`, `compare-runs` and `report` rebuild it.
  Scenario stored_scenario() const;

  const std::string& root() const { return root_; }

 private:
  std::string root_;
};

/// Hex digest identifying a full resolved configuration.
std::string configuration_hash(const nlohmann::ordered_json& resolved_full);

}  // namespace floorcast

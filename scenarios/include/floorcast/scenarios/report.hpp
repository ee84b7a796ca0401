// Turning unit results into what a person reads: observations.csv, summary.json, summary.md
// (tables in the papers' layout) and plots. Pure: returns contents, writes nothing.
#pragma once

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

#include "floorcast/scenarios/scenario.hpp"
#include "floorcast/scenarios/units.hpp"

namespace floorcast {

struct Report {
  std::string observations_csv;   ///< one row per work unit, matcher columns side by side
  nlohmann::ordered_json summary; ///< metrics per cell, per building group ("all" + labels), per matcher
  std::string summary_md;         ///< Markdown tables
  std::vector<std::pair<std::string, cv::Mat>> plots;  ///< file name -> BGR image
};

/// `units` must hold every unit of the scenario (the report refuses to pass partial results off
/// as complete: it throws InputError listing how many are missing). `timing` is copied into the
/// summary (reference workload time and anything else measured at run level).
Report build_report(const Scenario& scenario, const std::vector<UnitResult>& units,
                    const nlohmann::ordered_json& timing);

/// Formats the single-shot records of one matcher in one group.
std::vector<SingleShotRecord> records_for(const std::vector<const UnitResult*>& units, const std::string& label);

}  // namespace floorcast

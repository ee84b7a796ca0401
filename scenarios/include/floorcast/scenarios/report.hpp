// Turning unit results into what a person reads: observations.csv, summary.json, summary.md
// (tables in the papers' layout) and plots. Pure: returns contents, writes nothing.
#pragma once

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

#include "floorcast/eval/paired.hpp"
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

/// A paired comparison as stored in summary.json (cells[i].paired.<group>."A vs B"): a, b, count,
/// per recall criterion {both, only_a, only_b, neither, p_value, difference, ci95}, per metric
/// {difference, ci95, lower_is_better}. Differences are A - B; null when undefined.
nlohmann::ordered_json paired_comparison_json(const PairedComparison& comparison);

/// The Markdown table of paired comparisons on one criterion (e.g. recall_1m_30deg) and one
/// metric (e.g. median_position_error_m); "" without pairs. `units_word`: "points", "walks".
std::string paired_comparisons_md(const std::vector<PairedComparison>& pairs, const std::string& criterion,
                                  const std::string& criterion_title, const std::string& metric,
                                  const std::string& metric_title, const std::string& units_word);

/// Paired comparisons between two runs (e.g. before and after a change) on the units both hold:
/// the same unit id with the same true pose. For every cell id both runs have, every matcher of
/// run A against every matcher of run B, and every tracker against every tracker; labels are
/// "<name_a>:<label>" and "<name_b>:<label>". Scored with run A's scoring parameters.
struct CrossRunComparison {
  std::string cell;
  int shared_units = 0;
  std::vector<PairedComparison> matchers;
  std::vector<PairedComparison> trackers;
};
std::vector<CrossRunComparison> compare_runs_paired(const Scenario& scenario_a, const std::vector<UnitResult>& units_a,
                                                    const std::string& name_a, const Scenario& scenario_b,
                                                    const std::vector<UnitResult>& units_b, const std::string& name_b);

/// Markdown tables of compare_runs_paired's result ("" when nothing is shared).
std::string cross_run_comparisons_md(const std::vector<CrossRunComparison>& comparisons, const Scenario& scenario_a);

/// The same as JSON: {"a": run_a, "b": run_b, "cells": [{cell, shared_units, matchers: {"X vs Y":
/// paired comparison}, trackers: {...}}]}.
nlohmann::ordered_json cross_run_comparisons_json(const std::vector<CrossRunComparison>& comparisons,
                                                  const std::string& run_a, const std::string& run_b);

/// Formats the single-shot records of one matcher in one group.
std::vector<SingleShotRecord> records_for(const std::vector<const UnitResult*>& units, const std::string& label);
/// Rejection records (positives and negatives) of one method over units: localized = the
/// observation worked and the method gave a pose; correct = positive and within the combined
/// threshold.
std::vector<RejectionRecord> rejection_records_for(const std::vector<const UnitResult*>& units, const std::string& label,
                                                  const ScoringParams& scoring);

}  // namespace floorcast

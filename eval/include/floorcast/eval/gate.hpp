// CI gates: compare a run's summary.json against a stored baseline.
//
// Baseline file (JSON):
//   {"description": "...",
//    "scenario_hash": "0123abcd...",   // the summary's "hash": `floorcast gate` refuses any other
//    "checks": [{"pointer": "/cells/0/groups/all/kernel/recall_1m_30deg", "min": 0.8},
//               {"pointer": "/cells/0/groups/all/kernel/median_position_error_m", "max": 0.5}],
//    "timing_ratios": [{"name": "kernel / reference",
//                       "numerator": "/cells/0/groups/all/kernel/mean_time_s",
//                       "denominator": "/timing/reference_s",
//                       "baseline": 12.0, "tolerance": 1.0}]}
//    "paired_checks": [{"a": "pf_palms", "not_worse_than": "pf_uniform",
//                       "at": "/cells/0/sequential_paired/all", "metric": "success_1m",
//                       "alpha": 0.05, "margin": 0.1}]}
// Accuracy checks compare values to fixed floors/ceilings. Paired checks read the run's paired
// comparisons (the object of "A vs B" entries at "at", either order) and require A not worse than
// B on the same units:
//   - a recall/success criterion (an entry with a McNemar test) fails when the test shows B
//     better: B wins more discordant units and p < alpha (default 0.05). With "margin" (a
//     fraction) it also demands evidence: the paired 95% interval of A - B must lie above -margin;
//   - a continuous metric (an entry with "lower_is_better") fails when the paired 95% interval
//     shows A worse (for errors: the interval of A - B lies above 0); with "margin" it demands the
//     interval's worse end within margin (for errors: ci_high <= margin). Timing is never judged in absolute
// seconds: a ratio of two times measured in the same run must not exceed
// baseline * (1 + tolerance).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace floorcast {

struct GateOutcome {
  bool passed = true;
  std::vector<std::string> failures;  ///< one clear sentence per failed check
  std::vector<std::string> passes;    ///< one line per passed check
};

/// Evaluates every check; a pointer missing from the summary is a failure (never skipped).
/// Throws InputError for a malformed baseline (naming `baseline_source` and the entry) and when
/// the baseline names a scenario_hash other than the summary's "hash" (floors measured on another
/// configuration say nothing about this one).
GateOutcome evaluate_gate(const nlohmann::json& summary, const nlohmann::json& baseline,
                          const std::string& baseline_source);

}  // namespace floorcast

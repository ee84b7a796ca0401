#include "floorcast/scenarios/report.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "floorcast/core/format.hpp"
#include "floorcast/eval/paired.hpp"
#include "floorcast/eval/plot.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/track/tracker.hpp"

namespace floorcast {
namespace {

using OJson = nlohmann::ordered_json;
constexpr double kInf = std::numeric_limits<double>::infinity();

OJson finite_or_null(double v) { return std::isfinite(v) ? OJson(v) : OJson(nullptr); }

std::string axis_value_text(const OJson& v) { return v.is_string() ? v.get<std::string>() : v.dump(); }

/// The sweep values of a cell in words ("schedule.every_steps = 10, ..."); empty without a sweep.
std::string cell_axes_text(const CellSpec& cell) {
  std::string t;
  for (auto it = cell.axes.begin(); it != cell.axes.end(); ++it) {
    t += (t.empty() ? "" : ", ") + it.key() + " = " + axis_value_text(it.value());
  }
  return t;
}

std::string cell_title(const CellSpec& cell) {
  const std::string axes = cell_axes_text(cell);
  return axes.empty() ? cell.id : cell.id + " (" + axes + ")";
}

/// A plot title for one cell: the sweep values in words, never the internal cell id.
std::string plot_title(const std::string& what, const CellSpec& cell) {
  const std::string axes = cell_axes_text(cell);
  return axes.empty() ? what : what + ", " + axes;
}

std::string pct(const MetricValue& v) {
  if (!std::isfinite(v.value)) return "n/a";
  std::ostringstream os;
  os << std::fixed << std::setprecision(1) << 100.0 * v.value;
  if (v.has_ci) os << " [" << 100.0 * v.ci_low << ", " << 100.0 * v.ci_high << "]";
  return os.str();
}

std::string num(double v, int decimals) {
  return std::isfinite(v) ? format_fixed(v, decimals) : "n/a";
}

std::string csv_escape(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

OJson summary_json(const Summary& s) {
  OJson j;
  j["count"] = s.count;
  OJson ci = OJson::object();
  for (const std::string& name : s.order) {
    const MetricValue& v = s.values.at(name);
    j[name] = finite_or_null(v.value);
    if (v.has_ci) ci[name] = {finite_or_null(v.ci_low), finite_or_null(v.ci_high)};
  }
  j["ci95"] = ci;
  return j;
}

/// A message on one Markdown line: newlines become " / ", backticks quotes, at most max_chars.
std::string one_line(const std::string& text, std::size_t max_chars) {
  std::string out;
  for (char c : text) {
    if (c == '\n') out += " / ";
    else if (c == '`') out += '\'';
    else if (c != '\r') out += c;
  }
  if (out.size() > max_chars) out = out.substr(0, max_chars) + "...";
  return out;
}

OJson interval_json(const PairedDifference& d) {
  return d.has_ci ? OJson::array({finite_or_null(d.ci_low), finite_or_null(d.ci_high)}) : OJson(nullptr);
}

}  // namespace

OJson paired_comparison_json(const PairedComparison& c) {
  OJson j;
  j["a"] = c.a;
  j["b"] = c.b;
  j["count"] = c.count;
  for (const PairedCriterion& x : c.criteria) {
    OJson e;
    e["both"] = x.test.both;
    e["only_a"] = x.test.only_a;
    e["only_b"] = x.test.only_b;
    e["neither"] = x.test.neither;
    e["p_value"] = x.test.p_value;
    e["difference"] = finite_or_null(x.difference.value);
    e["ci95"] = interval_json(x.difference);
    j[x.name] = e;
  }
  for (const PairedMetric& x : c.metrics) {
    OJson e;
    e["difference"] = finite_or_null(x.difference.value);
    e["ci95"] = interval_json(x.difference);
    e["lower_is_better"] = !x.higher_is_better;
    j[x.name] = e;
  }
  return j;
}

std::string paired_comparisons_md(const std::vector<PairedComparison>& pairs, const std::string& criterion,
                                  const std::string& criterion_title, const std::string& metric,
                                  const std::string& metric_title, const std::string& units_word) {
  if (pairs.empty()) return "";
  std::ostringstream md;
  md << "Paired comparisons on the same " << pairs.front().count << " " << units_word << " (A - B; McNemar's exact test on "
     << criterion_title << ", paired bootstrap 95% intervals):\n\n"
     << "| A vs B | " << criterion_title << " A / B | only A | only B | McNemar p | difference (percentage points) | "
     << metric_title << " difference | verdict at 5% |\n|---|---|---|---|---|---|---|---|\n";
  for (const PairedComparison& c : pairs) {
    const PairedCriterion* x = nullptr;
    for (const PairedCriterion& k : c.criteria)
      if (k.name == criterion) x = &k;
    const PairedMetric* m = nullptr;
    for (const PairedMetric& k : c.metrics)
      if (k.name == metric) m = &k;
    if (!x) continue;
    auto interval = [](const PairedDifference& d, double scale, int decimals) {
      if (!std::isfinite(d.value)) return std::string("n/a");
      std::string t = (d.value * scale >= 0 ? "+" : "") + format_fixed(d.value * scale, decimals);
      if (d.has_ci && std::isfinite(d.ci_low) && std::isfinite(d.ci_high))
        t += " [" + format_fixed(d.ci_low * scale, decimals) + ", " + format_fixed(d.ci_high * scale, decimals) + "]";
      return t;
    };
    const int n = std::max(c.count, 1);
    std::string verdict = "no significant difference";
    if (x->test.p_value < 0.05) verdict = (x->test.only_a > x->test.only_b ? c.a : c.b) + " better";
    md << "| " << c.a << " vs " << c.b << " | " << format_fixed(100.0 * (x->test.both + x->test.only_a) / n, 1) << " / "
       << format_fixed(100.0 * (x->test.both + x->test.only_b) / n, 1) << " | " << x->test.only_a << " | " << x->test.only_b
       << " | " << format_general(x->test.p_value, 3) << " | " << interval(x->difference, 100.0, 1) << " | "
       << (m ? interval(m->difference, 1.0, 2) : std::string("n/a")) << " | " << verdict << " |\n";
  }
  return md.str() + "\n";
}

std::vector<SingleShotRecord> records_for(const std::vector<const UnitResult*>& units, const std::string& label) {
  std::vector<SingleShotRecord> out;
  for (const UnitResult* u : units) {
    SingleShotRecord r;
    r.position_error_m = kInf;
    r.yaw_error_deg = 180.0;
    for (const MatcherOutcome& o : u->outcomes) {
      if (o.label != label) continue;
      r.time_s = o.match_s;
      if (!o.ok) break;
      r.position_error_m = o.estimate.position_error_m;
      r.yaw_error_deg = o.estimate.yaw_error_deg;
      for (const PoseEstimate& p : o.top_k) {
        r.top_k_position_error_m.push_back(p.position_error_m);
        r.top_k_yaw_error_deg.push_back(p.yaw_error_deg);
      }
    }
    out.push_back(std::move(r));
  }
  return out;
}

std::vector<RejectionRecord> rejection_records_for(const std::vector<const UnitResult*>& units, const std::string& label,
                                                  const ScoringParams& scoring) {
  std::vector<RejectionRecord> out;
  for (const UnitResult* u : units) {
    RejectionRecord r;
    r.positive = !u->unit.negative();
    for (const MatcherOutcome& o : u->outcomes) {
      if (o.label != label) continue;
      r.time_s = o.match_s;
      r.localized = u->observation_ok && o.ok;
      r.correct = r.positive && r.localized && o.estimate.position_error_m <= scoring.combined_threshold_m &&
                  o.estimate.yaw_error_deg <= scoring.combined_threshold_deg;
    }
    out.push_back(r);
  }
  return out;
}

Report build_report(const Scenario& scenario, const std::vector<UnitResult>& units, const OJson& timing) {
  const std::vector<WorkUnit> expected = enumerate_units(scenario);
  std::map<std::string, const UnitResult*> by_id;
  for (const UnitResult& u : units) by_id[u.unit.id] = &u;
  std::size_t missing = 0;
  for (const WorkUnit& w : expected) missing += by_id.count(w.id) ? 0 : 1;
  if (missing > 0) {
    throw InputError("scenario \"" + scenario.name + "\": " + std::to_string(missing) + " of " +
                     std::to_string(expected.size()) + " work units have no result; refusing to report partial results");
  }

  std::vector<std::string> labels;
  for (const MatcherSpec& m : scenario.cells.front().matchers) labels.push_back(m.label);

  Report rep;
  OJson& sum = rep.summary;
  sum["scenario"] = scenario.name;
  sum["hash"] = scenario.hash;
  sum["complete"] = true;
  sum["units"] = expected.size();
  sum["timing"] = timing;
  sum["matchers"] = labels;
  sum["cells"] = OJson::array();

  std::ostringstream md;
  md << "# " << scenario.name << "\n\n";
  if (!scenario.description.empty()) md << scenario.description << "\n\n";
  md << "Scenario hash `" << scenario.hash << "`, " << expected.size() << " work units ("
     << scenario.cells.size() << " cells x " << scenario.buildings.size() << " buildings x "
     << scenario.sampling.count << " points";
  if (scenario.sampling.negatives > 0) {
    md << " + " << scenario.sampling.negatives << " negative samples per building: observations made in the other buildings, "
       << "which a method should reject";
  }
  md << "). Recalls in percent with bootstrap 95% intervals; they count positive samples only.\n\n";
  {
    // Where the points are: the PALMS+ protocol (transitional spaces) or not, per building.
    std::map<std::string, std::vector<std::string>> by_region;
    for (const BuildingSpec& b : scenario.buildings) by_region[b.sampling_region].push_back(b.label);
    auto list = [](const std::vector<std::string>& v) {
      std::string out;
      for (const std::string& x : v) out += (out.empty() ? "" : ", ") + x;
      return out;
    };
    md << "Observation points:";
    const char* sep = " ";
    for (const auto& [region, labels] : by_region) {
      md << sep;
      sep = "; ";
      if (region == "transitional") md << "in transitional spaces (hallways, corridors, lobbies, ...)";
      else if (region == "transitional_or_uniform")
        md << "in transitional spaces where they can be sampled, else uniform over the free space (the run log says "
              "which)";
      else if (region == "kinds") md << "in rooms of kinds " << list(scenario.sampling.region_kinds);
      else if (region == "uniform") md << "uniform over the free space";
      else md << "uniform over the free space, **no room labels** (not the transitional protocol)";
      md << " in " << list(labels);
    }
    md << ".\n\n";
    for (const BuildingSpec& b : scenario.buildings) sum["sampling_region"][b.label] = b.sampling_region;
  }

  std::map<std::string, std::map<std::string, std::vector<double>>> cdf_by_cell;  // cell -> label -> errors
  // Pooled per axis value for accuracy-vs-axis plots (one per sweep axis; zipped keys form one
  // axis): axis -> value text -> label -> records.
  std::vector<std::map<std::string, std::map<std::string, std::vector<SingleShotRecord>>>> per_axis(scenario.sweep_axes.size());
  std::vector<std::vector<std::string>> axis_order(scenario.sweep_axes.size());
  auto axis_text = [&scenario](std::size_t a, const CellSpec& cell) {
    std::string t;
    for (const std::string& k : scenario.sweep_axes[a])
      t += (t.empty() ? "" : " / ") + (cell.axes.contains(k) ? axis_value_text(cell.axes.at(k)) : std::string("?"));
    return t;
  };

  const ScoringParams& sp = scenario.scoring;
  const std::string combined = "recall_" + threshold_name(sp.combined_threshold_m) + "_" +
                               [&] { std::ostringstream o; o << std::setprecision(6) << sp.combined_threshold_deg; return o.str(); }() + "deg";
  const std::string topk = "top" + std::to_string(sp.top_k) + "_recall_" + threshold_name(sp.combined_threshold_m);

  std::ostringstream overview;
  std::map<std::string, std::map<std::string, std::vector<SequentialRecord>>> seq_records;  // cell -> tracker -> walks
  for (const CellSpec& cell : scenario.cells) {
    std::vector<const UnitResult*> cell_units;
    for (const WorkUnit& w : expected)
      if (w.cell == cell.index) cell_units.push_back(by_id.at(w.id));
    OJson cj;
    cj["id"] = cell.id;
    cj["axes"] = cell.axes;
    OJson groups;
    std::map<std::string, std::map<std::string, Summary>> summaries;  // group -> label -> summary
    std::vector<std::string> group_names = {"all"};
    for (const BuildingSpec& b : scenario.buildings) group_names.push_back(b.label);
    OJson paired = OJson::object();
    std::vector<PairedComparison> pairs_all;
    std::map<std::string, std::map<std::string, Summary>> rejections;  // group -> label -> summary
    for (const std::string& g : group_names) {
      std::vector<const UnitResult*> members, positives;
      for (const UnitResult* u : cell_units) {
        if (g != "all" && scenario.buildings[static_cast<std::size_t>(u->unit.building)].label != g) continue;
        members.push_back(u);
        if (!u->unit.negative()) positives.push_back(u);
      }
      OJson gj;
      for (const std::string& label : labels) {
        const std::vector<SingleShotRecord> recs = records_for(positives, label);
        const Summary s = summarize_single_shot(recs, sp);
        summaries[g][label] = s;
        gj[label] = summary_json(s);
        rejections[g][label] = summarize_rejection(rejection_records_for(members, label, sp), sp);
        gj[label]["rejection"] = summary_json(rejections[g][label]);
        if (g == "all") {
          for (const auto& r : recs) cdf_by_cell[cell.id][label].push_back(r.position_error_m);
          for (std::size_t a = 0; a < scenario.sweep_axes.size(); ++a) {
            const std::string vt = axis_text(a, cell);
            auto& order = axis_order[a];
            if (std::find(order.begin(), order.end(), vt) == order.end()) order.push_back(vt);
            auto& bucket = per_axis[a][vt][label];
            bucket.insert(bucket.end(), recs.begin(), recs.end());
          }
        }
      }
      groups[g] = gj;
      // Every pair of methods on this group's units (positives: the recalls' samples).
      OJson pj = OJson::object();
      for (std::size_t i = 0; i < labels.size(); ++i) {
        for (std::size_t k = i + 1; k < labels.size(); ++k) {
          PairedComparison c = compare_single_shot(labels[i], records_for(positives, labels[i]), labels[k],
                                                   records_for(positives, labels[k]), sp);
          pj[labels[i] + " vs " + labels[k]] = paired_comparison_json(c);
          if (g == "all") pairs_all.push_back(std::move(c));
        }
      }
      paired[g] = pj;
    }
    cj["groups"] = groups;
    if (labels.size() > 1) cj["paired"] = paired;
    // Mean stage timings over the cell.
    std::map<std::string, double> stage_sum;
    for (const UnitResult* u : cell_units)
      for (const auto& [k, v] : u->timings_s) stage_sum[k] += v;
    OJson tj = OJson::object();
    for (const auto& [k, v] : stage_sum) tj[k] = v / std::max<std::size_t>(cell_units.size(), 1);
    cj["timing_mean_s"] = tj;
    int failed_obs = 0;
    for (const UnitResult* u : cell_units) failed_obs += u->observation_ok ? 0 : 1;
    cj["failed_observations"] = failed_obs;
    // Methods that produced no pose from a usable observation (an empty posterior: every cell
    // scored 0), per method: a reported state, counted as a miss, never an invented pose.
    std::map<std::string, int> no_pose;
    for (const std::string& label : labels) no_pose[label] = 0;
    int cell_positives = 0;
    for (const UnitResult* u : cell_units) {
      if (u->unit.negative()) continue;
      ++cell_positives;
      if (!u->observation_ok) continue;
      for (const MatcherOutcome& o : u->outcomes) no_pose[o.label] += o.ok ? 0 : 1;
    }
    OJson npj = OJson::object();
    // Errors of misbehaving (external) methods: misses apart from empty posteriors, with the
    // first message, so a broken method never passes for a weak one.
    std::map<std::string, int> errors;
    std::map<std::string, std::string> first_error;
    for (const UnitResult* u : cell_units) {
      for (const MatcherOutcome& o : u->outcomes) {
        if (!o.error) continue;
        ++errors[o.label];
        --no_pose[o.label];
        if (!first_error.count(o.label)) first_error[o.label] = u->unit.id + ": " + o.failure;
      }
      for (const TrackOutcome& t : u->tracks) {
        if (!t.error) continue;
        ++errors[t.label];
        if (!first_error.count(t.label)) first_error[t.label] = u->unit.id + ": " + t.failure;
      }
    }
    for (const std::string& label : labels) npj[label] = no_pose[label];
    cj["no_pose"] = npj;
    if (!errors.empty()) {
      OJson ej = OJson::object();
      for (const auto& [label, n] : errors) ej[label] = {{"units", n}, {"first", first_error[label]}};
      cj["errors"] = ej;
    }
    sum["cells"].push_back(cj);

    // Markdown: the PALMS+ Table 1 layout for this cell.
    md << "## " << cell_title(cell) << "\n\n";
    md << "| method |";
    for (double t : sp.recall_thresholds_m) md << " @" << threshold_name(t) << " |";
    md << " @" << threshold_name(sp.combined_threshold_m) << " " << sp.combined_threshold_deg << "° | top-" << sp.top_k
       << " @" << threshold_name(sp.combined_threshold_m) << " | median error (m) | median yaw error (°) | time / obs (s) |\n";
    md << "|---|";
    for (std::size_t i = 0; i < sp.recall_thresholds_m.size() + 5; ++i) md << "---|";
    md << "\n";
    for (const std::string& label : labels) {
      const Summary& s = summaries["all"][label];
      md << "| " << label << " |";
      for (double t : sp.recall_thresholds_m) md << " " << pct(s.values.at("recall_" + threshold_name(t))) << " |";
      md << " " << pct(s.values.at(combined)) << " | " << pct(s.values.at(topk)) << " | "
         << num(s.values.at("median_position_error_m").value, 2) << " | " << num(s.values.at("median_yaw_error_deg").value, 1)
         << " | " << num(s.values.at("mean_time_s").value, 3) << " |\n";
    }
    for (const PaperReference& ref : scenario.paper) {
      if (!ref.cell.empty() && ref.cell != cell.id) continue;
      auto paper_value = [&ref](const std::string& metric, bool percent, int decimals) {
        auto it = ref.values.find(metric);
        if (it == ref.values.end()) return std::string("–");
        return percent ? num(100.0 * it->second, 1) : num(it->second, decimals);
      };
      md << "| *" << ref.label << "* |";
      for (double t : sp.recall_thresholds_m) md << " " << paper_value("recall_" + threshold_name(t), true, 1) << " |";
      md << " " << paper_value(combined, true, 1) << " | " << paper_value(topk, true, 1) << " | "
         << paper_value("median_position_error_m", false, 2) << " | " << paper_value("median_yaw_error_deg", false, 1) << " | "
         << paper_value("mean_time_s", false, 3) << " |\n";
    }
    for (const PaperReference& ref : scenario.paper)
      if ((ref.cell.empty() || ref.cell == cell.id) && !ref.source.empty()) md << "\n*" << ref.label << "*: " << ref.source << ".";
    if (!scenario.paper.empty()) md << "\n";
    if (scenario.buildings.size() > 1) {
      md << "\nPer building, @" << threshold_name(sp.combined_threshold_m) << " " << sp.combined_threshold_deg << "°:\n\n| building |";
      for (const std::string& label : labels) md << " " << label << " |";
      md << "\n|---|";
      for (std::size_t i = 0; i < labels.size(); ++i) md << "---|";
      md << "\n";
      for (const BuildingSpec& b : scenario.buildings) {
        md << "| " << b.label << " |";
        for (const std::string& label : labels) md << " " << pct(summaries[b.label][label].values.at(combined)) << " |";
        md << "\n";
      }
    }
    if (!pairs_all.empty()) {
      std::ostringstream deg;
      deg << std::setprecision(6) << sp.combined_threshold_deg;
      md << "\n" << paired_comparisons_md(pairs_all, combined, "@" + threshold_name(sp.combined_threshold_m) + " " + deg.str() + "°",
                                          "median_position_error_m", "median error (m)", "points");
    }
    if (failed_obs > 0) md << "\n" << failed_obs << " observation(s) failed and count as misses.\n";
    for (const auto& [label, n] : errors) {
      md << "\n**Errors:** " << label << " misbehaved on " << n << " of " << cell_units.size()
         << " units (counted as misses; a resumed run runs them again). First: `" << one_line(first_error[label], 300) << "`\n";
    }
    bool any_no_pose = false;
    for (const auto& [label, n] : no_pose) any_no_pose = any_no_pose || n > 0;
    if (any_no_pose) {
      md << "\nNo pose (empty posterior, counted as a miss):";
      for (const std::string& label : labels) md << " " << label << " " << no_pose[label] << " of " << cell_positives - failed_obs << ";";
      md << "\n";
    }
    md << "\n";

    // Scoring with rejection (VoxelPlane-Reloc Tables 1, 3, 6, 7): every sample, positive or
    // negative; "not localized" is an answer. Shown when there are negatives or a method did not
    // answer (otherwise precision is the @1 m 30 deg recall above).
    const int negatives = static_cast<int>(cell_units.size()) - cell_positives;
    if (negatives > 0 || any_no_pose) {
      md << "Scoring with rejection (" << cell_positives << " positive, " << negatives
         << " negative samples; TP = localized within @" << threshold_name(sp.combined_threshold_m) << " "
         << sp.combined_threshold_deg << "°, FP = a pose for a negative or a wrong pose for a positive, FN = positive "
         << "not localized, TN = negative not localized):\n\n"
         << "| method | TP | FP (wrong pose) | FP (negatives) | TN | FN | precision | recall | F1 | precision (negatives only) | time / sample (s) |\n"
         << "|---|---|---|---|---|---|---|---|---|---|---|\n";
      for (const std::string& label : labels) {
        const Summary& x = rejections["all"][label];
        auto n = [&](const char* k) { return num(x.values.at(k).value, 0); };
        md << "| " << label << " | " << n("tp") << " | " << n("fp_wrong_pose") << " | " << n("fp_negative") << " | " << n("tn")
           << " | " << n("fn") << " | " << pct(x.values.at("precision")) << " | " << pct(x.values.at("recall")) << " | "
           << pct(x.values.at("f1")) << " | " << pct(x.values.at("precision_negatives_only")) << " | "
           << num(x.values.at("mean_time_s").value, 3) << " |\n";
      }
      for (const PaperReference& ref : scenario.paper) {
        if (!ref.cell.empty() && ref.cell != cell.id) continue;
        if (!ref.values.count("precision") && !ref.values.count("recall")) continue;
        auto v = [&ref](const char* k, bool percent, int decimals) {
          auto it = ref.values.find(k);
          if (it == ref.values.end()) return std::string("–");
          return percent ? num(100.0 * it->second, 1) : num(it->second, decimals);
        };
        md << "| *" << ref.label << "* | " << v("tp", false, 0) << " | – | " << v("fp", false, 0) << " | " << v("tn", false, 0)
           << " | " << v("fn", false, 0) << " | " << v("precision", true, 1) << " | " << v("recall", true, 1) << " | "
           << v("f1", true, 1) << " | " << v("precision", true, 1) << " | " << v("avg_time_s", false, 3) << " |\n";
      }
      md << "\n";
    }

    // Sequential cells: every tracker over the walks (PALMS Table I layout), per building too.
    if (cell.sequential) {
      SequentialScoring sq = scenario.sequential_scoring;
      sq.bootstrap_resamples = sp.bootstrap_resamples;
      sq.bootstrap_seed = sp.bootstrap_seed;
      OJson seq;
      std::map<std::string, std::map<std::string, Summary>> by_group;  // group -> tracker -> summary
      std::map<std::string, std::map<std::string, std::vector<SequentialRecord>>> recs_by_group;
      OJson seq_paired = OJson::object();
      std::vector<PairedComparison> seq_pairs_all;
      for (const std::string& g : group_names) {
        OJson gj;
        for (const TrackerSpec& t : cell.sequential->trackers) {
          std::vector<SequentialRecord> recs;
          for (const UnitResult* u : cell_units) {
            if (g != "all" && scenario.buildings[static_cast<std::size_t>(u->unit.building)].label != g) continue;
            for (const TrackOutcome& o : u->tracks)
              if (o.label == t.label) recs.push_back(o.record);
          }
          by_group[g][t.label] = summarize_sequential(recs, sq);
          gj[t.label] = summary_json(by_group[g][t.label]);
          recs_by_group[g][t.label] = recs;
          if (g == "all") seq_records[cell.id][t.label] = recs;
        }
        seq[g] = gj;
        OJson pj = OJson::object();
        const auto& ts = cell.sequential->trackers;
        for (std::size_t i = 0; i < ts.size(); ++i) {
          for (std::size_t k = i + 1; k < ts.size(); ++k) {
            PairedComparison c = compare_sequential(ts[i].label, recs_by_group[g][ts[i].label], ts[k].label,
                                                    recs_by_group[g][ts[k].label], sq);
            pj[ts[i].label + " vs " + ts[k].label] = paired_comparison_json(c);
            if (g == "all") seq_pairs_all.push_back(std::move(c));
          }
        }
        seq_paired[g] = pj;
      }
      sum["cells"].back()["sequential"] = seq;
      if (cell.sequential->trackers.size() > 1) sum["cells"].back()["sequential_paired"] = seq_paired;
      const std::string s1 = "success_" + threshold_name(sq.success_thresholds_m.at(0));
      md << "Tracking " << cell_units.size() << " walks (scan, then walk; PALMS Table I metrics, medians over walks):\n\n"
         << "| tracker | matcher | success " << threshold_name(sq.success_thresholds_m.at(0)) << " | success "
         << threshold_name(sq.success_thresholds_m.size() > 1 ? sq.success_thresholds_m[1] : sq.success_thresholds_m[0])
         << " | RMSE (m) | last-10 RMSE (m) | end error (m) | converged | convergence time (s) | convergence distance (m) | within 1 m after convergence | time / step (ms) |\n"
         << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
      for (const TrackerSpec& t : cell.sequential->trackers) {
        const Summary& x = by_group["all"][t.label];
        auto v = [&](const std::string& k) { return x.values.count(k) ? x.values.at(k) : MetricValue{}; };
        const std::string s2 = "success_" + threshold_name(sq.success_thresholds_m.size() > 1 ? sq.success_thresholds_m[1] : sq.success_thresholds_m[0]);
        md << "| " << t.label << " | " << t.matcher << " | " << pct(v(s1)) << " | " << pct(v(s2)) << " | "
           << num(v("median_rmse_m").value, 2) << " | " << num(v("median_rmse_last_m").value, 2) << " | "
           << num(v("median_end_error_m").value, 2) << " | " << pct(v("converged")) << " | "
           << num(v("median_convergence_time_s").value, 1) << " | " << num(v("median_convergence_distance_m").value, 1) << " | "
           << pct(v("within_" + threshold_name(sq.within_m) + "_after_convergence")) << " | "
           << num(1e3 * v("mean_time_per_step_s").value, 1) << " |\n";
      }
      // "Converged" is each tracker's own (PALMS' two stages are a particle-filter notion).
      md << "\nConverged means:";
      for (const TrackerSpec& t : cell.sequential->trackers) {
        md << " " << t.label << ", " << describe_convergence(t.config->name(), t.config->parameters()) << ";";
      }
      md << "\n";
      if (scenario.buildings.size() > 1) {
        md << "\nPer building, tracking success " << threshold_name(sq.success_thresholds_m.at(0)) << ":\n\n| building |";
        for (const TrackerSpec& t : cell.sequential->trackers) md << " " << t.label << " |";
        md << "\n|---|";
        for (std::size_t i = 0; i < cell.sequential->trackers.size(); ++i) md << "---|";
        md << "\n";
        for (const BuildingSpec& bs : scenario.buildings) {
          md << "| " << bs.label << " |";
          for (const TrackerSpec& t : cell.sequential->trackers) md << " " << pct(by_group[bs.label][t.label].values.at(s1)) << " |";
          md << "\n";
        }
      }
      if (!seq_pairs_all.empty())
        md << "\n" << paired_comparisons_md(seq_pairs_all, s1, "success " + threshold_name(sq.success_thresholds_m.at(0)),
                                            "median_rmse_m", "median RMSE (m)", "walks");
      md << "\n";
    }

    overview << "| " << cell.id << " |";
    for (auto it = cell.axes.begin(); it != cell.axes.end(); ++it) overview << " " << axis_value_text(it.value()) << " |";
    for (const std::string& label : labels) overview << " " << pct(summaries["all"][label].values.at(combined)) << " |";
    overview << "\n";
  }

  if (scenario.cells.size() > 1) {
    md << "## Sweep overview (@" << threshold_name(sp.combined_threshold_m) << " " << sp.combined_threshold_deg << "°)\n\n| cell |";
    for (const std::string& k : scenario.sweep_keys) md << " " << k << " |";
    for (const std::string& label : labels) md << " " << label << " |";
    md << "\n|---|";
    for (std::size_t i = 0; i < scenario.sweep_keys.size() + labels.size(); ++i) md << "---|";
    md << "\n" << overview.str() << "\n";
  }
  rep.summary_md = md.str();

  // observations.csv: one row per work unit.
  std::ostringstream csv;
  csv << "unit,cell";
  for (const std::string& k : scenario.sweep_keys) csv << "," << csv_escape(k);
  csv << ",building,point,negative,truth_x_m,truth_y_m,truth_yaw_deg,observation_ok,simulate_s,observe_s";
  for (const std::string& label : labels)
    csv << "," << label << "_ok," << label << "_x_m," << label << "_y_m," << label << "_yaw_deg," << label
        << "_position_error_m," << label << "_yaw_error_deg," << label << "_best_top" << sp.top_k << "_error_m," << label
        << "_match_s";
  csv << "\n";
  constexpr double kDeg = 180.0 / kPi;
  for (const WorkUnit& w : expected) {
    const UnitResult& u = *by_id.at(w.id);
    const CellSpec& cell = scenario.cells[static_cast<std::size_t>(w.cell)];
    csv << w.id << "," << cell.id;
    for (const std::string& k : scenario.sweep_keys) csv << "," << csv_escape(cell.axes.contains(k) ? axis_value_text(cell.axes[k]) : "");
    csv << "," << scenario.buildings[static_cast<std::size_t>(w.building)].label << "," << w.point << ","
        << (w.negative() ? scenario.buildings[static_cast<std::size_t>(w.source_building)].label : std::string()) << "," << u.truth.x_m << ","
        << u.truth.y_m << "," << u.truth.yaw_rad * kDeg << "," << (u.observation_ok ? 1 : 0) << ","
        << (u.timings_s.count("simulate") ? u.timings_s.at("simulate") : 0.0) << ","
        << (u.timings_s.count("observe") ? u.timings_s.at("observe") : 0.0);
    for (const std::string& label : labels) {
      const MatcherOutcome* o = nullptr;
      for (const MatcherOutcome& m : u.outcomes)
        if (m.label == label) o = &m;
      if (!o || !o->ok) {
        csv << ",0,,,,,,," << (o ? o->match_s : 0.0);
        continue;
      }
      // A metric is finite before it is written: a matcher (a user's own, registered from Python)
      // that reports a NaN pose is named here instead of writing "nan" into the table.
      for (const double v : {o->estimate.x_m, o->estimate.y_m, o->estimate.yaw_rad, o->estimate.position_error_m,
                             o->estimate.yaw_error_deg}) {
        if (!std::isfinite(v)) {
          throw InputError(w.id + ": matcher " + label + " reported a non-finite estimate or error; the report was not written");
        }
      }
      double best = kInf;
      for (int i = 0; i < std::min<int>(sp.top_k, static_cast<int>(o->top_k.size())); ++i)
        best = std::min(best, o->top_k[static_cast<std::size_t>(i)].position_error_m);
      csv << ",1," << o->estimate.x_m << "," << o->estimate.y_m << "," << o->estimate.yaw_rad * kDeg << ","
          << o->estimate.position_error_m << "," << o->estimate.yaw_error_deg << "," << (std::isfinite(best) ? best : o->estimate.position_error_m)
          << "," << o->match_s;
    }
    csv << "\n";
  }
  rep.observations_csv = csv.str();

  // Plots.
  for (const CellSpec& cell : scenario.cells) {
    const LinePlot p = error_cdf_plot(cdf_by_cell[cell.id], 10.0, plot_title("Position error CDF", cell), "position error [m]");
    rep.plots.emplace_back("error_cdf_" + cell.id + ".png", draw_line_plot(p));
  }
  // Sequential: median position error vs step, and the share of walks within 1 m vs step.
  for (const auto& [cell_id, by_tracker] : seq_records) {
    const auto cell_it = std::find_if(scenario.cells.begin(), scenario.cells.end(),
                                      [&id = cell_id](const CellSpec& c) { return c.id == id; });
    const CellSpec cell = cell_it != scenario.cells.end() ? *cell_it : CellSpec{};
    LinePlot err, ok;
    err.title = plot_title("Tracking error vs step (median over walks)", cell);
    err.x_label = "step";
    err.y_label = "position error [m]";
    err.y_min = 0.0;
    ok.title = plot_title("Walks within 1 m vs step", cell);
    ok.x_label = "step";
    ok.y_label = "share of walks";
    ok.y_min = 0.0;
    ok.y_max = 1.0;
    double top = 1.0;
    for (const auto& [label, recs] : by_tracker) {
      std::size_t steps = 0;
      for (const SequentialRecord& r : recs) steps = std::max(steps, r.position_error_m.size());
      PlotSeries e{label, {}, {}, {}, {}}, w{label, {}, {}, {}, {}};
      for (std::size_t k = 0; k < steps; ++k) {
        std::vector<double> at;
        double within = 0.0;
        for (const SequentialRecord& r : recs) {
          const double x = k < r.position_error_m.size() ? r.position_error_m[k] : kInf;
          at.push_back(x);
          within += x <= 1.0 ? 1.0 : 0.0;
        }
        const double med = median(at);
        e.x.push_back(static_cast<double>(k));
        e.y.push_back(std::isfinite(med) ? med : NAN);
        if (std::isfinite(med)) top = std::max(top, med);
        w.x.push_back(static_cast<double>(k));
        w.y.push_back(recs.empty() ? 0.0 : within / static_cast<double>(recs.size()));
      }
      err.series.push_back(std::move(e));
      ok.series.push_back(std::move(w));
    }
    err.y_max = std::min(top * 1.05, 60.0);
    rep.plots.emplace_back("tracking_error_" + cell_id + ".png", draw_line_plot(err));
    rep.plots.emplace_back("tracking_success_" + cell_id + ".png", draw_line_plot(ok));
  }
  for (std::size_t a = 0; a < per_axis.size(); ++a) {
    if (axis_order[a].size() < 2) continue;  // an axis with one value shows nothing
    std::string key;
    for (const std::string& k : scenario.sweep_axes[a]) key += (key.empty() ? "" : " / ") + k;
    LinePlot p;
    p.title = "Recall " + combined.substr(7) + " vs " + key + " (all buildings, 95% bootstrap intervals)";
    p.x_label = key;
    p.y_label = "recall";
    p.y_min = 0.0;
    p.y_max = 1.0;
    p.draw_markers = true;
    p.x_categories = axis_order[a];
    for (const std::string& label : labels) {
      PlotSeries s;
      s.label = label;
      for (std::size_t i = 0; i < p.x_categories.size(); ++i) {
        const auto& recs = per_axis[a].at(p.x_categories[i]).at(label);
        const MetricValue v = summarize_single_shot(recs, sp).values.at(combined);
        s.x.push_back(static_cast<double>(i));
        s.y.push_back(v.value);
        s.y_low.push_back(v.has_ci ? v.ci_low : NAN);
        s.y_high.push_back(v.has_ci ? v.ci_high : NAN);
      }
      p.series.push_back(std::move(s));
    }
    std::string file = "accuracy_vs_" + scenario.sweep_axes[a].front() + ".png";
    for (char& c : file)
      if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-')) c = '_';
    rep.plots.emplace_back(file, draw_line_plot(p));
  }
  return rep;
}

std::vector<CrossRunComparison> compare_runs_paired(const Scenario& scenario_a, const std::vector<UnitResult>& units_a,
                                                    const std::string& name_a, const Scenario& scenario_b,
                                                    const std::vector<UnitResult>& units_b, const std::string& name_b) {
  std::map<std::string, const UnitResult*> by_id_b;
  for (const UnitResult& u : units_b) by_id_b[u.unit.id] = &u;
  auto cell_id = [](const Scenario& s, const UnitResult& u) { return s.cells.at(static_cast<std::size_t>(u.unit.cell)).id; };
  // Shared units per cell id, in run A's order.
  std::map<std::string, std::vector<std::pair<const UnitResult*, const UnitResult*>>> shared;
  std::vector<std::string> cell_order;
  for (const UnitResult& a : units_a) {
    auto it = by_id_b.find(a.unit.id);
    if (it == by_id_b.end()) continue;
    const UnitResult& b = *it->second;
    if (cell_id(scenario_a, a) != cell_id(scenario_b, b)) continue;
    if (std::abs(a.truth.x_m - b.truth.x_m) > 1e-9 || std::abs(a.truth.y_m - b.truth.y_m) > 1e-9 ||
        std::abs(a.truth.yaw_rad - b.truth.yaw_rad) > 1e-9)
      continue;  // another point under the same id: not the same unit
    const std::string c = cell_id(scenario_a, a);
    if (!shared.count(c)) cell_order.push_back(c);
    shared[c].push_back({&a, &b});
  }
  std::vector<CrossRunComparison> out;
  const ScoringParams& sp = scenario_a.scoring;
  SequentialScoring sq = scenario_a.sequential_scoring;
  sq.bootstrap_resamples = sp.bootstrap_resamples;
  sq.bootstrap_seed = sp.bootstrap_seed;
  for (const std::string& c : cell_order) {
    const auto& pairs = shared[c];
    std::vector<const UnitResult*> ua, ub;
    for (const auto& [a, b] : pairs) {
      ua.push_back(a);
      ub.push_back(b);
    }
    auto labels_of = [](const UnitResult& u) {
      std::vector<std::string> l;
      for (const MatcherOutcome& o : u.outcomes) l.push_back(o.label);
      return l;
    };
    auto trackers_of = [](const UnitResult& u) {
      std::vector<std::string> l;
      for (const TrackOutcome& o : u.tracks) l.push_back(o.label);
      return l;
    };
    auto track_records = [](const std::vector<const UnitResult*>& units, const std::string& label) {
      std::vector<SequentialRecord> r;
      for (const UnitResult* u : units) {
        SequentialRecord rec;
        rec.failed = true;
        for (const TrackOutcome& o : u->tracks)
          if (o.label == label) rec = o.record;
        r.push_back(std::move(rec));
      }
      return r;
    };
    CrossRunComparison cmp;
    cmp.cell = c;
    cmp.shared_units = static_cast<int>(pairs.size());
    for (const std::string& la : labels_of(*ua.front()))
      for (const std::string& lb : labels_of(*ub.front()))
        cmp.matchers.push_back(compare_single_shot(name_a + ":" + la, records_for(ua, la), name_b + ":" + lb, records_for(ub, lb), sp));
    for (const std::string& la : trackers_of(*ua.front()))
      for (const std::string& lb : trackers_of(*ub.front()))
        cmp.trackers.push_back(compare_sequential(name_a + ":" + la, track_records(ua, la), name_b + ":" + lb, track_records(ub, lb), sq));
    out.push_back(std::move(cmp));
  }
  return out;
}

nlohmann::ordered_json cross_run_comparisons_json(const std::vector<CrossRunComparison>& comparisons,
                                                  const std::string& run_a, const std::string& run_b) {
  using OJ = nlohmann::ordered_json;
  OJ cells = OJ::array();
  for (const CrossRunComparison& x : comparisons) {
    OJ cj;
    cj["cell"] = x.cell;
    cj["shared_units"] = x.shared_units;
    cj["matchers"] = OJ::object();
    for (const PairedComparison& p : x.matchers) cj["matchers"][p.a + " vs " + p.b] = paired_comparison_json(p);
    cj["trackers"] = OJ::object();
    for (const PairedComparison& p : x.trackers) cj["trackers"][p.a + " vs " + p.b] = paired_comparison_json(p);
    cells.push_back(cj);
  }
  return OJ{{"a", run_a}, {"b", run_b}, {"cells", cells}};
}

std::string cross_run_comparisons_md(const std::vector<CrossRunComparison>& comparisons, const Scenario& scenario_a) {
  const ScoringParams& sp = scenario_a.scoring;
  std::ostringstream deg;
  deg << std::setprecision(6) << sp.combined_threshold_deg;
  const std::string combined = "recall_" + threshold_name(sp.combined_threshold_m) + "_" + deg.str() + "deg";
  const std::string s1 = "success_" + threshold_name(scenario_a.sequential_scoring.success_thresholds_m.at(0));
  std::ostringstream md;
  for (const CrossRunComparison& c : comparisons) {
    md << "## Cell " << c.cell << " (" << c.shared_units << " shared units)\n\n";
    md << paired_comparisons_md(c.matchers, combined, "@" + threshold_name(sp.combined_threshold_m) + " " + deg.str() + "°",
                                "median_position_error_m", "median error (m)", "points");
    md << paired_comparisons_md(c.trackers, s1, "success " + threshold_name(scenario_a.sequential_scoring.success_thresholds_m.at(0)),
                                "median_rmse_m", "median RMSE (m)", "walks");
  }
  return md.str();
}

}  // namespace floorcast

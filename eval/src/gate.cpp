#include "floorcast/eval/gate.hpp"

#include <cmath>
#include <sstream>

#include "floorcast/core/format.hpp"
#include "floorcast/core/json_text.hpp"
#include "floorcast/core/types.hpp"

namespace floorcast {
namespace {

using Json = nlohmann::json;

bool lookup(const Json& summary, const std::string& pointer, double& value, std::string& why) {
  Json::json_pointer ptr;
  try {
    ptr = Json::json_pointer(pointer);
  } catch (const Json::exception& e) {
    why = "bad JSON pointer \"" + pointer + "\"";
    return false;
  }
  const Json* found = nullptr;
  try {
    // contains() and at() throw for an array index that does not fit a size_t.
    if (summary.contains(ptr)) found = &summary.at(ptr);
  } catch (const Json::exception&) {
    found = nullptr;
  }
  if (!found) {
    why = pointer + " is missing from the summary";
    return false;
  }
  const Json& v = *found;
  if (!v.is_number()) {
    why = pointer + " is not a number (" + json_excerpt(v) + ")";
    return false;
  }
  value = v.get<double>();
  if (!std::isfinite(value)) {
    why = pointer + " is not finite";
    return false;
  }
  return true;
}


}  // namespace

GateOutcome evaluate_gate(const Json& summary, const Json& baseline, const std::string& baseline_source) {
  GateOutcome out;
  if (!baseline.is_object()) throw InputError(baseline_source + ": baseline must be a JSON object");
  for (auto it = baseline.begin(); it != baseline.end(); ++it) {
    if (it.key() != "description" && it.key() != "checks" && it.key() != "timing_ratios" && it.key() != "scenario" &&
        it.key() != "scenario_hash" && it.key() != "paired_checks")
      throw InputError(baseline_source + ": unknown key \"" + it.key() + "\"");
  }
  // A baseline belongs to one scenario: its "scenario" (the scenario file, or its name) must name
  // the run's scenario, or the floors are checked against another experiment's numbers.
  if (baseline.contains("scenario")) {
    if (!baseline["scenario"].is_string()) throw InputError(baseline_source + ": \"scenario\" must be a string");
    const std::string named = baseline["scenario"].get<std::string>();
    std::string want = named;
    const auto slash = want.find_last_of('/');
    if (slash != std::string::npos) want = want.substr(slash + 1);
    for (const char* ext : {".yaml", ".yml"}) {
      const std::string e(ext);
      if (want.size() > e.size() && want.compare(want.size() - e.size(), e.size(), e) == 0) want.resize(want.size() - e.size());
    }
    const std::string have = summary.is_object() && summary.contains("scenario") && summary["scenario"].is_string()
                                 ? summary["scenario"].get<std::string>()
                                 : std::string();
    if (have != want && have != named) {
      throw InputError("the summary is a run of scenario " + (have.empty() ? std::string("(none named)") : "\"" + have + "\"") +
                       ", but " + baseline_source + " holds the floors of scenario \"" + named +
                       "\": gate each run against its own baseline");
    }
  }
  // Floors hold for the configuration they were measured with: refuse any other.
  if (baseline.contains("scenario_hash")) {
    if (!baseline["scenario_hash"].is_string()) throw InputError(baseline_source + ": \"scenario_hash\" must be a string");
    const std::string want = baseline["scenario_hash"].get<std::string>();
    const std::string have = summary.is_object() && summary.contains("hash") && summary["hash"].is_string()
                                 ? summary["hash"].get<std::string>()
                                 : std::string();
    if (want != have) {
      throw InputError("the summary's scenario hash " + (have.empty() ? std::string("(none)") : have) +
                       " differs from the hash " + want + " that " + baseline_source +
                       " was measured with: the run used another configuration (the scenario file or a parameter "
                       "default changed). Re-measure, review the floors, then set \"scenario_hash\" to " +
                       (have.empty() ? std::string("the new hash") : "\"" + have + "\""));
    }
  }
  auto fail = [&out](const std::string& s) {
    out.passed = false;
    out.failures.push_back(s);
  };
  const Json checks = baseline.value("checks", Json::array());
  if (!checks.is_array()) throw InputError(baseline_source + ": \"checks\" must be a list");
  for (std::size_t i = 0; i < checks.size(); ++i) {
    const Json& c = checks[i];
    const std::string where = baseline_source + ": checks[" + std::to_string(i) + "]";
    if (!c.is_object() || !c.contains("pointer") || !c["pointer"].is_string())
      throw InputError(where + ": needs a \"pointer\" string");
    if (!c.contains("min") && !c.contains("max")) throw InputError(where + ": needs \"min\" and/or \"max\"");
    for (auto it = c.begin(); it != c.end(); ++it)
      if (it.key() != "pointer" && it.key() != "min" && it.key() != "max" && it.key() != "note")
        throw InputError(where + ": unknown key \"" + it.key() + "\"");
    const std::string ptr = c["pointer"].get<std::string>();
    double v = 0.0;
    std::string why;
    if (!lookup(summary, ptr, v, why)) {
      fail("accuracy check " + ptr + ": " + why);
      continue;
    }
    bool ok = true;
    if (c.contains("min")) {
      if (!c["min"].is_number()) throw InputError(where + ": \"min\" must be a number");
      const double lo = c["min"].get<double>();
      if (v < lo) {
        fail("accuracy regression: " + ptr + " = " + format_general(v, 4) + " is below its floor " + format_general(lo, 4));
        ok = false;
      }
    }
    if (c.contains("max")) {
      if (!c["max"].is_number()) throw InputError(where + ": \"max\" must be a number");
      const double hi = c["max"].get<double>();
      if (v > hi) {
        fail("accuracy regression: " + ptr + " = " + format_general(v, 4) + " is above its ceiling " + format_general(hi, 4));
        ok = false;
      }
    }
    if (ok) out.passes.push_back("ok: " + ptr + " = " + format_general(v, 4));
  }

  const Json paired = baseline.value("paired_checks", Json::array());
  if (!paired.is_array()) throw InputError(baseline_source + ": \"paired_checks\" must be a list");
  for (std::size_t i = 0; i < paired.size(); ++i) {
    const Json& c = paired[i];
    const std::string where = baseline_source + ": paired_checks[" + std::to_string(i) + "]";
    if (!c.is_object()) throw InputError(where + ": must be an object");
    for (const char* key : {"a", "not_worse_than", "at", "metric"})
      if (!c.contains(key) || !c[key].is_string()) throw InputError(where + ": needs a \"" + std::string(key) + "\" string");
    for (auto it = c.begin(); it != c.end(); ++it)
      if (it.key() != "a" && it.key() != "not_worse_than" && it.key() != "at" && it.key() != "metric" && it.key() != "alpha" &&
          it.key() != "margin" && it.key() != "note")
        throw InputError(where + ": unknown key \"" + it.key() + "\"");
    if (c.contains("alpha") && !(c["alpha"].is_number() && c["alpha"].get<double>() > 0.0 && c["alpha"].get<double>() < 1.0))
      throw InputError(where + ": \"alpha\" must be a number in (0, 1)");
    if (c.contains("margin") && !(c["margin"].is_number() && c["margin"].get<double>() >= 0.0))
      throw InputError(where + ": \"margin\" must be a number >= 0");
    const std::string a = c["a"], b = c["not_worse_than"], at = c["at"], metric = c["metric"];
    const double alpha = c.value("alpha", 0.05);
    const std::string name = a + " not worse than " + b + " on " + metric + " (" + at + ")";
    // The pair is stored once, in either order; orient it as A - B.
    std::string entry_ptr;
    double sign = 1.0;
    for (const auto& [key, s] : {std::pair<std::string, double>{a + " vs " + b, 1.0}, {b + " vs " + a, -1.0}}) {
      try {
        const Json::json_pointer p(at + "/" + key + "/" + metric);
        if (summary.contains(p)) {
          entry_ptr = p.to_string();
          sign = s;
          break;
        }
      } catch (const Json::exception&) {
        throw InputError(where + ": bad JSON pointer \"" + at + "\"");
      }
    }
    if (entry_ptr.empty()) {
      fail("paired check " + name + ": no \"" + a + " vs " + b + "\" comparison with " + metric + " in the summary");
      continue;
    }
    const Json& e = summary.at(Json::json_pointer(entry_ptr));
    const Json& ci = e.contains("ci95") ? e["ci95"] : Json();
    const bool has_ci = ci.is_array() && ci.size() == 2 && ci[0].is_number() && ci[1].is_number();
    // Oriented interval of A - B.
    const double lo = has_ci ? (sign > 0 ? ci[0].get<double>() : -ci[1].get<double>()) : 0.0;
    const double hi = has_ci ? (sign > 0 ? ci[1].get<double>() : -ci[0].get<double>()) : 0.0;
    const std::string interval = has_ci ? "[" + format_general(lo, 4) + ", " + format_general(hi, 4) + "]" : "(none)";
    if (e.contains("p_value")) {
      if (!e["p_value"].is_number() || !e["only_a"].is_number() || !e["only_b"].is_number()) {
        fail("paired check " + name + ": malformed McNemar entry " + entry_ptr);
        continue;
      }
      const double p = e["p_value"].get<double>();
      const int wins_a = sign > 0 ? e["only_a"].get<int>() : e["only_b"].get<int>();
      const int wins_b = sign > 0 ? e["only_b"].get<int>() : e["only_a"].get<int>();
      if (wins_b > wins_a && p < alpha) {
        fail("paired regression: " + b + " beats " + a + " on " + metric + " (" + std::to_string(wins_b) + " vs " +
             std::to_string(wins_a) + " discordant units, McNemar p = " + format_general(p, 3) + " < " + format_general(alpha, 3) + ")");
        continue;
      }
      if (c.contains("margin")) {
        const double margin = c["margin"].get<double>();
        if (!has_ci || lo < -margin) {
          fail("paired check " + name + ": the paired 95% interval of the difference " + interval + " does not exclude " + a +
               " being worse by more than the margin " + format_general(margin, 4));
          continue;
        }
      }
      out.passes.push_back("ok: " + name + ": " + std::to_string(wins_a) + " vs " + std::to_string(wins_b) +
                           " discordant units, McNemar p = " + format_general(p, 3) + ", difference interval " + interval);
    } else if (e.contains("lower_is_better") && e["lower_is_better"].is_boolean()) {
      const bool lower = e["lower_is_better"].get<bool>();
      if (c.contains("alpha"))
        throw InputError(where + ": \"alpha\" applies to recall criteria (McNemar's test); " + metric +
                         " is judged by its paired 95% interval");
      if (!has_ci) {
        fail("paired check " + name + ": no paired interval in the summary (undefined difference)");
        continue;
      }
      // "Worse" for an error: A - B > 0.
      const double worse_lo = lower ? lo : -hi, worse_hi = lower ? hi : -lo;
      if (worse_lo > 0.0) {
        fail("paired regression: " + a + " is worse than " + b + " on " + metric + ": the paired 95% interval of A - B is " + interval);
        continue;
      }
      if (c.contains("margin") && worse_hi > c["margin"].get<double>()) {
        fail("paired check " + name + ": the paired 95% interval " + interval + " does not exclude " + a +
             " being worse by more than the margin " + format_general(c["margin"].get<double>(), 4));
        continue;
      }
      out.passes.push_back("ok: " + name + ": paired 95% interval of A - B " + interval);
    } else {
      fail("paired check " + name + ": " + entry_ptr + " is neither a criterion with a McNemar test nor a metric");
    }
  }

  const Json ratios = baseline.value("timing_ratios", Json::array());
  if (!ratios.is_array()) throw InputError(baseline_source + ": \"timing_ratios\" must be a list");
  // A gate that checks nothing passes every run: refused, not reported as "passed (0 checks)".
  if (checks.empty() && ratios.empty() && paired.empty()) {
    throw InputError(baseline_source + ": no \"checks\", \"paired_checks\" or \"timing_ratios\": a gate with nothing to "
                     "check would pass any run");
  }
  for (std::size_t i = 0; i < ratios.size(); ++i) {
    const Json& r = ratios[i];
    const std::string where = baseline_source + ": timing_ratios[" + std::to_string(i) + "]";
    for (const char* key : {"numerator", "denominator"})
      if (!r.is_object() || !r.contains(key) || !r[key].is_string())
        throw InputError(where + ": needs a \"" + key + "\" pointer string");
    if (!r.contains("baseline") || !r["baseline"].is_number() || !(r["baseline"].get<double>() > 0.0))
      throw InputError(where + ": needs a positive \"baseline\" ratio");
    if (r.contains("tolerance") && !r["tolerance"].is_number()) throw InputError(where + ": \"tolerance\" must be a number");
    const double tol = r.contains("tolerance") ? r["tolerance"].get<double>() : 0.5;
    if (!(tol >= 0.0)) throw InputError(where + ": \"tolerance\" must be >= 0");
    if (r.contains("name") && !r["name"].is_string()) throw InputError(where + ": \"name\" must be a string");
    const std::string name = r.contains("name") ? r["name"].get<std::string>() : r["numerator"].get<std::string>();
    double num = 0.0, den = 0.0;
    std::string why;
    if (!lookup(summary, r["numerator"], num, why) || !lookup(summary, r["denominator"], den, why)) {
      fail("timing check " + name + ": " + why);
      continue;
    }
    if (!(den > 0.0)) {
      fail("timing check " + name + ": reference time is " + format_general(den, 4));
      continue;
    }
    const double ratio = num / den;
    const double limit = r["baseline"].get<double>() * (1.0 + tol);
    if (ratio > limit) {
      fail("timing regression: " + name + " ratio " + format_general(ratio, 4) + " exceeds baseline " + format_general(r["baseline"].get<double>(), 4) +
           " x (1 + " + format_general(tol, 4) + ") = " + format_general(limit, 4));
    } else {
      out.passes.push_back("ok: " + name + " ratio " + format_general(ratio, 4) + " <= " + format_general(limit, 4));
    }
  }
  return out;
}

}  // namespace floorcast

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
        it.key() != "scenario_hash")
      throw InputError(baseline_source + ": unknown key \"" + it.key() + "\"");
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

  const Json ratios = baseline.value("timing_ratios", Json::array());
  if (!ratios.is_array()) throw InputError(baseline_source + ": \"timing_ratios\" must be a list");
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

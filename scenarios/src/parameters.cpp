#include "floorcast/scenarios/parameters.hpp"

#include "floorcast/match/matcher.hpp"
#include "floorcast/observe/observation_module.hpp"
#include "floorcast/scenarios/scenario.hpp"
#include "floorcast/sim/odometry.hpp"
#include "floorcast/sim/walk.hpp"
#include "floorcast/track/tracker.hpp"

namespace floorcast {

std::vector<ParameterSet> parameter_sets() {
  std::vector<ParameterSet> out;
  for (auto& [block, fields] : scenario_block_fields()) {
    out.push_back({"scenario " + block, "scenario `" + block + ":` block", std::move(fields)});
  }
  out.push_back({"shared", "scenario `shared:` block; applied to every stage unless it overrides a key",
                 shared_fields().describe(SharedParams{})});
  out.push_back({"observation module",
                 "scenario `observation: {observe_params: {SECTION: {KEY: VALUE}}}`; `floorcast observe --observe-params "
                 "FILE`",
                 observation_fields().describe(ObservationParams{})});
  for (const std::string& name : builtin_matcher_names()) {
    out.push_back({"matcher " + name,
                   "scenario `matchers: {LABEL: {matcher: " + name + ", KEY: VALUE}}`; `floorcast localize --matcher " +
                       name + " --param KEY=VALUE`",
                   matcher_parameter_fields(name)});
  }
  out.push_back({"walk", "scenario `walk:` block (sequential scenarios); `floorcast sim walk --walk-params JSON`",
                 WalkParams::fields().describe()});
  out.push_back({"odometry", "scenario `odometry:` block; `floorcast sim walk --odometry-params JSON`",
                 OdometryParams::fields().describe()});
  out.push_back({"schedule", "scenario `schedule:` block: when observations are made along a walk",
                 schedule_fields().describe()});
  for (const std::string& name : tracker_names()) {
    out.push_back({"tracker " + name,
                   "scenario `trackers: {LABEL: {tracker: " + name + ", KEY: VALUE}}`; `floorcast track --filter " + name +
                       " --param KEY=VALUE`",
                   tracker_parameter_fields(name)});
  }
  return out;
}

nlohmann::ordered_json parameter_defaults_json(const std::vector<ParameterSet>& sets) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const ParameterSet& s : sets) {
    nlohmann::ordered_json one = nlohmann::ordered_json::object();
    for (const FieldInfo& f : s.fields) {
      nlohmann::ordered_json* node = &one;
      std::string key = f.key;
      for (auto dot = key.find('.'); dot != std::string::npos; dot = key.find('.')) {
        node = &(*node)[key.substr(0, dot)];
        key = key.substr(dot + 1);
      }
      (*node)[key] = f.value;
    }
    j[s.name] = one;
  }
  return j;
}

std::string parameters_markdown(const std::vector<ParameterSet>& sets) {
  std::string out =
      "# Parameters\n\n"
      "Generated from the field lists in the code (core/fields.hpp) by `floorcast params --markdown`; do not edit by\n"
      "hand (tests/scenarios/test_parameters_doc.cpp fails when this file is not current). Defaults are the code's;\n"
      "matcher defaults are shown with the shared quantities at their defaults (a scenario's `shared:` block changes\n"
      "range and blocking keys unless the matcher sets them itself).\n";
  for (const ParameterSet& s : sets) {
    out += "\n## " + s.name + "\n\nWhere: " + s.where + ".\n\n" + fields_markdown(s.fields);
  }
  return out;
}

}  // namespace floorcast

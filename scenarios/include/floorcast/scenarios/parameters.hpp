// Every parameter set of floorcast's stages, listed from their field lists (core/fields.hpp): the
// defaults listing of `floorcast params` and the docs table docs/parameters.md (generated from it;
// tests/scenarios/test_parameters_doc.cpp fails when the file is not current).
#pragma once

#include <string>
#include <vector>

#include "floorcast/core/fields.hpp"

namespace floorcast {

struct ParameterSet {
  std::string name;   ///< "matcher kernel", "tracker pf", "shared"
  std::string where;  ///< where a scenario or command takes it ("matchers.LABEL (matcher: kernel)", "--param")
  std::vector<FieldInfo> fields;
};

/// Every parameter set: the shared quantities, every registered matcher, every registered tracker.
std::vector<ParameterSet> parameter_sets();

/// The sets' defaults as one JSON object: name -> {key: default} (sections nested by dotted key).
nlohmann::ordered_json parameter_defaults_json(const std::vector<ParameterSet>& sets);

/// docs/parameters.md: one Markdown table per set.
std::string parameters_markdown(const std::vector<ParameterSet>& sets);

}  // namespace floorcast

// docs/parameters.md is generated from the field lists (floorcast params --markdown): it must be
// current, and the listing must cover every registered matcher and tracker.
#include <gtest/gtest.h>

#include "floorcast/core/file_io.hpp"
#include "floorcast/match/matcher.hpp"
#include "floorcast/scenarios/parameters.hpp"
#include "floorcast/track/tracker.hpp"

namespace floorcast {
namespace {

TEST(ParametersDoc, IsCurrent) {
  const std::string path = std::string(FLOORCAST_SOURCE_DIR) + "/docs/parameters.md";
  const std::string expected = parameters_markdown(parameter_sets());
  EXPECT_EQ(read_text_file(path), expected)
      << path << " is not what the field lists generate: regenerate it with\n"
      << "  build/bin/floorcast params --markdown > docs/parameters.md";
}

TEST(ParametersDoc, ListsEveryRegisteredMatcherAndTrackerWithTheDefaultsTheyWrite) {
  const std::vector<ParameterSet> sets = parameter_sets();
  const nlohmann::ordered_json defaults = parameter_defaults_json(sets);
  for (const std::string& m : builtin_matcher_names()) {
    ASSERT_TRUE(defaults.contains("matcher " + m)) << m;
    nlohmann::ordered_json expected = defaults.at("matcher " + m);
    nlohmann::json overrides = nlohmann::json::object();
    if (m == "external") {  // its program has no default
      overrides["command"] = {"my_matcher"};
      expected["command"] = {"my_matcher"};
    }
    EXPECT_EQ(expected, make_matcher_config(m, overrides)->parameters()) << m;
  }
  for (const std::string& t : tracker_names()) {
    ASSERT_TRUE(defaults.contains("tracker " + t)) << t;
    EXPECT_EQ(defaults.at("tracker " + t), make_tracker_config(t)->parameters()) << t;
  }
}

}  // namespace
}  // namespace floorcast

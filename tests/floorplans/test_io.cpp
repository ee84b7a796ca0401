#include <gtest/gtest.h>

#include "common/scratch_dir.hpp"

#include <nlohmann/json.hpp>

#include "floorcast/floorplans/io.hpp"
#include "test_plans.hpp"

namespace floorcast {
namespace {

using Json = nlohmann::ordered_json;

TEST(PlanIo, RoundTripIsByteIdenticalAndLossless) {
  const FloorPlan plan = test::furnished_room();
  const std::string text = floor_plan_to_json(plan);
  const FloorPlan back = parse_floor_plan_json(text, "mem.json");
  EXPECT_EQ(floor_plan_to_json(back), text);
  ASSERT_EQ(back.walls.size(), plan.walls.size());
  EXPECT_EQ(back.name, "furnished");
  EXPECT_EQ(back.level, 2);
  EXPECT_EQ(back.walls[1].material, WallMaterial::kGlass);
  ASSERT_TRUE(back.walls[1].glass_head_m.has_value());
  EXPECT_DOUBLE_EQ(*back.walls[1].glass_head_m, 2.4);
  EXPECT_EQ(back.doors[1].closed, true);
  EXPECT_DOUBLE_EQ(back.obstacles[0].yaw_rad, 0.3);
  EXPECT_EQ(back.obstacles[1].kind, ObstacleKind::kPillar);
  EXPECT_EQ(plan_hash(back), plan_hash(plan));
}

TEST(PlanIo, HashChangesWithContent) {
  FloorPlan a = test::box_room();
  FloorPlan b = a;
  b.walls[0].thickness_m = 0.25;
  EXPECT_NE(plan_hash(a), plan_hash(b));
}

TEST(PlanIo, MinimalFileUsesDocumentedDefaults) {
  const std::string text = R"({"format_version": 1, "walls": [
    {"id": "w", "a": [0, 0], "b": [3, 0]}]})";
  const FloorPlan p = parse_floor_plan_json(text, "min.json");
  EXPECT_EQ(p.name, "");
  EXPECT_EQ(p.level, 0);
  EXPECT_DOUBLE_EQ(p.walls[0].thickness_m, 0.15);
  EXPECT_EQ(p.walls[0].material, WallMaterial::kSolid);
}

struct BadCase {
  const char* what;
  std::function<void(Json&)> mutate;  // applied to a valid plan's JSON (empty = use raw text)
  const char* raw;                    // used when non-null
  std::vector<const char*> expected;  // substrings of the message
};

void PrintTo(const BadCase& c, std::ostream* os) { *os << c.what; }

class PlanValidation : public ::testing::TestWithParam<BadCase> {};

TEST_P(PlanValidation, RefusesWithAClearMessage) {
  const BadCase& c = GetParam();
  std::string text;
  if (c.raw) {
    text = c.raw;
  } else {
    Json j = Json::parse(floor_plan_to_json(test::furnished_room()));
    c.mutate(j);
    text = j.dump();
  }
  try {
    (void)parse_floor_plan_json(text, "bad.json");
    FAIL() << c.what << ": accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind("bad.json:", 0), 0u) << msg;  // "bad.json: ..." or "bad.json:LINE:COLUMN: ..."
    for (const char* s : c.expected) EXPECT_NE(msg.find(s), std::string::npos) << c.what << ": " << msg;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Errors, PlanValidation,
    ::testing::Values(
        BadCase{"malformed", {}, "{\"format_version\": 1, \"walls\": [", {"malformed JSON"}},
        BadCase{"nan literal", {}, "{\"format_version\": 1, \"walls\": [{\"id\":\"w\",\"a\":[NaN,0],\"b\":[1,0]}]}",
                {"malformed JSON"}},
        BadCase{"not an object", {}, "[1, 2]", {"top level must be a JSON object"}},
        BadCase{"overflowing number", {}, "{\"format_version\": 1, \"walls\": [{\"id\":\"w\",\"a\":[1e999,0],\"b\":[1,0]}]}",
                {"malformed JSON", "overflow"}},
        BadCase{"missing version", [](Json& j) { j.erase("format_version"); }, nullptr,
                {"missing required field \"format_version\""}},
        BadCase{"future version", [](Json& j) { j["format_version"] = 7; }, nullptr,
                {"unsupported format_version 7"}},
        BadCase{"unknown top field", [](Json& j) { j["colour"] = "red"; }, nullptr, {"unknown field \"colour\""}},
        BadCase{"missing walls", [](Json& j) { j.erase("walls"); }, nullptr, {"missing required field \"walls\""}},
        BadCase{"no walls", [](Json& j) {
                  j["walls"] = Json::array();
                  j["doors"] = Json::array();
                  j["windows"] = Json::array();
                }, nullptr, {"plan has no walls"}},
        BadCase{"missing wall endpoint", [](Json& j) { j["walls"][2].erase("b"); }, nullptr,
                {"walls[2] (id \"north\")", "missing required field \"b\""}},
        BadCase{"unknown wall field", [](Json& j) { j["walls"][0]["height"] = 3; }, nullptr,
                {"walls[0] (id \"south\")", "unknown field \"height\""}},
        BadCase{"wrong type", [](Json& j) { j["walls"][0]["thickness_m"] = "thick"; }, nullptr,
                {"walls[0]", "must be a number"}},
        BadCase{"bad point", [](Json& j) { j["walls"][0]["a"] = Json::array({1, 2, 3}); }, nullptr,
                {"walls[0]", "array [x, y]"}},
        BadCase{"zero-length wall", [](Json& j) { j["walls"][3]["b"] = j["walls"][3]["a"]; }, nullptr,
                {"walls[3] (id \"west\")", "degenerate"}},
        BadCase{"absurd wall", [](Json& j) { j["walls"][0]["b"] = Json::array({20000.0, 0.0}); }, nullptr,
                {"walls[0] (id \"south\")", "absurd"}},
        BadCase{"absurd coordinate", [](Json& j) {
                  j["walls"][0]["a"] = Json::array({2e5, 0.0});
                  j["walls"][0]["b"] = Json::array({2e5 + 1, 0.0});
                }, nullptr, {"walls[0]", "absurdly far"}},
        BadCase{"zero thickness", [](Json& j) { j["walls"][0]["thickness_m"] = 0.0; }, nullptr,
                {"walls[0]", "thickness_m"}},
        BadCase{"bad material", [](Json& j) { j["walls"][0]["material"] = "wood"; }, nullptr,
                {"walls[0]", "material must be"}},
        BadCase{"glass fields on solid", [](Json& j) { j["walls"][0]["glass_sill_m"] = 0.5; }, nullptr,
                {"walls[0]", "solid wall"}},
        BadCase{"duplicate id", [](Json& j) { j["doors"][1]["id"] = "south"; }, nullptr,
                {"doors[1]", "duplicate id \"south\"", "walls[0]"}},
        BadCase{"door off its wall", [](Json& j) { j["doors"][0]["center"] = Json::array({2.0, 1.0}); }, nullptr,
                {"doors[0] (id \"d1\")", "does not lie on wall \"south\"", "from the wall axis"}},
        BadCase{"door beyond wall end", [](Json& j) { j["doors"][0]["center"] = Json::array({5.9, 0.0}); }, nullptr,
                {"doors[0] (id \"d1\")", "leaves the wall"}},
        BadCase{"door on unknown wall", [](Json& j) { j["doors"][0]["wall"] = "nowhere"; }, nullptr,
                {"doors[0]", "unknown wall \"nowhere\""}},
        BadCase{"overlapping doors", [](Json& j) { j["doors"][1]["wall"] = "south"; j["doors"][1]["center"] = Json::array({2.5, 0.0}); }, nullptr,
                {"overlaps"}},
        BadCase{"window in glass", [](Json& j) { j["windows"][0]["wall"] = "east"; j["windows"][0]["center"] = Json::array({6.0, 2.0}); }, nullptr,
                {"windows[0]", "glass wall"}},
        BadCase{"window head below sill", [](Json& j) { j["windows"][0]["head_m"] = 0.5; }, nullptr,
                {"windows[0]", "head_m must be above sill_m"}},
        BadCase{"obstacle kind", [](Json& j) { j["obstacles"][0]["kind"] = "sofa"; }, nullptr,
                {"obstacles[0] (id \"desk\")", "kind must be"}},
        BadCase{"obstacle negative size", [](Json& j) { j["obstacles"][0]["size_m"] = Json::array({-1.0, 1.0}); }, nullptr,
                {"obstacles[0]", "size_m[0]"}},
        BadCase{"obstacle missing height", [](Json& j) { j["obstacles"][1].erase("height_m"); }, nullptr,
                {"obstacles[1] (id \"pillar\")", "missing required field \"height_m\""}}),
    [](const ::testing::TestParamInfo<BadCase>& info) {
      std::string name = info.param.what;
      for (char& ch : name) if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      return name;
    });

TEST(PlanIo, MissingFileNamesThePath) {
  try {
    (void)load_floor_plan("/nonexistent/plan.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/plan.json"), std::string::npos);
  }
}

TEST(PlanIo, SaveThenLoad) {
  const test::ScratchDir scratch;
  const std::string path = scratch.file("roundtrip.json");
  const FloorPlan plan = test::furnished_room();
  save_floor_plan(plan, path);
  EXPECT_EQ(floor_plan_to_json(load_floor_plan(path)), floor_plan_to_json(plan));
}

}  // namespace
}  // namespace floorcast

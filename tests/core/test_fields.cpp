// The field-list mechanism (core/fields.hpp): one declaration gives reading, writing, validation
// and the docs table, and they agree with one another.
#include <gtest/gtest.h>

#include "floorcast/core/fields.hpp"

namespace floorcast {
namespace {

enum class Colour { kRed, kGreen };

struct Inner {
  double width_m = 1.5;
  int count = 3;
};

struct Example {
  double alpha = 0.5;
  int steps = 10;
  std::uint64_t seed = 7;
  bool enabled = true;
  std::string label = "x";
  std::vector<double> scales = {0.9, 1.0};
  Colour colour = Colour::kGreen;
  Inner flat;
  Inner nested;
  BlockingOptions blocking;
};

const FieldList<Inner>& inner_fields() {
  static const FieldList<Inner> f = FieldList<Inner>("inner")
                                        .number("width_m", &Inner::width_m, 0.0, 10.0, "width, m")
                                        .integer("count", &Inner::count, 1, 5, "how many")
                                        .check([](const Inner& i, const ParamReader& r) {
                                          if (i.count == 4) r.fail("count", "must not be 4");
                                        });
  return f;
}

const FieldList<Example>& example_fields() {
  using E = Example;
  static const FieldList<E> f =
      FieldList<E>("example")
          .number("alpha", &E::alpha, 0.0, 1.0, "a weight")
          .integer("steps", &E::steps, 1, 100, "steps")
          .unsigned_integer("seed", &E::seed, "seed")
          .flag("enabled", &E::enabled, "on or off")
          .text("label", &E::label, "a name")
          .numbers("scales", &E::scales, 0.1, 10.0, "scales")
          .choice("colour", &E::colour, std::vector<std::pair<const char*, Colour>>{{"red", Colour::kRed}, {"green", Colour::kGreen}},
                  "a colour")
          .flatten(&E::flat, inner_fields())
          .section("nested", [](auto& e) -> auto& { return e.nested; }, inner_fields())
          .flatten(&E::blocking, blocking_fields());
  return f;
}

TEST(Fields, WritesEveryFieldInDeclarationOrderWithItsType) {
  const nlohmann::ordered_json j = example_fields().write(Example{});
  EXPECT_EQ(j.dump(),
            R"({"alpha":0.5,"steps":10,"seed":7,"enabled":true,"label":"x","scales":[0.9,1.0],"colour":"green",)"
            R"("width_m":1.5,"count":3,"nested":{"width_m":1.5,"count":3},"doors_closed":false,"glass_blocks":true,)"
            R"("obstacles_block":false,"cut_height_m":1.5})");
}

TEST(Fields, ReadIsTheInverseOfWrite) {
  Example a;
  a.alpha = 0.25;
  a.steps = 99;
  a.seed = 123456789012345ULL;
  a.enabled = false;
  a.label = "other";
  a.scales = {2.0};
  a.colour = Colour::kRed;
  a.flat.width_m = 9.0;
  a.nested.count = 5;
  a.blocking.glass_blocks = false;
  Example b;
  example_fields().read(b, nlohmann::json(example_fields().write(a)));
  EXPECT_EQ(example_fields().write(b).dump(), example_fields().write(a).dump());
}

TEST(Fields, RefusesBadValuesNamingTheKey) {
  auto key_of = [](const nlohmann::json& overrides) -> std::string {
    Example e;
    try {
      example_fields().read(e, overrides);
    } catch (const ParameterError& err) {
      return err.key();
    }
    return "(accepted)";
  };
  EXPECT_EQ(key_of({{"alpha", 2.0}}), "alpha");
  EXPECT_EQ(key_of({{"alpha", "0.5"}}), "alpha");
  EXPECT_EQ(key_of({{"steps", 1.5}}), "steps");
  EXPECT_EQ(key_of({{"seed", -1}}), "seed");
  EXPECT_EQ(key_of({{"colour", "blue"}}), "colour");
  EXPECT_EQ(key_of({{"scales", nlohmann::json::array()}}), "scales");
  EXPECT_EQ(key_of({{"nested", {{"count", 9}}}}), "nested.count");
  EXPECT_EQ(key_of({{"nested", {{"width", 1}}}}), "nested.width");
  EXPECT_EQ(key_of({{"nested", 3}}), "nested");
  EXPECT_EQ(key_of({{"count", 4}}), "count");             // a rule of the flattened struct
  EXPECT_EQ(key_of({{"nested", {{"count", 4}}}}), "nested.count");  // ... and of the section
  EXPECT_EQ(key_of({{"alhpa", 0.5}}), "alhpa");            // unknown key
  EXPECT_EQ(key_of({{"cut_height_m", -1.0}}), "cut_height_m");
  EXPECT_EQ(key_of({{"alpha", 1.0}, {"doors_closed", true}}), "(accepted)");
}

TEST(Fields, ValidateHoldsValuesSetInCodeToTheSameRanges) {
  Example e;
  EXPECT_NO_THROW(example_fields().validate(e));
  e.nested.width_m = 11.0;
  try {
    example_fields().validate(e);
    FAIL() << "accepted nested.width_m 11";
  } catch (const ParameterError& err) {
    EXPECT_EQ(err.key(), "nested.width_m");
  }
}

TEST(Fields, DescribeListsEveryKeyWithItsDefaultAndRange) {
  const std::vector<FieldInfo> d = example_fields().describe();
  ASSERT_EQ(d.size(), 15u);
  EXPECT_EQ(d[0].key, "alpha");
  EXPECT_EQ(d[0].range, "[0.0, 1.0]");
  EXPECT_EQ(d[1].range, "[1, 100]");
  EXPECT_EQ(d[6].type, "red | green");
  EXPECT_EQ(d[6].value, "green");
  EXPECT_EQ(d[9].key, "nested.width_m");
  EXPECT_EQ(d[11].key, "doors_closed");
  // Every listed key is one write() writes, with the same value.
  const nlohmann::ordered_json j = example_fields().write(Example{});
  for (const FieldInfo& f : d) {
    const auto dot = f.key.find('.');
    const nlohmann::ordered_json& v = dot == std::string::npos ? j.at(f.key) : j.at(f.key.substr(0, dot)).at(f.key.substr(dot + 1));
    EXPECT_EQ(v, f.value) << f.key;
  }
  const std::string md = fields_markdown(d);
  EXPECT_NE(md.find("| `colour` | `\"green\"` | red \\| green |  | a colour |"), std::string::npos) << md;
}

}  // namespace
}  // namespace floorcast

// The BEV value types (core/bev.hpp): log-spaced bins, the one-hot rendering rule, the
// observation schema's "bev" entries, and the scan folder's column semantics and view BEV files.
#include <gtest/gtest.h>

#include "common/scratch_dir.hpp"

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "floorcast/core/bev.hpp"
#include "floorcast/core/depth_io.hpp"
#include "floorcast/core/file_io.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/core/observation_io.hpp"
#include "floorcast/core/scan_io.hpp"

namespace floorcast {
namespace {

namespace fs = std::filesystem;

TEST(BevBins, LogSpacedEdgesAndBinOf) {
  const BevDepthBins b{32, 0.3, 10.0};
  EXPECT_DOUBLE_EQ(b.edge_m(0), 0.3);
  EXPECT_DOUBLE_EQ(b.edge_m(32), 10.0);
  const double q = std::pow(10.0 / 0.3, 1.0 / 32.0);
  for (int k = 0; k < 32; ++k) {
    EXPECT_NEAR(b.edge_m(k + 1) / b.edge_m(k), q, 1e-12);
    EXPECT_EQ(b.bin_of(b.edge_m(k)), k) << k;                   // edges belong to the bin above
    EXPECT_EQ(b.bin_of(b.centre_m(k)), k) << k;
    EXPECT_EQ(b.bin_of(std::nextafter(b.edge_m(k + 1), 0.0)), k) << k;
  }
  EXPECT_EQ(b.bin_of(0.0), 0);   // below the first edge: bin 0
  EXPECT_EQ(b.bin_of(0.1), 0);
  EXPECT_EQ(b.bin_of(10.0), -1);  // the last edge is outside
  EXPECT_EQ(b.bin_of(std::nan("")), -1);
  EXPECT_THROW(BevDepthBins({0, 0.3, 10.0}).check("x"), InputError);
  EXPECT_THROW(BevDepthBins({8, 2.0, 1.0}).check("x"), InputError);
}

// Doors (open and closed) and windows pass and mark their bin, the wall stops and wins its bin,
// furniture is not drawn; occupancy: walls and windows stop, doors vanish.
TEST(BevRender, ThesisRayCastingRule) {
  const BevDepthBins b{32, 0.3, 10.0};
  const std::vector<SemanticHit> hits = {{SemanticClass::kFurniture, 0.8},
                                         {SemanticClass::kDoorClosed, 1.5},
                                         {SemanticClass::kWindow, 3.0},
                                         {SemanticClass::kDoorOpen, 4.0},
                                         {SemanticClass::kWall, 6.0}};
  std::vector<int> cls(32);
  render_bev_column(hits, BevClasses::kSemantic, b, cls.data());
  for (int d = 0; d < 32; ++d) {
    int expect = kBevEmpty;
    if (d == b.bin_of(1.5) || d == b.bin_of(4.0)) expect = kBevDoor;
    if (d == b.bin_of(3.0)) expect = kBevWindow;
    if (d == b.bin_of(6.0)) expect = kBevWall;
    EXPECT_EQ(cls[static_cast<std::size_t>(d)], expect) << d;
  }
  render_bev_column(hits, BevClasses::kOccupancy, b, cls.data());
  for (int d = 0; d < 32; ++d) EXPECT_EQ(cls[static_cast<std::size_t>(d)], d == b.bin_of(3.0) ? kBevOccupied : kBevFree) << d;
  // A door in the wall's bin: the wall wins.
  render_bev_column({{SemanticClass::kDoorOpen, 6.0}, {SemanticClass::kWall, 6.01}}, BevClasses::kSemantic, b, cls.data());
  EXPECT_EQ(cls[static_cast<std::size_t>(b.bin_of(6.0))], kBevWall);
  // Beyond the last edge nothing is drawn.
  render_bev_column({{SemanticClass::kWall, 12.0}}, BevClasses::kSemantic, b, cls.data());
  for (int c : cls) EXPECT_EQ(c, kBevEmpty);
}

BevPrediction random_bev(BevClasses classes, int W, int D, unsigned seed) {
  BevPrediction b;
  b.classes = classes;
  b.bins = {D, 0.3, 10.0};
  b.column_azimuth_rad = full_circle_azimuths(W);
  const int C = b.num_classes();
  std::uint32_t s = seed;
  for (int i = 0; i < W * D; ++i) {
    float v[4], sum = 0.0f;
    for (int c = 0; c < C; ++c) {
      s = s * 1664525u + 1013904223u;
      v[c] = static_cast<float>((s >> 8) & 0xffff) / 65536.0f + 0.01f;
      sum += v[c];
    }
    for (int c = 0; c < C; ++c) b.probabilities.push_back(v[c] / sum);
  }
  return b;
}

TEST(BevObservationIo, RoundTripAndRefusals) {
  ObservationRecord rec;
  rec.observation.segments_m = {{Vec2(1, -1), Vec2(1, 1)}};
  rec.observation.bev = {random_bev(BevClasses::kSemantic, 12, 8, 1), random_bev(BevClasses::kOccupancy, 5, 8, 2)};
  const std::string text = observation_to_json_text(rec);
  const ObservationRecord back = parse_observation_json(text, "obs.json");
  ASSERT_EQ(back.observation.bev.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const BevPrediction& a = rec.observation.bev[i];
    const BevPrediction& b = back.observation.bev[i];
    EXPECT_EQ(a.classes, b.classes);
    EXPECT_TRUE(a.bins == b.bins);
    EXPECT_EQ(a.column_azimuth_rad, b.column_azimuth_rad);
    ASSERT_EQ(a.probabilities.size(), b.probabilities.size());
    for (std::size_t k = 0; k < a.probabilities.size(); ++k) EXPECT_NEAR(a.probabilities[k], b.probabilities[k], 6e-7);
  }
  EXPECT_EQ(observation_to_json_text(back), text);
  // A BEV whose distributions do not sum to 1, two of one class set, a short array.
  nlohmann::json j = nlohmann::json::parse(text);
  j["bev"][0]["probabilities"][0] = 0.9;
  j["bev"][0]["probabilities"][1] = 0.9;
  EXPECT_THROW(parse_observation_json(j.dump(), "o.json"), InputError);
  j = nlohmann::json::parse(text);
  j["bev"][1] = j["bev"][0];
  EXPECT_THROW(parse_observation_json(j.dump(), "o.json"), InputError);
  j = nlohmann::json::parse(text);
  j["bev"][0]["probabilities"].erase(0);
  try {
    parse_observation_json(j.dump(), "o.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bev[0]"), std::string::npos) << e.what();
  }
}

class BevScanIo : public ::testing::Test {
 protected:
  static Scan scan() {
    Scan s;
    DepthView v;
    v.intrinsics = {8, 6, 5.0, 5.0, 3.5, 2.5};
    v.depth_m = cv::Mat(6, 8, CV_32F, cv::Scalar(2.0f));
    v.column_semantics.resize(8);
    for (int u = 0; u < 8; ++u) {
      if (u % 2) v.column_semantics[static_cast<std::size_t>(u)].push_back({SemanticClass::kDoorOpen, 1.0 + 0.1 * u});
      v.column_semantics[static_cast<std::size_t>(u)].push_back({SemanticClass::kWall, 3.12345 + u});
    }
    s.views.push_back(v);
    return s;
  }
  const test::ScratchDir scratch_;
  const fs::path dir_ = scratch_.path() / "scan";
};

TEST_F(BevScanIo, ColumnSemanticsAndViewBevRoundTrip) {
  Scan s = scan();
  BevPrediction b = random_bev(BevClasses::kSemantic, 4, 16, 3);
  s.views[0].bev = b;
  save_scan(dir_.string(), s);
  EXPECT_TRUE(fs::exists(dir_ / "view_000_semantics.json"));
  EXPECT_TRUE(fs::exists(dir_ / "view_000_bev.npy"));
  const Scan back = load_scan(dir_.string());
  ASSERT_EQ(back.views.size(), 1u);
  // Ranges are written to 0.1 mm.
  ASSERT_EQ(back.views[0].column_semantics.size(), s.views[0].column_semantics.size());
  for (std::size_t u = 0; u < s.views[0].column_semantics.size(); ++u) {
    const auto& a = s.views[0].column_semantics[u];
    const auto& b = back.views[0].column_semantics[u];
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].label, b[i].label);
      EXPECT_NEAR(a[i].range_m, b[i].range_m, 5e-5);
    }
  }
  const BevPrediction& r = back.views[0].bev;
  EXPECT_EQ(r.classes, BevClasses::kSemantic);
  EXPECT_TRUE(r.bins == b.bins);
  ASSERT_EQ(r.probabilities.size(), b.probabilities.size());
  for (std::size_t k = 0; k < r.probabilities.size(); ++k) EXPECT_NEAR(r.probabilities[k], b.probabilities[k], 1e-6);
  // Columns spread over the image width, azimuths relative to the heading (left positive).
  ASSERT_EQ(r.num_columns(), 4);
  EXPECT_NEAR(r.column_azimuth_rad[0], std::atan((3.5 - 0.5) / 5.0), 1e-12);
  EXPECT_NEAR(r.column_azimuth_rad[3], std::atan((3.5 - 6.5) / 5.0), 1e-12);
}

TEST_F(BevScanIo, BroughtBevIsCheckedAndRepaired) {
  Scan s = scan();
  s.views[0].column_semantics.clear();
  save_scan(dir_.string(), s);
  // A view BEV needs the scan-level block.
  nlohmann::json j = nlohmann::json::parse(read_text_file((dir_ / "scan.json").string()));
  j["views"][0]["bev"] = "mine.npy";
  write_text_file_atomic((dir_ / "scan.json").string(), j.dump());
  write_npy((dir_ / "mine.npy").string(), {3, 4, 4}, std::vector<float>(48, 0.25f));
  EXPECT_THROW(load_scan(dir_.string()), InputError);
  j["bev"] = {{"classes", "semantic"}, {"min_depth_m", 0.3}, {"max_depth_m", 10.0}};
  write_text_file_atomic((dir_ / "scan.json").string(), j.dump());
  EXPECT_EQ(load_scan(dir_.string()).views[0].bev.num_columns(), 3);
  // Slightly off sums are renormalised; logits and wrong class counts are refused with the file named.
  std::vector<float> off(48, 0.2505f);
  write_npy((dir_ / "mine.npy").string(), {3, 4, 4}, off);
  const Scan repaired = load_scan(dir_.string());
  EXPECT_NEAR(repaired.views[0].bev.p(0, 0, 0), 0.25f, 1e-7);
  write_npy((dir_ / "mine.npy").string(), {3, 4, 4}, std::vector<float>(48, 2.0f));
  EXPECT_THROW(load_scan(dir_.string()), InputError);
  write_npy((dir_ / "mine.npy").string(), {3, 4, 2}, std::vector<float>(24, 0.5f));
  try {
    load_scan(dir_.string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mine.npy"), std::string::npos) << e.what();
  }
}

TEST(BevColumnSemanticsIo, RefusesMalformedFiles) {
  const std::string ok = column_semantics_json_text({{{SemanticClass::kWall, 2.0}}, {}});
  EXPECT_EQ(parse_column_semantics(ok, "s.json", 2).size(), 2u);
  EXPECT_THROW(parse_column_semantics(ok, "s.json", 3), InputError);  // one entry per column
  nlohmann::json j = nlohmann::json::parse(ok);
  j["columns"][1] = {{"wall", 2.0}, {"door_open", 3.0}};  // a hit after the wall
  EXPECT_THROW(parse_column_semantics(j.dump(), "s.json", 2), InputError);
  j["columns"][1] = {{"door_open", 3.0}, {"wall", 2.0}};  // not nearest first
  EXPECT_THROW(parse_column_semantics(j.dump(), "s.json", 2), InputError);
  j["columns"][1] = {{"painting", 3.0}};
  EXPECT_THROW(parse_column_semantics(j.dump(), "s.json", 2), InputError);
}

}  // namespace
}  // namespace floorcast

// The simulated BEV predictor (observe/bev_predictor.hpp): the perfect preset is the one-hot
// rendering of the truth, each error-model component does what it says, the same scan gives the
// same bytes, a brought BEV replaces the prediction, and a simulated scan through the perfect
// predictor localises exactly with the BEV matcher.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "floorcast/core/math.hpp"
#include "floorcast/match/bev_matcher.hpp"
#include "floorcast/observe/bev_predictor.hpp"
#include "floorcast/observe/observation_module.hpp"
#include "floorcast/sim/mesh.hpp"
#include "floorcast/sim/ray_scene.hpp"
#include "floorcast/sim/scan_sim.hpp"

namespace floorcast {
namespace {

const BevDepthBins kBins{32, 0.3, 10.0};

double class_mass(const std::vector<float>& col, int C, int cls, int from = 0, int to = 32) {
  double m = 0.0;
  for (int d = from; d < to; ++d) m += col[static_cast<std::size_t>(d) * C + cls];
  return m;
}

BevColumnElement el(SemanticClass c, double r) {
  BevColumnElement e;
  e.truth = c;
  e.range_m = r;
  return e;
}

TEST(BevPredictorColumn, PerfectIsTheOneHotRendering) {
  const BevErrorModel perfect = bev_error_preset("perfect");
  const std::vector<SemanticHit> hits = {{SemanticClass::kFurniture, 0.9},
                                         {SemanticClass::kDoorClosed, 1.7},
                                         {SemanticClass::kWindow, 2.6},
                                         {SemanticClass::kWall, 5.5}};
  std::vector<BevColumnElement> els;
  for (const SemanticHit& h : hits) els.push_back(el(h.label, h.range_m));
  for (const BevClasses classes : {BevClasses::kSemantic, BevClasses::kOccupancy}) {
    const std::vector<float> col = predict_bev_column(els, classes, kBins, perfect);
    std::vector<int> cls(32);
    render_bev_column(hits, classes, kBins, cls.data());
    const int C = bev_class_count(classes);
    for (int d = 0; d < 32; ++d) {
      for (int c = 0; c < C; ++c) {
        EXPECT_EQ(col[static_cast<std::size_t>(d) * C + c], c == cls[static_cast<std::size_t>(d)] ? 1.0f : 0.0f) << d << " " << c;
      }
    }
  }
}

TEST(BevPredictorColumn, ErrorComponents) {
  BevErrorModel m = bev_error_preset("perfect");
  const int C = 4;
  const int win = kBins.bin_of(2.6), wall = kBins.bin_of(5.5), door = kBins.bin_of(1.7);
  // A window predicted as a wall stops the ray there: no wall behind.
  std::vector<BevColumnElement> els = {el(SemanticClass::kWindow, 2.6), el(SemanticClass::kWall, 5.5)};
  els[0].as_wall = true;
  std::vector<float> col = predict_bev_column(els, BevClasses::kSemantic, kBins, m);
  EXPECT_EQ(col[static_cast<std::size_t>(win) * C + kBevWall], 1.0f);
  EXPECT_EQ(class_mass(col, C, kBevWall), 1.0);
  // A wall predicted as a window (a painting).
  els = {el(SemanticClass::kWall, 5.5)};
  els[0].as_window = true;
  col = predict_bev_column(els, BevClasses::kSemantic, kBins, m);
  EXPECT_EQ(col[static_cast<std::size_t>(wall) * C + kBevWindow], 1.0f);
  EXPECT_EQ(class_mass(col, C, kBevWall), 0.0);
  // A missed door leaves no door mass; an open door does not occlude the wall behind.
  els = {el(SemanticClass::kDoorOpen, 1.7), el(SemanticClass::kWall, 5.5)};
  els[0].missed = true;
  col = predict_bev_column(els, BevClasses::kSemantic, kBins, m);
  EXPECT_EQ(class_mass(col, C, kBevDoor), 0.0);
  EXPECT_EQ(col[static_cast<std::size_t>(wall) * C + kBevWall], 1.0f);
  // Behind a closed door the wall is unseen: with occluded_spread 1 its mass is spread evenly over
  // the bins beyond the door.
  m.occluded_spread = 1.0;
  els = {el(SemanticClass::kDoorClosed, 1.7), el(SemanticClass::kWall, 5.5)};
  col = predict_bev_column(els, BevClasses::kSemantic, kBins, m);
  EXPECT_NEAR(col[static_cast<std::size_t>(door) * C + kBevDoor], 1.0f, 1e-6);
  EXPECT_NEAR(class_mass(col, C, kBevWall, door + 1, 32), 1.0, 1e-6);
  EXPECT_NEAR(col[static_cast<std::size_t>(door + 1) * C + kBevWall], 1.0 / (31 - door), 1e-6);
  // Furniture masked (not a wall): the same for the wall behind it; predicted as a wall: it stops.
  els = {el(SemanticClass::kFurniture, 1.7), el(SemanticClass::kWall, 5.5)};
  col = predict_bev_column(els, BevClasses::kSemantic, kBins, m);
  EXPECT_NEAR(class_mass(col, C, kBevWall, door + 1, 32), 1.0, 1e-6);
  els[0].as_wall = true;
  col = predict_bev_column(els, BevClasses::kSemantic, kBins, m);
  EXPECT_EQ(col[static_cast<std::size_t>(door) * C + kBevWall], 1.0f);
  EXPECT_EQ(class_mass(col, C, kBevWall), 1.0);
  // Depth spread: the mass leaves the true bin, grows with range, keeps its total.
  m = bev_error_preset("perfect");
  m.depth_sigma_ln = 0.05;
  m.depth_sigma_ln_per_m = 0.02;
  col = predict_bev_column({el(SemanticClass::kWall, 1.0)}, BevClasses::kSemantic, kBins, m);
  const float near_peak = col[static_cast<std::size_t>(kBins.bin_of(1.0)) * C + kBevWall];
  col = predict_bev_column({el(SemanticClass::kWall, 6.0)}, BevClasses::kSemantic, kBins, m);
  const float far_peak = col[static_cast<std::size_t>(kBins.bin_of(6.0)) * C + kBevWall];
  EXPECT_LT(far_peak, near_peak);
  EXPECT_LT(near_peak, 1.0f);
  EXPECT_NEAR(class_mass(col, C, kBevWall), 1.0, 2e-3);  // the tail beyond 10 m is lost
  // Confidence and floor mass; every (bin) stays a distribution.
  m.peak_mass = 0.8;
  m.floor_mass = 0.2;
  col = predict_bev_column({el(SemanticClass::kWall, 3.0)}, BevClasses::kSemantic, kBins, m);
  EXPECT_NEAR(class_mass(col, C, kBevWall), 0.8 * 0.8 + 0.2 * 32 / 4.0, 1e-3);
  for (int d = 0; d < 32; ++d) {
    double s = 0.0;
    for (int c = 0; c < C; ++c) s += col[static_cast<std::size_t>(d) * C + c];
    EXPECT_NEAR(s, 1.0, 1e-6);
    EXPECT_GE(col[static_cast<std::size_t>(d) * C + kBevDoor], 0.2f / 4 - 1e-6);
  }
}

/// A one-view scan whose annotation has a door and a wall in every column.
Scan annotated_scan() {
  Scan s;
  DepthView v;
  v.intrinsics = {64, 48, 40.0, 40.0, 31.5, 23.5};
  // Looking along the scan's +x: camera z = +x, camera x = -y, camera y = -z.
  v.T_scan_camera.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  v.column_semantics.resize(64);
  for (int u = 0; u < 64; ++u) {
    v.column_semantics[static_cast<std::size_t>(u)] = {{SemanticClass::kDoorOpen, 1.5 + 0.01 * u},
                                                       {SemanticClass::kWall, 4.0 + 0.02 * u}};
  }
  s.views.push_back(v);
  return s;
}

TEST(BevPredictor, ColumnsDeterminismAndBroughtBevs) {
  const Scan scan = annotated_scan();
  BevPredictorParams p;
  p.enabled = true;
  const BevPredictionResult a = predict_bev(scan, p), b = predict_bev(scan, p);
  ASSERT_EQ(a.bev.size(), 2u);
  EXPECT_EQ(a.bev[0].classes, BevClasses::kSemantic);
  EXPECT_EQ(a.bev[1].classes, BevClasses::kOccupancy);
  // 5 deg columns within the view's +-38.2 deg field of view around its heading (0).
  const double heading = view_heading_rad(scan.views[0]);
  EXPECT_NEAR(heading, 0.0, 1e-12);
  for (const double az : a.bev[0].column_azimuth_rad) {
    EXPECT_LE(std::abs(wrap_angle_rad(az - heading)), std::atan(31.5 / 40.0) + 1e-9);
    EXPECT_NEAR(std::remainder(az, deg_to_rad(5.0)), 0.0, 1e-9);
  }
  EXPECT_EQ(a.bev[0].num_columns(), 15);
  EXPECT_EQ(a.bev[0].probabilities, b.bev[0].probabilities);
  ASSERT_NO_THROW(a.bev[0].check("a"));
  ASSERT_NO_THROW(a.bev[1].check("a"));
  p.seed = 2;
  EXPECT_NE(predict_bev(scan, p).bev[0].probabilities, a.bev[0].probabilities);
  // A brought BEV replaces the prediction (its class set only).
  Scan byo = scan;
  BevPrediction& own = byo.views[0].bev;
  own.classes = BevClasses::kSemantic;
  own.bins = kBins;
  for (int w = 0; w < 8; ++w) own.column_azimuth_rad.push_back(std::atan((31.5 - (8.0 * w + 3.5)) / 40.0));
  own.probabilities.assign(8 * 32 * 4, 0.25f);
  const BevPredictionResult r = predict_bev(byo, p);
  ASSERT_EQ(r.bev.size(), 1u);
  EXPECT_EQ(r.views_brought, std::vector<int>{0});
  for (const float x : r.bev[0].probabilities) EXPECT_EQ(x, 0.25f);
  // No annotation, no BEV: a warning.
  Scan bare = scan;
  bare.views[0].column_semantics.clear();
  const BevPredictionResult none = predict_bev(bare, p);
  EXPECT_TRUE(none.bev.empty());
  EXPECT_FALSE(none.warnings.empty());
}

FloorPlan test_floor() {
  FloorPlan p;
  auto wall = [](const char* id, double ax, double ay, double bx, double by) {
    Wall w;
    w.id = id;
    w.a_m = {ax, ay};
    w.b_m = {bx, by};
    w.thickness_m = 0.15;
    return w;
  };
  p.walls = {wall("s", 0, 0, 12, 0), wall("e", 12, 0, 12, 8), wall("n", 12, 8, 0, 8), wall("w", 0, 8, 0, 0),
             wall("m1", 5, 0, 5, 5), wall("m2", 5, 5, 12, 5), wall("m3", 8.5, 5, 8.5, 8), wall("r1", 0, 3, 3, 3),
             wall("diag", 1.0, 5.0, 3.0, 7.0), wall("stub", 9.5, 0, 9.5, 1.8)};
  p.doors = {{"d1", "m1", {5.0, 2.0}, 0.9, false}, {"d2", "m2", {7.0, 5.0}, 1.0, false}, {"d3", "m3", {8.5, 6.5}, 0.9, true}};
  p.windows = {{"w1", "n", {3.0, 8.0}, 1.2, 0.9, 2.1}, {"w2", "s", {7.5, 0.0}, 1.5, 0.9, 2.1}};
  return p;
}

// Simulated scan -> column semantics -> perfect predictor -> BEV matcher: exactly the true cell
// and orientation (full scan), within a cell (one 60 deg perspective view of a distinctive room).
TEST(BevPredictor, PerfectPredictorLocalisesExactly) {
  const FloorPlan plan = test_floor();
  const RayScene scene(extrude_plan(plan));
  BevMatcherParams mp;
  mp.blocking.open_doors_block = false;  // the scan keeps the plan's open doors open
  const BevMatcher matcher(plan, mp);
  const GridSpec& g = matcher.grid();
  ObservationParams op;
  op.bev.enabled = true;
  op.bev.preset = "perfect";
  op.bev.error = bev_error_preset("perfect");
  SimulationOptions so;
  so.column_semantics = true;
  for (const auto& [x, y, k] : {std::tuple<double, double, int>{3.23, 1.61, 4}, {10.31, 3.07, 25}, {6.72, 6.83, 33}}) {
    int row = 0, col = 0;
    ASSERT_TRUE(g.world_to_cell({x, y}, row, col));
    const Vec2 c = g.cell_center_m(row, col);
    const Pose2 truth{c.x(), c.y(), 2.0 * kPi * k / 36.0};
    for (const ScanSetting setting : {ScanSetting::kFull, ScanSetting::kSingle}) {
      ScanParams sp = scan_preset("phone");
      sp.sensor = scan_preset("perfect").sensor;
      sp.setting = setting;
      const SimulatedScan scan = simulate_scan(scene, truth, sp, so);
      ASSERT_EQ(scan.scan.views.front().column_semantics.size(), static_cast<std::size_t>(sp.geometry.width_px));
      const ObservationResult obs = observe_scan(scan.scan, op);
      ASSERT_EQ(obs.observation.bev.size(), 2u);
      const MatchResult r = matcher.match(obs.observation, MatchRequest::modes(1));
      ASSERT_TRUE(r.has_pose());
      const double err = std::hypot(r.estimate().x_m - truth.x_m, r.estimate().y_m - truth.y_m);
      if (setting == ScanSetting::kFull) {
        EXPECT_EQ(r.estimate().row, row) << x << ", " << y;
        EXPECT_EQ(r.estimate().col, col) << x << ", " << y;
        EXPECT_EQ(r.estimate().slice, k) << x << ", " << y;
      } else {
        EXPECT_LE(err, 0.15) << x << ", " << y << " single view";
        EXPECT_LE(angle_distance_rad(r.estimate().yaw_rad, truth.yaw_rad), deg_to_rad(10.0)) << x << ", " << y;
      }
    }
  }
}

}  // namespace
}  // namespace floorcast

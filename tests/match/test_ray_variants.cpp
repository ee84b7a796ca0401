// The ray matcher's paper-faithful variants (RayMatcherParams: cast_point, distances, ray_convention,
// fov_deg, clip_observation, cells): defaults unchanged, each variant's arithmetic against a known
// answer or a slow version. F3Loc's own arithmetic end to end: test_f3loc_reference.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "floorcast/core/hash.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/core/random.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/match/plan_raster.hpp"
#include "floorcast/match/ray_matcher.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "match_test_plans.hpp"

namespace floorcast {
namespace {

/// Seeded perfect observations (num_rays rays) at valid poses of the plan (random yaw).
std::vector<std::pair<Pose2, Observation2D>> seeded_observations(const FloorPlan& plan, const GridSpec& grid,
                                                                 int num_rays, double range_m, int count,
                                                                 std::uint64_t seed) {
  PerfectObservationParams op;
  op.num_rays = num_rays;
  op.max_range_m = range_m;
  const PerfectObserver observer(plan, op);
  const cv::Mat valid = matcher_valid_mask(plan, grid, closed_door_map());
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> ur(0, grid.height_px - 1), uc(0, grid.width_px - 1);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::vector<std::pair<Pose2, Observation2D>> out;
  while (static_cast<int>(out.size()) < count) {
    const int r = ur(rng), c = uc(rng);
    if (!valid.at<std::uint8_t>(r, c)) continue;
    const Pose2 pose{grid.origin_x_m + (c + u01(rng)) * grid.resolution_m_per_px,
                     grid.origin_y_m + (r + u01(rng)) * grid.resolution_m_per_px, 2.0 * kPi * u01(rng)};
    out.emplace_back(pose, observer.observe(pose));
  }
  return out;
}

std::uint64_t volume_hash(const DistanceVolume& v) {
  std::uint64_t h = fnv1a64(std::string(reinterpret_cast<const char*>(v.cells.data()), v.cells.size() * 4));
  h ^= mix64(fnv1a64(std::string(reinterpret_cast<const char*>(v.mm.data()), v.mm.size() * 2)));
  return h;
}

// The new keys at their defaults change nothing, and the defaults are what they were before the
// variants existed: the volume bytes and the modes of seeded observations are pinned by hashes
// computed with the same code linked against main 25bdd7e's libraries (before the variants); the
// volume's re-pinned when the rasterizer stopped losing walls whose axis fell between two cells'
// boxes (Raster.AWallBetweenTwoCellsBoxesIsPainted; the modes did not change).
TEST(RayVariants, DefaultsUnchanged) {
  const FloorPlan plan = test::asymmetric_floor();
  RayMatcherParams explicit_defaults;
  explicit_defaults.apply_overrides({{"cast_point", "centre"}, {"distances", "exact"}, {"ray_convention", "floorcast"},
                                     {"fov_deg", 360.0}, {"clip_observation", true}, {"cells", "valid"}});
  const RayMatcher a(plan, RayMatcherParams{});
  const RayMatcher b(plan, explicit_defaults);
  EXPECT_EQ(volume_hash(a.volume()), volume_hash(b.volume()));
  EXPECT_EQ(a.volume().sample_offset, 0.5);
  std::uint64_t modes_hash = 0;
  for (const auto& [pose, obs] : seeded_observations(plan, a.grid(), 36, 10.0, 20, 7)) {
    const MatchResult ra = a.match(obs, MatchRequest::modes(3));
    const MatchResult rb = b.match(obs, MatchRequest::modes(3));
    ASSERT_EQ(ra.modes.size(), rb.modes.size());
    for (std::size_t i = 0; i < ra.modes.size(); ++i) {
      EXPECT_EQ(ra.modes[i].x_m, rb.modes[i].x_m);
      EXPECT_EQ(ra.modes[i].y_m, rb.modes[i].y_m);
      EXPECT_EQ(ra.modes[i].score, rb.modes[i].score);
      EXPECT_EQ(ra.modes[i].slice, rb.modes[i].slice);
      modes_hash = mix64(modes_hash ^ static_cast<std::uint64_t>(ra.modes[i].row * 100000 + ra.modes[i].col * 100 +
                                                                 ra.modes[i].slice));
    }
  }
  EXPECT_EQ(hex64(volume_hash(a.volume())), "6353f30fa4c44eac");
  EXPECT_EQ(hex64(modes_hash), "0e9b562fac733d71");
}

// F3Loc's localize() used correctly (rays left to right, heading where its flip puts it) is
// floorcast's comparison re-indexed: the same modes and scores bit for bit, at 36 and 180 rays,
// over 360 deg and over F3Loc's +-50 deg.
TEST(RayVariants, F3LocConventionEqualsFloorcast) {
  const FloorPlan plan = test::asymmetric_floor();
  for (int D : {36, 180}) {
    for (double fov : {360.0, 100.0}) {
      RayMatcherParams p;
      p.num_directions = D;
      p.fov_deg = fov;
      const RayMatcher ours(plan, p);
      p.ray_convention = RayConvention::kF3Loc;
      const RayMatcher f3loc(ours, p);
      for (const auto& [pose, obs] : seeded_observations(plan, ours.grid(), D, 10.0, 6, 11)) {
        const RayMatcher::ComparedRays a = ours.compared_rays(obs), b = f3loc.compared_rays(obs);
        ASSERT_EQ(a.offset.size(), b.offset.size());
        EXPECT_EQ(static_cast<int>(a.offset.size()), fov == 360.0 ? D : 2 * static_cast<int>(50.0 / (360.0 / D)) + 1);
        // Same (offset, range) pairs, in another order.
        std::vector<std::pair<int, double>> pa, pb;
        for (std::size_t i = 0; i < a.offset.size(); ++i) pa.emplace_back(a.offset[i], a.range_m[i]);
        for (std::size_t i = 0; i < b.offset.size(); ++i) pb.emplace_back(b.offset[i], b.range_m[i]);
        std::sort(pa.begin(), pa.end());
        std::sort(pb.begin(), pb.end());
        EXPECT_EQ(pa, pb) << "D " << D << " fov " << fov;
        const MatchResult ra = ours.match(obs), rb = f3loc.match(obs);
        for (std::size_t o = 0; o < ra.posterior.scores.size(); ++o)
          EXPECT_EQ(cv::norm(ra.posterior.scores[o], rb.posterior.scores[o], cv::NORM_INF), 0.0);
        ASSERT_FALSE(ra.modes.empty());
        EXPECT_EQ(ra.modes[0].row, rb.modes[0].row);
        EXPECT_EQ(ra.modes[0].col, rb.modes[0].col);
        EXPECT_EQ(ra.modes[0].slice, rb.modes[0].slice);
      }
    }
  }
}

// The wrong conventions, as a re-implementation slips into them (36 rays over 360 deg, V = D):
// one_bin_off reports every heading one bin (10 deg) off, heading_ray0 V//2 + 1 bins off (190
// deg), both at the right cell with the right score; mirrored compares the ray at +a with the
// direction at -a. The field of view narrows the compared rays to F3Loc's 11.
TEST(RayVariants, WrongConventionsKnownAnswers) {
  const FloorPlan plan = test::asymmetric_floor();
  const RayMatcher ours(plan, RayMatcherParams{});
  const int D = 36;
  auto with = [&](RayConvention c, double fov = 360.0) {
    RayMatcherParams p;
    p.ray_convention = c;
    p.fov_deg = fov;
    return RayMatcher(ours, p);
  };
  const RayMatcher one_bin = with(RayConvention::kOneBinOff), ray0 = with(RayConvention::kHeadingRay0),
                   mirrored = with(RayConvention::kMirrored), fov = with(RayConvention::kF3Loc, 100.0),
                   fov_one_bin = with(RayConvention::kOneBinOff, 100.0);
  for (const auto& [pose, obs] : seeded_observations(plan, ours.grid(), D, 10.0, 8, 3)) {
    const std::vector<double> r = ours.observation_rays(obs);
    const MatchResult a = ours.match(obs);
    const MatchResult b = one_bin.match(obs);
    const MatchResult c = ray0.match(obs);
    ASSERT_FALSE(a.modes.empty());
    // The same scores, relabelled: slice o of the wrong convention is slice o - shift of ours.
    for (int o = 0; o < D; ++o) {
      EXPECT_EQ(cv::norm(b.posterior.scores[static_cast<std::size_t>((o + 1) % D)], a.posterior.scores[static_cast<std::size_t>(o)],
                         cv::NORM_INF), 0.0);
      EXPECT_EQ(cv::norm(c.posterior.scores[static_cast<std::size_t>((o + D / 2 + 1) % D)],
                         a.posterior.scores[static_cast<std::size_t>(o)], cv::NORM_INF),
                0.0);
    }
    const RayMatcher::ComparedRays m = mirrored.compared_rays(obs);
    ASSERT_EQ(static_cast<int>(m.offset.size()), D);
    for (std::size_t j = 0; j < m.offset.size(); ++j)
      EXPECT_EQ(m.range_m[j], r[static_cast<std::size_t>((D - m.offset[j]) % D)]) << "offset " << m.offset[j];
    const RayMatcher::ComparedRays f = fov.compared_rays(obs);
    ASSERT_EQ(f.offset.size(), 11u);
    for (std::size_t j = 0; j < f.offset.size(); ++j) {
      const int signed_offset = f.offset[j] <= D / 2 ? f.offset[j] : f.offset[j] - D;
      EXPECT_LE(std::abs(signed_offset), 5);
      EXPECT_EQ(f.range_m[j], r[static_cast<std::size_t>(f.offset[j])]);
    }
    // With an odd number of rays (F3Loc's 11) the heading index V//2 is right: no bin off.
    const RayMatcher::ComparedRays f1 = fov_one_bin.compared_rays(obs);
    EXPECT_EQ(f1.offset, f.offset);
    EXPECT_EQ(f1.range_m, f.range_m);
  }
}

// A field of view narrower than 360 deg is searched exhaustively: modes equal the posterior's.
TEST(RayVariants, FieldOfViewModesEqualPosterior) {
  const FloorPlan plan = test::asymmetric_floor();
  RayMatcherParams p;
  p.fov_deg = 100.0;
  const RayMatcher m(plan, p);
  for (const auto& [pose, obs] : seeded_observations(plan, m.grid(), 36, 10.0, 6, 5)) {
    const MatchResult full = m.match(obs, MatchRequest{MatchOutput::kPosterior, 4, 1.0, kPi / 6});
    const MatchResult modes = m.match(obs, MatchRequest::modes(4));
    ASSERT_EQ(full.modes.size(), modes.modes.size());
    for (std::size_t i = 0; i < full.modes.size(); ++i) {
      EXPECT_EQ(full.modes[i].row, modes.modes[i].row);
      EXPECT_EQ(full.modes[i].col, modes.modes[i].col);
      EXPECT_EQ(full.modes[i].slice, modes.modes[i].slice);
      EXPECT_EQ(full.modes[i].score, modes.modes[i].score);
    }
  }
}

// Cast from each cell's corner: the distances are the brute-force caster's from the corner, and
// poses are reported at the corner, by both output paths.
TEST(RayVariants, CornerCastPoint) {
  const FloorPlan plan = test::asymmetric_floor();
  RayMatcherParams p;
  p.cast_point = RayCastPoint::kCorner;
  const RayMatcher m(plan, p);
  const DistanceVolume& v = m.volume();
  EXPECT_EQ(v.sample_offset, 0.0);
  const std::vector<Segment2> outline = outline_segments(blocking_outline(plan, p.blocking));
  std::mt19937_64 rng(2);
  int checked = 0;
  for (int k = 0; k < 400; ++k) {
    const std::size_t i = rng() % v.num_cells();
    const int d = static_cast<int>(rng() % 36);
    const int lin = v.cells[i];
    const Vec2 corner = volume_cast_point(v, lin / v.grid.width_px, lin % v.grid.width_px);
    EXPECT_NEAR(corner.x(), v.grid.origin_x_m + (lin % v.grid.width_px) * 0.1, 1e-12);
    const double ang = 2.0 * kPi * d / 36;
    const double expected = brute_force_ray_distance(outline, corner, ang, 10.0);
    // A corner lying exactly on a wall face (faces on grid lines) sees through the face's back
    // side in the z-buffer and 0 m in the either-side brute force: a degenerate cast point.
    if (expected < 1e-9) continue;
    // Rays grazing a wall end may fall on either side (as in DistanceVolume.EqualsBruteForceCaster).
    if (std::abs(v.range_m(i, d) - expected) > 1e-3) {
      bool grazes = false;
      const Vec2 u(std::cos(ang), std::sin(ang));
      for (const Segment2& s : outline)
        for (const Vec2& e : {s.a_m, s.b_m}) {
          const Vec2 w = e - corner;
          if (w.dot(u) > -1e-6 && std::abs(u.x() * w.y() - u.y() * w.x()) < 1e-6) grazes = true;
        }
      EXPECT_TRUE(grazes) << "cell " << i << " direction " << d << ": " << v.range_m(i, d) << " vs " << expected;
    }
    ++checked;
  }
  EXPECT_GT(checked, 300);
  for (const auto& [pose, obs] : seeded_observations(plan, m.grid(), 36, 10.0, 4, 9)) {
    const MatchResult full = m.match(obs);
    const MatchResult modes = m.match(obs, MatchRequest::modes(1));
    ASSERT_FALSE(full.modes.empty());
    const Vec2 corner = volume_cast_point(v, full.modes[0].row, full.modes[0].col);
    EXPECT_EQ(full.modes[0].x_m, corner.x());
    EXPECT_EQ(full.modes[0].y_m, corner.y());
    EXPECT_EQ(modes.modes[0].x_m, corner.x());
    EXPECT_EQ(modes.modes[0].y_m, corner.y());
  }
}

// Every cell of the grid scored: the volume stores all of them; a cast point inside a wall sees
// 0 m everywhere; the valid cells keep their distances.
TEST(RayVariants, AllCells) {
  const FloorPlan plan = test::asymmetric_floor();
  const RayMatcher valid(plan, RayMatcherParams{});
  RayMatcherParams p;
  p.cells = RayCells::kAll;
  const RayMatcher all(plan, p);
  const DistanceVolume& va = all.volume();
  const DistanceVolume& vv = valid.volume();
  EXPECT_EQ(va.num_cells(), static_cast<std::size_t>(va.grid.width_px) * va.grid.height_px);
  const cv::Mat occ = rasterize_occupancy(plan, va.grid, p.blocking);
  int inside_walls = 0;
  for (std::size_t i = 0; i < va.num_cells(); ++i) {
    const int lin = va.cells[i];
    if (occ.data[lin]) {
      ++inside_walls;
      for (int d = 0; d < 36; ++d) EXPECT_EQ(va.units(i, d), 0);
    }
    const int j = vv.cell_index[static_cast<std::size_t>(lin)];
    if (j < 0) continue;
    for (int d = 0; d < 36; ++d) EXPECT_EQ(va.units(i, d), vv.units(static_cast<std::size_t>(j), d));
  }
  EXPECT_GT(inside_walls, 100);
}

// Unclipped observation rays (F3Loc's evaluation): rays beyond the volume's range count in full
// against the clipped volume; the bounded search still finds the exhaustive modes.
TEST(RayVariants, ObservationUnclipped) {
  const FloorPlan plan = test::asymmetric_floor();
  RayMatcherParams p;
  p.max_range_m = 4.0;
  p.clip_observation = false;
  const RayMatcher m(plan, p);
  RayMatcherParams pe = p;
  pe.search = RaySearch::kExhaustive;
  const RayMatcher ex(m, pe);
  for (const auto& [pose, obs] : seeded_observations(plan, m.grid(), 36, 10.0, 6, 13)) {
    const RayMatcher::ComparedRays cr = m.compared_rays(obs);
    double longest = 0.0;
    for (double x : cr.range_m) longest = std::max(longest, x);
    const MatchResult full = m.match(obs);
    ASSERT_FALSE(full.modes.empty());
    const PoseHypothesis& h = full.modes[0];
    const std::size_t cell = static_cast<std::size_t>(m.volume().cell_index[static_cast<std::size_t>(h.row * m.grid().width_px + h.col)]);
    // Slow L1: the volume's (clipped) distances against the raw rays.
    double l1 = 0.0;
    for (int i = 0; i < 36; ++i)
      l1 += std::abs(m.volume().range_m(cell, (h.slice + i) % 36) - std::round(cr.range_m[static_cast<std::size_t>(i)] * 1000.0) / 1000.0);
    EXPECT_NEAR(h.score, std::exp(-l1 / 40.0), 2e-6 * std::exp(-l1 / 40.0));
    const MatchResult a = m.match(obs, MatchRequest::modes(3)), b = ex.match(obs, MatchRequest::modes(3));
    ASSERT_EQ(a.modes.size(), b.modes.size());
    for (std::size_t i = 0; i < a.modes.size(); ++i) {
      EXPECT_EQ(a.modes[i].row, b.modes[i].row);
      EXPECT_EQ(a.modes[i].col, b.modes[i].col);
      EXPECT_EQ(a.modes[i].slice, b.modes[i].slice);
      EXPECT_EQ(a.modes[i].score, b.modes[i].score);
    }
    if (longest > 4.0) {
      RayMatcherParams pc = p;
      pc.clip_observation = true;
      const RayMatcher clipped(m, pc);
      EXPECT_NE(clipped.match(obs).modes[0].score, h.score);
    }
  }
}

// Raster distances (F3Loc's march through a 0.01 m occupancy image) agree with the exact ones
// to about the fine pixel wherever the ray does not graze a wall end or door edge; cast from
// corners, as F3Loc, too.
TEST(RayVariants, RasterDistancesNearExact) {
  const FloorPlan plan = test::asymmetric_floor();
  for (RayCastPoint cp : {RayCastPoint::kCentre, RayCastPoint::kCorner}) {
    RayMatcherParams pe;
    pe.cast_point = cp;
    pe.cells = RayCells::kAll;
    RayMatcherParams pr = pe;
    pr.distances = RayDistances::kRaster;
    const RayMatcher exact(plan, pe), raster(plan, pr);
    const DistanceVolume& a = exact.volume();
    const DistanceVolume& b = raster.volume();
    ASSERT_EQ(a.cells, b.cells);
    const cv::Mat valid = matcher_valid_mask(plan, a.grid, pe.blocking);
    std::size_t n = 0, close = 0;
    for (std::size_t i = 0; i < a.num_cells(); ++i) {
      if (!valid.data[static_cast<std::size_t>(a.cells[i])]) continue;
      for (int d = 0; d < 36; ++d) {
        ++n;
        // Up to one fine pixel along the ray (about 0.01 m / min(|cos|, |sin|) at shallow angles).
        if (std::abs(a.range_m(i, d) - b.range_m(i, d)) <= 0.03) ++close;
      }
    }
    EXPECT_GT(static_cast<double>(close) / static_cast<double>(n), 0.97) << close << " of " << n;
  }
}

}  // namespace
}  // namespace floorcast

// WGS84 local tangent plane against hand-computed distances.
#include <gtest/gtest.h>

#include <cmath>

#include "floorcast/floorplans/import.hpp"

namespace floorcast {
namespace {

constexpr double kLat0 = 47.3769, kLon0 = 8.5417;
constexpr double kDeg = M_PI / 180.0;

TEST(LocalTangentPlane, RadiiOfCurvatureMatchHandComputedValues) {
  // WGS84 a = 6378137, f = 1/298.257223563; at 47.3769 deg:
  // M = a (1 - e^2) / (1 - e^2 sin^2)^1.5 = 6370041.068 m, N = a / sqrt(1 - e^2 sin^2) = 6389727.571 m.
  EXPECT_NEAR(LocalTangentPlane::meridian_radius_m(kLat0), 6370041.068, 1e-3);
  EXPECT_NEAR(LocalTangentPlane::prime_vertical_radius_m(kLat0), 6389727.571, 1e-3);
  // Equator and pole: M(0) = a (1 - e^2), N(0) = a; M(90) = N(90) = a / sqrt(1 - e^2).
  const double e2 = (1.0 / 298.257223563) * (2.0 - 1.0 / 298.257223563);
  EXPECT_NEAR(LocalTangentPlane::meridian_radius_m(0.0), 6378137.0 * (1.0 - e2), 1e-6);
  EXPECT_NEAR(LocalTangentPlane::prime_vertical_radius_m(0.0), 6378137.0, 1e-6);
  EXPECT_NEAR(LocalTangentPlane::meridian_radius_m(90.0), 6378137.0 / std::sqrt(1.0 - e2), 1e-6);
}

TEST(LocalTangentPlane, ProjectsOffsetsToHandComputedDistances) {
  const LocalTangentPlane ltp(kLat0, kLon0);
  EXPECT_NEAR(ltp.to_local_m(kLat0, kLon0).norm(), 0.0, 1e-9);
  // 0.001 deg north: the meridian arc M(mid-latitude) * dphi = 111.1782 m.
  const Vec2 north = ltp.to_local_m(kLat0 + 0.001, kLon0);
  EXPECT_NEAR(north.x(), 0.0, 1e-6);
  EXPECT_NEAR(north.y(), 111.17820, 1e-3);
  // 0.001 deg east: the parallel's radius N cos(phi) * dlambda = 75.5195 m.
  const Vec2 east = ltp.to_local_m(kLat0, kLon0 + 0.001);
  EXPECT_NEAR(east.x(), 75.51951, 1e-3);
  EXPECT_NEAR(east.y(), 0.0, 1e-3);  // the parallel curves away from the tangent plane by ~0.4 mm
  // A diagonal 100 m: Pythagoras on the local radii.
  const double dphi = 60.0 / LocalTangentPlane::meridian_radius_m(kLat0) / kDeg;
  const double dlam = 80.0 / (LocalTangentPlane::prime_vertical_radius_m(kLat0) * std::cos(kLat0 * kDeg)) / kDeg;
  const Vec2 diag = ltp.to_local_m(kLat0 + dphi, kLon0 + dlam);
  EXPECT_NEAR(diag.norm(), 100.0, 2e-3);
  EXPECT_NEAR(std::atan2(diag.y(), diag.x()), std::atan2(60.0, 80.0), 1e-5);
  // South-west is the mirror image.
  const Vec2 sw = ltp.to_local_m(kLat0 - dphi, kLon0 - dlam);
  EXPECT_NEAR((diag + sw).norm(), 0.0, 2e-3);
}

TEST(OsmLevels, ParsesSingleValuesListsAndRanges) {
  std::vector<std::pair<double, double>> r;
  ASSERT_TRUE(parse_osm_levels("0", r));
  EXPECT_EQ(r, (std::vector<std::pair<double, double>>{{0, 0}}));
  ASSERT_TRUE(parse_osm_levels("-1", r));
  EXPECT_EQ(r, (std::vector<std::pair<double, double>>{{-1, -1}}));
  ASSERT_TRUE(parse_osm_levels("1;2", r));
  EXPECT_EQ(r, (std::vector<std::pair<double, double>>{{1, 1}, {2, 2}}));
  ASSERT_TRUE(parse_osm_levels("0-2", r));
  EXPECT_EQ(r, (std::vector<std::pair<double, double>>{{0, 2}}));
  ASSERT_TRUE(parse_osm_levels("-3--1", r));
  EXPECT_EQ(r, (std::vector<std::pair<double, double>>{{-3, -1}}));
  ASSERT_TRUE(parse_osm_levels("-1-1", r));
  EXPECT_EQ(r, (std::vector<std::pair<double, double>>{{-1, 1}}));
  ASSERT_TRUE(parse_osm_levels("0.5", r));
  EXPECT_EQ(r, (std::vector<std::pair<double, double>>{{0.5, 0.5}}));
  ASSERT_TRUE(parse_osm_levels(" -4 ; 0;4-5 ", r));
  EXPECT_EQ(r, (std::vector<std::pair<double, double>>{{-4, -4}, {0, 0}, {4, 5}}));
  for (const char* bad : {"", "a", "1;", ";1", "1--", "1-2-3", "ground", "1e3", "nan", "0x10"}) {
    EXPECT_FALSE(parse_osm_levels(bad, r)) << bad;
  }
}

}  // namespace
}  // namespace floorcast

// Coordinates of geographic sources (GeoFrame, through PROJ) against hand-computed distances; OSM
// level values.
#include <gtest/gtest.h>

#include <cmath>

#include "floorcast/floorplans/import.hpp"
#include "import_test_util.hpp"

namespace floorcast {
namespace {

constexpr double kLat0 = 47.3769, kLon0 = 8.5417;
constexpr double kDeg = M_PI / 180.0;

TEST(GeoFrame, ReferenceRadiiOfCurvatureMatchHandComputedValues) {
  // WGS84 a = 6378137, f = 1/298.257223563; at 47.3769 deg:
  // M = a (1 - e^2) / (1 - e^2 sin^2)^1.5 = 6370041.068 m, N = a / sqrt(1 - e^2 sin^2) = 6389727.571 m.
  EXPECT_NEAR(test::meridian_radius_m(kLat0), 6370041.068, 1e-3);
  EXPECT_NEAR(test::prime_vertical_radius_m(kLat0), 6389727.571, 1e-3);
  // Equator and pole: M(0) = a (1 - e^2), N(0) = a; M(90) = N(90) = a / sqrt(1 - e^2).
  const double e2 = (1.0 / 298.257223563) * (2.0 - 1.0 / 298.257223563);
  EXPECT_NEAR(test::meridian_radius_m(0.0), 6378137.0 * (1.0 - e2), 1e-6);
  EXPECT_NEAR(test::prime_vertical_radius_m(0.0), 6378137.0, 1e-6);
  EXPECT_NEAR(test::meridian_radius_m(90.0), 6378137.0 / std::sqrt(1.0 - e2), 1e-6);
}

// WGS84 (the default): PROJ's geodetic -> geocentric -> topocentric plane against hand-computed
// meridian and parallel arcs.
TEST(GeoFrame, ProjectsWgs84OffsetsToHandComputedDistances) {
  GeoFrame frame;
  EXPECT_TRUE(frame.geographic());
  frame.set_origin_deg({kLon0, kLat0});
  EXPECT_NEAR(frame.to_local_m({kLon0, kLat0}).norm(), 0.0, 1e-9);
  // 0.001 deg north: the meridian arc M(mid-latitude) * dphi = 111.1782 m.
  const Vec2 north = frame.to_local_m({kLon0, kLat0 + 0.001});
  EXPECT_NEAR(north.x(), 0.0, 1e-6);
  EXPECT_NEAR(north.y(), 111.17820, 1e-3);
  // 0.001 deg east: the parallel's radius N cos(phi) * dlambda = 75.5195 m.
  const Vec2 east = frame.to_local_m({kLon0 + 0.001, kLat0});
  EXPECT_NEAR(east.x(), 75.51951, 1e-3);
  EXPECT_NEAR(east.y(), 0.0, 1e-3);  // the parallel curves away from the tangent plane by ~0.4 mm
  // A diagonal 100 m: Pythagoras on the local radii.
  const double dphi = 60.0 / test::meridian_radius_m(kLat0) / kDeg;
  const double dlam = 80.0 / (test::prime_vertical_radius_m(kLat0) * std::cos(kLat0 * kDeg)) / kDeg;
  const Vec2 diag = frame.to_local_m({kLon0 + dlam, kLat0 + dphi});
  EXPECT_NEAR(diag.norm(), 100.0, 2e-3);
  EXPECT_NEAR(std::atan2(diag.y(), diag.x()), std::atan2(60.0, 80.0), 1e-5);
  // South-west is the mirror image.
  const Vec2 sw = frame.to_local_m({kLon0 - dlam, kLat0 - dphi});
  EXPECT_NEAR((diag + sw).norm(), 0.0, 2e-3);
  // Positions outside longitude/latitude are refused, with the hint when they look like metres.
  test::expect_input_error([&] { frame.to_geographic_deg({465000.0, 5247000.0}, "f.geojson: features[3]"); },
                           {"f.geojson: features[3]", "look like metres", "--crs EPSG:NNNN"});
}

// A projected source (UTM zone 32N): PROJ inverts the projection onto WGS84 longitude/latitude.
// Reference: the zone's central meridian 9 deg E on the equator is (500000, 0); 1 deg of
// longitude west of it at 47.3769 N lies ~75.5 km west (less the 0.9996 scale).
TEST(GeoFrame, ConvertsProjectedPositionsToLongitudeLatitude) {
  const GeoFrame utm("EPSG:32632", "test");
  EXPECT_FALSE(utm.geographic());
  EXPECT_NE(utm.description().find("UTM zone 32N"), std::string::npos) << utm.description();
  const Vec2 origin = utm.to_geographic_deg({500000.0, 0.0}, "test");
  EXPECT_NEAR(origin.x(), 9.0, 1e-9);
  EXPECT_NEAR(origin.y(), 0.0, 1e-9);
  // The same point written as easting/northing and as longitude/latitude lands on the same local
  // metres, and a 100 m step of easting near the central meridian is 100 m / 0.9996 on the ground.
  GeoFrame geo;
  const Vec2 a = utm.to_geographic_deg({500000.0, 5247000.0}, "a"), b = utm.to_geographic_deg({500100.0, 5247000.0}, "b");
  geo.set_origin_deg(a);
  EXPECT_NEAR(geo.to_local_m(b).norm(), 100.0 / 0.9996, 2e-3);
  test::expect_input_error([] { GeoFrame("EPSG:999999", "f.geojson"); }, {"f.geojson", "EPSG:999999", "not one PROJ knows"});
  test::expect_input_error([] { GeoFrame("EPSG:4978", "f.geojson"); }, {"neither geographic nor projected"});
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

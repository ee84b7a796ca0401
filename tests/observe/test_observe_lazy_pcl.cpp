// The observation module loads PCL only when a stage needs it: a process linking observe maps no
// PCL library until the first ground-plane or plane extraction, which then works through the
// module (known answer: a flat floor at z = -1.4 m is found within 1 cm).
#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <string>

#include "floorcast/observe/observation_module.hpp"
#include "floorcast/observe/observe_planes.hpp"

namespace floorcast {
namespace {

bool maps_pcl() {
  std::ifstream maps("/proc/self/maps");
  std::string line;
  while (std::getline(maps, line))
    if (line.find("libpcl_") != std::string::npos) return true;
  return false;
}

TEST(ObserveLazyPcl, PclIsMappedOnlyOnFirstUse) {
  ASSERT_FALSE(maps_pcl()) << "PCL is mapped before any observation stage ran";
  PointCloud3f cloud;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  std::normal_distribution<float> noise(0.0f, 0.005f);
  for (int i = 0; i < 3000; ++i) cloud.emplace_back(u(rng), u(rng), -1.4f + noise(rng));  // floor
  for (int i = 0; i < 3000; ++i) cloud.emplace_back(2.0f + noise(rng), u(rng), -1.4f + 1.2f + u(rng) * 0.6f);  // wall
  const GroundPlaneResult ground = detect_ground_plane(cloud, GroundPlaneParams{});
  ASSERT_TRUE(ground.found) << ground.reason;
  EXPECT_NEAR(ground.height_m, -1.4, 0.01);
  EXPECT_TRUE(maps_pcl());
  const std::vector<Plane3> planes = extract_planes_region_growing(cloud, PclRegionGrowingParams{});
  ASSERT_GE(planes.size(), 2u);
  EXPECT_GT(std::abs(planes[0].normal.z()) + std::abs(planes[1].normal.z()), 0.99);
}

}  // namespace
}  // namespace floorcast

// The scenario loader: YAML text -> Scenario (every stage's parameters parsed, sweeps expanded).
// Relative plan paths resolve against the source tree (floorplans/buildings/...).
#include "floorcast/scenarios/scenario.hpp"
#include "fuzz_common.hpp"

FLOORCAST_FUZZ_INIT

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return floorcast::fuzz::run([&] {
    (void)floorcast::parse_scenario(floorcast::fuzz::text(data, size), "fuzz.yaml", FLOORCAST_SOURCE_DIR,
                                    FLOORCAST_SOURCE_DIR);
  });
}

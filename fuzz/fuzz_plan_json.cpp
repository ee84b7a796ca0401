// The native plan loader: JSON text -> validated FloorPlan (parse_floor_plan_json).
#include "floorcast/floorplans/io.hpp"
#include "fuzz_common.hpp"

FLOORCAST_FUZZ_INIT

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return floorcast::fuzz::run([&] {
    const floorcast::FloorPlan plan = floorcast::parse_floor_plan_json(floorcast::fuzz::text(data, size), "fuzz.json");
    (void)floorcast::floor_plan_to_json(plan);  // what was accepted can be written back
  });
}

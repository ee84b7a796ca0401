// Observation files: JSON text -> ObservationRecord, and the record written back.
#include "floorcast/core/observation_io.hpp"
#include "fuzz_common.hpp"

FLOORCAST_FUZZ_INIT

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return floorcast::fuzz::run([&] {
    const floorcast::ObservationRecord r = floorcast::parse_observation_json(floorcast::fuzz::text(data, size), "fuzz.json");
    (void)floorcast::observation_to_json_text(r);
  });
}

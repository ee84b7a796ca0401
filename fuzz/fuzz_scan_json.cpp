// Scan folders' scan.json: JSON text -> validated view descriptions (images are not read).
#include "floorcast/core/scan_io.hpp"
#include "fuzz_common.hpp"

FLOORCAST_FUZZ_INIT

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return floorcast::fuzz::run(
      [&] { (void)floorcast::parse_scan_description(floorcast::fuzz::text(data, size), "scan.json"); });
}

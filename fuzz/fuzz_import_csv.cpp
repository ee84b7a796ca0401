// The CSV importer (PALMS-style wall segments) with clean-up and validation.
#include "floorcast/floorplans/import.hpp"
#include "fuzz_common.hpp"

FLOORCAST_FUZZ_INIT

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return floorcast::fuzz::run([&] { (void)floorcast::import_csv_text(floorcast::fuzz::text(data, size), "fuzz.csv"); });
}

// The OSM importer (indoor=* ways, doors, levels) with clean-up and validation.
#include "floorcast/floorplans/import.hpp"
#include "fuzz_common.hpp"

FLOORCAST_FUZZ_INIT

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return floorcast::fuzz::run([&] { (void)floorcast::import_osm_xml(floorcast::fuzz::text(data, size), "fuzz.osm"); });
}

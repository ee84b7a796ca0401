// The IMDF importer: one input holds level.geojson, unit.geojson and opening.geojson separated by
// lines "\n#unit\n" and "\n#opening\n" (the seed corpus is written that way by scripts/fuzz.sh).
#include "floorcast/floorplans/import.hpp"
#include "fuzz_common.hpp"

FLOORCAST_FUZZ_INIT

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string all = floorcast::fuzz::text(data, size);
  const auto u = all.find("\n#unit\n");
  const auto o = all.find("\n#opening\n", u == std::string::npos ? 0 : u);
  const std::string level = all.substr(0, u);
  const std::string unit = u == std::string::npos ? std::string() : all.substr(u + 7, o == std::string::npos ? std::string::npos : o - u - 7);
  const std::string opening = o == std::string::npos ? std::string() : all.substr(o + 10);
  return floorcast::fuzz::run([&] { (void)floorcast::import_imdf_texts(level, unit, opening, "fuzz.imdf"); });
}

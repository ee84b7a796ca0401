// The PNG importer: image bytes -> decode (header size checked first) -> wall extraction.
#include "floorcast/core/image_io.hpp"
#include "floorcast/floorplans/import.hpp"
#include "fuzz_common.hpp"

FLOORCAST_FUZZ_INIT

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return floorcast::fuzz::run([&] {
    const cv::Mat image = floorcast::decode_image(floorcast::fuzz::text(data, size), "fuzz.png");
    floorcast::ImportOptions options;
    options.resolution_m_per_px = 0.05;
    (void)floorcast::import_png_image(image, "fuzz.png", options);
  });
}

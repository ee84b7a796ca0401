// Shared set-up of the libFuzzer targets: smaller limits (so the fuzzer explores inputs rather
// than spending its time on legitimately large ones) and the one rule every target checks.
//
// A target feeds the input to one entry point. InputError (a clear refusal) is the expected
// outcome for bad input; any other exception escapes, aborts, and libFuzzer records a crash:
// exactly the inputs that would end in "floorcast: internal error". Signals, sanitizer reports,
// timeouts (-timeout) and memory blow-ups (-rss_limit_mb) are findings as well.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "floorcast/core/limits.hpp"
#include "floorcast/core/types.hpp"

namespace floorcast::fuzz {

inline void set_fuzz_limits() {
  InputLimits l = input_limits();
  l.max_file_bytes = 1 << 20;
  l.max_yaml_nodes = 1e5;
  l.max_plan_elements = 2e4;
  l.max_raster_cells = 4e6;
  l.max_raster_bytes = 2.5e8;
  l.max_points = 1e6;
  l.max_segments = 1e4;
  l.max_image_pixels = 4e6;
  l.max_vertices_per_element = 1e4;
  l.max_level_range = 100;
  l.max_sweep_cells = 200;
  l.max_units = 1e5;
  set_input_limits(l);
}

template <class F>
int run(F&& fn) {
  try {
    fn();
  } catch (const InputError&) {
    // A refusal with a message: the expected outcome for bad input.
  }
  return 0;
}

inline std::string text(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

}  // namespace floorcast::fuzz

#define FLOORCAST_FUZZ_INIT                                        \
  extern "C" int LLVMFuzzerInitialize(int*, char***) {             \
    ::floorcast::fuzz::set_fuzz_limits();                          \
    return 0;                                                      \
  }

// A reference workload measured in the same run as the methods, so that timing checks are
// ratios (method time / reference time) rather than absolute seconds on a noisy shared machine.
#pragma once

namespace floorcast {

/// Median wall-clock seconds of a fixed, deterministic CPU workload (forward and inverse 2D DFT
/// of a 1024 x 1024 float image plus a Gaussian blur, single-threaded) over `repeats` runs.
double reference_workload_s(int repeats = 5);

}  // namespace floorcast

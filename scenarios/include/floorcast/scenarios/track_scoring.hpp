// A track against the walk's truth: the one scorer of `floorcast track` and sequential scenarios.
#pragma once

#include <vector>

#include "floorcast/eval/sequential.hpp"
#include "floorcast/sim/walk.hpp"
#include "floorcast/track/run.hpp"

namespace floorcast {

/// Per step of `run` (which started at `first_step`): position and heading error against
/// truth[step], the distance walked since the tracker started, the convergence stage; the mean
/// tracker time per step. The distance counts the steps after first_step only: the step the
/// tracker starts at is its initialisation (its step length is the walking done before the
/// tracker existed), so a track started at the walk's third observation is scored from there,
/// exactly as one started at step 0 is scored from step 0. Throws InputError naming the step when
/// an error, distance or time is not finite (nothing non-finite is scored or written).
SequentialRecord track_record(const TrackRun& run, const std::vector<WalkStep>& truth, int first_step);

}  // namespace floorcast

#include "floorcast/track/run.hpp"

#include <chrono>

namespace floorcast {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

TrackRun run_tracker(Tracker& tracker, const std::vector<OdometryStep>& odometry, int first_step,
                     const std::function<std::optional<PosteriorQuery>(int step)>& posterior_at) {
  TrackRun run;
  if (first_step < 0 || static_cast<std::size_t>(first_step) >= odometry.size()) {
    run.failure = "no odometry at the first observation's step";
    return run;
  }
  const std::optional<PosteriorQuery> first = posterior_at(first_step);
  if (!first) {
    run.failure = "no observation at the first step";
    return run;
  }
  const Posterior& first_posterior = first->full();  // computed here, outside the tracker's time
  const auto t0 = std::chrono::steady_clock::now();
  try {
    tracker.initialise(first_posterior, odometry[static_cast<std::size_t>(first_step)]);
  } catch (const InputError& e) {
    run.failure = e.what();
    return run;
  }
  run.init_s = seconds_since(t0);
  run.started = true;
  TrackRunStep s0;
  s0.step = first_step;
  s0.t_s = odometry[static_cast<std::size_t>(first_step)].t_s;
  s0.estimate = tracker.estimate();
  s0.updated = true;
  s0.time_s = run.init_s;
  run.steps.push_back(s0);
  for (std::size_t k = static_cast<std::size_t>(first_step) + 1; k < odometry.size(); ++k) {
    const std::optional<PosteriorQuery> post = posterior_at(static_cast<int>(k));
    const auto t = std::chrono::steady_clock::now();
    tracker.predict(odometry[k]);
    if (post) tracker.update(*post);
    TrackRunStep s;
    s.step = static_cast<int>(k);
    s.t_s = odometry[k].t_s;
    s.estimate = tracker.estimate();
    s.updated = post.has_value();
    s.time_s = seconds_since(t);
    run.steps.push_back(s);
  }
  return run;
}

}  // namespace floorcast

#include "floorcast/scenarios/track_scoring.hpp"

#include "floorcast/core/math.hpp"

namespace floorcast {

SequentialRecord track_record(const TrackRun& run, const std::vector<WalkStep>& truth, int first_step) {
  SequentialRecord rec;
  rec.failed = !run.started;
  double walked = 0.0, total_s = 0.0;
  for (const TrackRunStep& s : run.steps) {
    const WalkStep& t = truth.at(static_cast<std::size_t>(s.step));
    if (s.step > first_step) walked += t.step_length_m;
    rec.t_s.push_back(s.t_s);
    rec.distance_m.push_back(walked);
    rec.position_error_m.push_back((s.estimate.pose.position_m() - t.T_world_body.position_m()).norm());
    rec.yaw_error_deg.push_back(rad_to_deg(angle_distance_rad(s.estimate.pose.yaw_rad, t.T_world_body.yaw_rad)));
    rec.stage.push_back(s.estimate.stage);
    total_s += s.time_s;
  }
  rec.time_per_step_s = run.steps.empty() ? 0.0 : total_s / static_cast<double>(run.steps.size());
  return rec;
}

}  // namespace floorcast

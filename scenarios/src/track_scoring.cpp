#include "floorcast/scenarios/track_scoring.hpp"

#include <cmath>
#include <sstream>

#include "floorcast/core/math.hpp"

namespace floorcast {

SequentialRecord track_record(const TrackRun& run, const std::vector<WalkStep>& truth, int first_step) {
  SequentialRecord rec;
  rec.failed = !run.started;
  double walked = 0.0, total_s = 0.0;
  for (const TrackRunStep& s : run.steps) {
    const WalkStep& t = truth.at(static_cast<std::size_t>(s.step));
    if (s.step > first_step) walked += t.step_length_m;
    const Pose2& e = s.estimate.pose;
    const double err = (e.position_m() - t.T_world_body.position_m()).norm();
    const double yaw_err = rad_to_deg(angle_distance_rad(e.yaw_rad, t.T_world_body.yaw_rad));
    // Every metric is finite before it is scored or written (a NaN would reach errors.csv and the
    // RMSE as "-nan"): a non-finite estimate or truth is named, not averaged.
    if (!std::isfinite(err) || !std::isfinite(yaw_err) || !std::isfinite(walked) || !std::isfinite(s.t_s)) {
      std::ostringstream os;
      os << "step " << s.step << ": the estimate (" << e.x_m << ", " << e.y_m << ", " << e.yaw_rad << ") or the truth ("
         << t.T_world_body.x_m << ", " << t.T_world_body.y_m << ", " << t.T_world_body.yaw_rad << "), walked " << walked
         << " m at t = " << s.t_s << " s, is not finite; nothing was scored";
      throw InputError(os.str());
    }
    rec.t_s.push_back(s.t_s);
    rec.distance_m.push_back(walked);
    rec.position_error_m.push_back(err);
    rec.yaw_error_deg.push_back(yaw_err);
    rec.stage.push_back(s.estimate.stage);
    total_s += s.time_s;
  }
  rec.time_per_step_s = run.steps.empty() ? 0.0 : total_s / static_cast<double>(run.steps.size());
  return rec;
}

}  // namespace floorcast

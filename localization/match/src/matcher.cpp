#include <stdexcept>

#include "floorcast/match/matcher.hpp"

namespace floorcast {

const PoseHypothesis& MatchResult::estimate() const {
  if (modes.empty()) throw std::logic_error("MatchResult::estimate: no pose (every score is 0)");
  return modes.front();
}

PosteriorQuery Matcher::query(const Observation2D& observation) const { return PosteriorQuery(match(observation).posterior); }

void finish_from_posterior(MatchResult& result, const MatchRequest& request) {
  Posterior& post = result.posterior;
  result.grid = post.grid;
  result.modes = post.top_k(request.top_k, request.mode_separation_m, request.mode_separation_rad);
  if (request.output == MatchOutput::kMaxOverYaw) result.max_over_yaw = post.max_over_yaw();
  if (request.output != MatchOutput::kPosterior) {
    post.scores.clear();
    post.scores.shrink_to_fit();
    post.yaw_rad.clear();
  }
}

}  // namespace floorcast

#include "floorcast/match/posterior_query.hpp"

#include <atomic>
#include <mutex>
#include <stdexcept>

#include "floorcast/core/types.hpp"

namespace floorcast {

struct PosteriorQuery::State {
  PointScorer scorer;
  FullPosterior compute;
  std::mutex mutex;
  bool have_full = false;
  Posterior full;
  std::atomic<std::int64_t> scored{0};
};

namespace {

double posterior_max(const Posterior& p) {
  float best = 0.0f;
  for (const cv::Mat& m : p.scores) {
    for (int r = 0; r < m.rows; ++r) {
      const float* row = m.ptr<float>(r);
      for (int c = 0; c < m.cols; ++c) best = std::max(best, row[c]);
    }
  }
  return best;
}

}  // namespace

PosteriorQuery::PosteriorQuery(Posterior posterior)
    : grid_(posterior.grid), yaw_rad_(posterior.yaw_rad), max_score_(posterior_max(posterior)), state_(std::make_shared<State>()) {
  state_->full = std::move(posterior);
  state_->have_full = true;
}

PosteriorQuery::PosteriorQuery(GridSpec grid, std::vector<double> yaw_rad, double max_score, PointScorer scorer,
                               FullPosterior full)
    : grid_(grid), yaw_rad_(std::move(yaw_rad)), max_score_(max_score), state_(std::make_shared<State>()) {
  if (!scorer || !full) throw std::invalid_argument("PosteriorQuery: a point scorer and a full posterior are needed");
  state_->scorer = std::move(scorer);
  state_->compute = std::move(full);
}

int PosteriorQuery::nearest_slice(double yaw, double* gap_rad) const {
  int slice = 0;
  double gap = 1e9;
  for (int s = 0; s < num_slices(); ++s) {
    const double a = angle_distance_rad(yaw, yaw_rad_[static_cast<std::size_t>(s)]);
    if (a < gap) {
      gap = a;
      slice = s;
    }
  }
  if (gap_rad) *gap_rad = gap;
  return slice;
}

bool PosteriorQuery::has_full() const {
  std::lock_guard<std::mutex> lock(state_->mutex);
  return state_->have_full;
}

const Posterior& PosteriorQuery::full() const {
  std::lock_guard<std::mutex> lock(state_->mutex);
  if (!state_->have_full) {
    state_->full = state_->compute();
    state_->have_full = true;
  }
  return state_->full;
}

bool PosteriorQuery::scores_points() const { return static_cast<bool>(state_->scorer); }

std::int64_t PosteriorQuery::cells_scored() const { return state_->scored.load(); }

void PosteriorQuery::scores(const std::vector<PosteriorCell>& cells, std::vector<float>& out) const {
  out.resize(cells.size());
  for (const PosteriorCell& c : cells) {
    if (c.slice < 0 || c.slice >= num_slices() || !grid_.contains(c.row, c.col)) {
      throw std::invalid_argument("PosteriorQuery::scores: cell outside the posterior");
    }
  }
  if (!state_->scorer) {
    // Built from a full posterior: look the cells up. (A query with a point scorer keeps scoring
    // even after full() was computed, so its answers never depend on who asked for what first.)
    const Posterior& p = state_->full;
    for (std::size_t i = 0; i < cells.size(); ++i)
      out[i] = p.scores[static_cast<std::size_t>(cells[i].slice)].at<float>(cells[i].row, cells[i].col);
    return;
  }
  if (!cells.empty()) state_->scorer(cells, out.data());
  state_->scored += static_cast<std::int64_t>(cells.size());
}

}  // namespace floorcast

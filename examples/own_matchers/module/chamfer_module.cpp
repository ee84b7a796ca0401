// The chamfer matcher of ../chamfer.py in C++, as a floorcast matcher module: scenarios and
// commands name it `chamfer_cpp` like `kernel`. Parameters: sigma_m, clearance_m (as chamfer.py),
// resolution_m, yaw_bins (the shared grid, floorcast/match/external.hpp).
#include <opencv2/core.hpp>

#include <chrono>
#include <cmath>

#include "floorcast/core/params.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/match/external.hpp"
#include "floorcast/match/matcher_module.hpp"

namespace {

using namespace floorcast;

struct ChamferParams {
  double sigma_m = 0.2;
  double clearance_m = 0.2;
  double resolution_m = 0.2;
  int yaw_bins = 36;
  nlohmann::ordered_json to_json() const {
    return {{"sigma_m", sigma_m}, {"clearance_m", clearance_m}, {"resolution_m", resolution_m}, {"yaw_bins", yaw_bins}};
  }
};

class ChamferMatcher final : public Matcher {
 public:
  ChamferMatcher(const FloorPlan& plan, const ChamferParams& p) : params_(p) {
    const auto t0 = std::chrono::steady_clock::now();
    grid_ = shared_posterior_grid(plan, p.resolution_m, p.yaw_bins);
    distance_m_ = distance_to_blocked_m(rasterize_occupancy(plan, grid_.grid, closed_door_map()), grid_.grid);
    likelihood_.create(distance_m_.size(), CV_32F);
    for (int r = 0; r < distance_m_.rows; ++r)
      for (int c = 0; c < distance_m_.cols; ++c) {
        const double d = distance_m_.at<float>(r, c) / p.sigma_m;
        likelihood_.at<float>(r, c) = static_cast<float>(std::exp(-0.5 * d * d));
      }
    precompute_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  std::string name() const override { return "chamfer_cpp"; }
  nlohmann::ordered_json parameters() const override { return params_.to_json(); }
  double precompute_s() const override { return precompute_s_; }
  std::size_t precompute_bytes() const override { return 2 * likelihood_.total() * sizeof(float); }
  BlockingOptions blocking() const override { return closed_door_map(); }

  MatchResult match(const Observation2D& observation, const MatchRequest& request) const override {
    const auto t0 = std::chrono::steady_clock::now();
    // Points every 0.25 m along the observed segments (observer frame), at most 96.
    std::vector<Vec2> points;
    for (const Segment2& s : observation.segments_m) {
      const int n = std::max(1, static_cast<int>((s.b_m - s.a_m).norm() / 0.25));
      for (int i = 0; i < n; ++i) points.push_back(s.a_m + (i + 0.5) / n * (s.b_m - s.a_m));
    }
    if (points.size() > 96) {
      std::vector<Vec2> thinned;
      for (int i = 0; i < 96; ++i) thinned.push_back(points[static_cast<std::size_t>(std::lround(i * (points.size() - 1) / 95.0))]);
      points.swap(thinned);
    }
    const int h = grid_.grid.height_px, w = grid_.grid.width_px;
    const double res = grid_.grid.resolution_m_per_px;
    ExternalMatchOutput out;
    out.has_posterior = true;
    out.grid = grid_;
    for (double yaw : grid_.yaw_rad) {
      cv::Mat acc = cv::Mat::zeros(h, w, CV_32F);
      for (const Vec2& p : points) {
        // Cell (r, c) sees the point at cell (r + dy, c + dx).
        const int dx = static_cast<int>(std::lround((std::cos(yaw) * p.x() - std::sin(yaw) * p.y()) / res));
        const int dy = static_cast<int>(std::lround((std::sin(yaw) * p.x() + std::cos(yaw) * p.y()) / res));
        const cv::Rect dst = cv::Rect(0, 0, w, h) & cv::Rect(-dx, -dy, w, h);
        if (dst.empty()) continue;
        acc(dst) += likelihood_(dst + cv::Point(dx, dy));
      }
      if (!points.empty()) acc /= static_cast<double>(points.size());
      acc.setTo(0.0f, distance_m_ < params_.clearance_m);
      out.scores.push_back(acc);
    }
    MatchResult r = finish_external_output(std::move(out), grid_, request, "chamfer_cpp");
    r.match_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
  }
  using Matcher::match;

 private:
  ChamferParams params_;
  PosteriorGrid grid_;
  cv::Mat distance_m_, likelihood_;
  double precompute_s_ = 0.0;
};

class ChamferConfig final : public MatcherConfig {
 public:
  explicit ChamferConfig(ChamferParams p) : params_(p) {}
  std::string name() const override { return "chamfer_cpp"; }
  nlohmann::ordered_json parameters() const override { return params_.to_json(); }
  std::unique_ptr<Matcher> build(const FloorPlan& plan) const override { return std::make_unique<ChamferMatcher>(plan, params_); }

 private:
  ChamferParams params_;
};

std::shared_ptr<const MatcherConfig> parse(const nlohmann::json& overrides, const SharedParams&) {
  ChamferParams p;
  ParamReader r(overrides, "matcher chamfer_cpp");
  r.read("sigma_m", p.sigma_m, 0.01, 10.0);
  r.read("clearance_m", p.clearance_m, 0.0, 10.0);
  r.read("resolution_m", p.resolution_m, 0.02, 2.0);
  r.read("yaw_bins", p.yaw_bins, 1, 720);
  r.finish();
  return std::make_shared<ChamferConfig>(p);
}

}  // namespace

FLOORCAST_MATCHER_MODULE(parse)

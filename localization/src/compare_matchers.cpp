#include "floorcast/localization/compare_matchers.hpp"
#include "floorcast/core/math.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>

namespace floorcast {
namespace {


std::string fmt(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

std::string markdown_table(const std::vector<std::string>& labels, const std::map<std::string, MatcherSummary>& s) {
  std::ostringstream out;
  out << "| matcher | n | @0.5 m | @1 m | @1 m 30 deg | @2 m | top-5 @1 m | median pos. err (m) | median yaw err (deg) | mean time (s) |\n";
  out << "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const std::string& l : labels) {
    auto it = s.find(l);
    if (it == s.end()) continue;
    const MatcherSummary& m = it->second;
    out << "| " << l << " | " << m.count << " | " << fmt(100 * m.recall_0_5m, 1) << "% | " << fmt(100 * m.recall_1m, 1)
        << "% | " << fmt(100 * m.recall_1m_30deg, 1) << "% | " << fmt(100 * m.recall_2m, 1) << "% | "
        << fmt(100 * m.top5_recall_1m, 1) << "% | " << fmt(m.median_position_error_m, 2) << " | "
        << fmt(m.median_yaw_error_deg, 1) << " | " << fmt(m.mean_time_s, 3) << " |\n";
  }
  return out.str();
}

}  // namespace

bool point_in_polygon(const std::vector<Vec2>& poly, const Vec2& p) {
  bool inside = false;
  const std::size_t n = poly.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      inside = !inside;
    }
  }
  return inside;
}

std::vector<Pose2> sample_observation_poses(const FloorPlan& plan, int n, std::uint64_t seed, int plan_index,
                                            double clearance_m, double resolution_m,
                                            const std::vector<std::vector<Vec2>>& regions) {
  RasterOptions ro;
  ro.resolution_m_per_px = resolution_m;
  const PlanRasters rasters = make_plan_rasters(plan, ro);
  const GridSpec& g = rasters.grid;
  // Nobody stands inside furniture: every obstacle footprint blocks, whatever its height (the
  // default rasters cut at 1.5 m, where beds, sofas and desks do not exist). The clearance is
  // kept from walls and obstacles alike.
  BlockingOptions standing = ro.blocking;
  standing.obstacles_block = true;
  standing.cut_height_m = 0.01;
  cv::Mat blocked = rasterize_occupancy(plan, g, standing);
  cv::max(blocked, rasters.occupancy, blocked);
  const cv::Mat distance_m = distance_to_blocked_m(blocked, g);
  // A blocked cell's centre may be up to half a diagonal farther than the surface in it, and the
  // point moves up to half a diagonal inside its cell: keep a full diagonal of slack.
  const float need = static_cast<float>(clearance_m + std::sqrt(2.0) * resolution_m);
  std::vector<std::pair<int, int>> cells;
  for (int r = 0; r < g.height_px; ++r) {
    const std::uint8_t* v = rasters.valid.ptr<std::uint8_t>(r);
    const float* d = distance_m.ptr<float>(r);
    for (int c = 0; c < g.width_px; ++c) {
      if (!v[c] || d[c] < need) continue;
      bool in_region = regions.empty();
      for (std::size_t k = 0; k < regions.size() && !in_region; ++k) {
        in_region = point_in_polygon(regions[k], g.cell_center_m(r, c));
      }
      if (in_region) cells.emplace_back(r, c);
    }
  }
  if (cells.empty()) {
    throw InputError("plan \"" + plan.name + "\": no free cell with " + fmt(clearance_m, 2) + " m clearance" +
                     (regions.empty() ? "" : " inside the sampling regions") + " to sample observation points from");
  }
  std::vector<Pose2> poses;
  poses.reserve(static_cast<std::size_t>(std::max(n, 0)));
  for (int i = 0; i < n; ++i) {
    std::seed_seq seq{static_cast<std::uint32_t>(seed & 0xffffffffu), static_cast<std::uint32_t>(seed >> 32),
                      static_cast<std::uint32_t>(plan_index), static_cast<std::uint32_t>(i)};
    std::mt19937_64 rng(seq);
    std::uniform_int_distribution<std::size_t> pick(0, cells.size() - 1);
    std::uniform_real_distribution<double> jitter(-0.5, 0.5);
    std::uniform_real_distribution<double> yaw(0.0, 2.0 * kPi);
    const auto [r, c] = cells[pick(rng)];
    const Vec2 centre = g.cell_center_m(r, c);
    Pose2 p;
    p.x_m = centre.x() + jitter(rng) * resolution_m;
    p.y_m = centre.y() + jitter(rng) * resolution_m;
    p.yaw_rad = yaw(rng);
    poses.push_back(p);
  }
  return poses;
}

MatcherSummary summarise(const std::vector<const PointOutcome*>& outcomes, double yaw_threshold_deg) {
  MatcherSummary s;
  s.count = static_cast<int>(outcomes.size());
  if (outcomes.empty()) return s;
  std::vector<double> pos, yaw;
  double time = 0.0;
  int r05 = 0, r1 = 0, r130 = 0, r2 = 0, top = 0;
  for (const PointOutcome* o : outcomes) {
    pos.push_back(o->position_error_m);
    yaw.push_back(o->yaw_error_deg);
    time += o->time_s;
    r05 += o->position_error_m <= 0.5;
    r1 += o->position_error_m <= 1.0;
    r130 += o->position_error_m <= 1.0 && o->yaw_error_deg <= yaw_threshold_deg;
    r2 += o->position_error_m <= 2.0;
    top += o->top_k_hit_1m;
  }
  const double n = static_cast<double>(outcomes.size());
  s.recall_0_5m = r05 / n;
  s.recall_1m = r1 / n;
  s.recall_1m_30deg = r130 / n;
  s.recall_2m = r2 / n;
  s.top5_recall_1m = top / n;
  s.median_position_error_m = median(pos);
  s.median_yaw_error_deg = median(yaw);
  s.mean_time_s = time / n;
  return s;
}

std::vector<MatcherSpec> default_comparison_specs(const std::vector<int>& ray_counts) {
  std::vector<MatcherSpec> specs;
  specs.push_back({"kernel", "kernel", nlohmann::json::object()});
  for (int n : ray_counts) {
    MatcherSpec s;
    s.label = n == 36 ? "ray" : "ray" + std::to_string(n);
    s.name = "ray";
    s.overrides = nlohmann::json{{"num_directions", n}};
    specs.push_back(s);
  }
  return specs;
}

ComparisonResult compare_matchers(const std::vector<NamedPlan>& plans, const std::vector<MatcherSpec>& specs,
                                  const ComparisonParams& params,
                                  const std::function<void(const std::string&)>& progress) {
  ComparisonResult result;
  for (const MatcherSpec& s : specs) result.labels.push_back(s.label);
  const double yaw_sep = params.top_k_separation_deg * kPi / 180.0;
  for (std::size_t pi = 0; pi < plans.size(); ++pi) {
    const NamedPlan& np = plans[pi];
    const std::vector<Pose2> poses = sample_observation_poses(np.plan, params.points_per_plan, params.seed,
                                                              static_cast<int>(pi), params.clearance_m,
                                                              params.sample_resolution_m, np.sample_regions);
    const PerfectObserver observer(np.plan, params.observation);
    std::vector<Observation2D> observations;
    observations.reserve(poses.size());
    std::vector<double> mean_range;
    for (const Pose2& p : poses) {
      observations.push_back(observer.observe(p));
      double sum = 0.0;
      for (double x : observer.ray_ranges(p.position_m(), 0.0, 36)) sum += x;
      mean_range.push_back(sum / 36.0);
    }
    if (progress) progress(np.name + ": " + std::to_string(poses.size()) + " perfect observations");

    std::vector<PointOutcome> plan_points(poses.size() * specs.size());
    // One matcher at a time per plan: its precomputation (e.g. a 180-direction volume) is freed
    // before the next one is built.
    for (std::size_t si = 0; si < specs.size(); ++si) {
      const MatcherSpec& spec = specs[si];
      const std::unique_ptr<Matcher> m = make_matcher(spec.name, np.plan, spec.overrides);
      MatcherPrecompute pc;
      pc.plan = np.name;
      pc.matcher = spec.label;
      pc.precompute_s = m->precompute_s();
      pc.precompute_mb = m->precompute_bytes() / 1e6;
      pc.parameters = m->parameters();
      result.precompute.push_back(pc);
      for (std::size_t i = 0; i < poses.size(); ++i) {
        const MatchResult mr = m->match(observations[i]);
        PointOutcome& o = plan_points[i * specs.size() + si];
        o.plan = np.name;
        o.point = static_cast<int>(i);
        o.matcher = spec.label;
        o.truth = poses[i];
        o.estimate = mr.posterior.argmax();
        o.position_error_m = std::hypot(o.estimate.x_m - o.truth.x_m, o.estimate.y_m - o.truth.y_m);
        o.yaw_error_deg = angle_distance_rad(o.estimate.yaw_rad, o.truth.yaw_rad) * 180.0 / kPi;
        for (const PoseHypothesis& h : mr.posterior.top_k(params.top_k, params.top_k_separation_m, yaw_sep)) {
          if (std::hypot(h.x_m - o.truth.x_m, h.y_m - o.truth.y_m) <= 1.0) o.top_k_hit_1m = true;
        }
        o.time_s = mr.match_s;
        o.num_segments = static_cast<int>(observations[i].segments_m.size());
        o.mean_range_m = mean_range[i];
      }
      if (progress) {
        progress(np.name + ": " + spec.label + " done (precompute " + fmt(pc.precompute_s, 2) + " s, " +
                 fmt(pc.precompute_mb, 1) + " MB)");
      }
    }
    for (const MatcherSpec& spec : specs) {
      std::vector<const PointOutcome*> sel;
      for (const PointOutcome& o : plan_points)
        if (o.matcher == spec.label) sel.push_back(&o);
      result.per_plan[np.name][spec.label] = summarise(sel, params.yaw_threshold_deg);
    }
    result.points.insert(result.points.end(), plan_points.begin(), plan_points.end());
  }
  for (const MatcherSpec& spec : specs) {
    std::vector<const PointOutcome*> sel;
    for (const PointOutcome& o : result.points)
      if (o.matcher == spec.label) sel.push_back(&o);
    result.summary[spec.label] = summarise(sel, params.yaw_threshold_deg);
  }
  return result;
}

nlohmann::ordered_json comparison_summary_json(const ComparisonResult& result) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const std::string& l : result.labels) {
    auto it = result.summary.find(l);
    if (it == result.summary.end()) continue;
    const MatcherSummary& s = it->second;
    nlohmann::ordered_json m;
    m["recall_0.5m"] = s.recall_0_5m;
    m["recall_1m"] = s.recall_1m;
    m["recall_1m_30deg"] = s.recall_1m_30deg;
    m["recall_2m"] = s.recall_2m;
    m["top5_recall_1m"] = s.top5_recall_1m;
    m["median_position_error_m"] = s.median_position_error_m;
    m["median_yaw_error_deg"] = s.median_yaw_error_deg;
    m["mean_time_s"] = s.mean_time_s;
    j[l] = m;
  }
  return j;
}

std::string comparison_points_csv(const ComparisonResult& result) {
  std::ostringstream out;
  out << "plan,point,matcher,true_x_m,true_y_m,true_yaw_deg,est_x_m,est_y_m,est_yaw_deg,score,position_error_m,"
         "yaw_error_deg,top5_hit_1m,time_s,num_segments,mean_range_m\n";
  for (const PointOutcome& o : result.points) {
    out << o.plan << "," << o.point << "," << o.matcher << "," << fmt(o.truth.x_m, 4) << "," << fmt(o.truth.y_m, 4)
        << "," << fmt(o.truth.yaw_rad * 180.0 / kPi, 3) << "," << fmt(o.estimate.x_m, 4) << ","
        << fmt(o.estimate.y_m, 4) << "," << fmt(o.estimate.yaw_rad * 180.0 / kPi, 3) << ","
        << fmt(o.estimate.score, 8) << "," << fmt(o.position_error_m, 4) << "," << fmt(o.yaw_error_deg, 3) << ","
        << (o.top_k_hit_1m ? 1 : 0) << "," << fmt(o.time_s, 5) << "," << o.num_segments << ","
        << fmt(o.mean_range_m, 3) << "\n";
  }
  return out.str();
}

std::string comparison_markdown(const ComparisonResult& result) {
  std::string out = markdown_table(result.labels, result.summary);
  if (result.per_plan.size() > 1) {
    for (const auto& [plan, s] : result.per_plan) {
      out += "\n" + plan + ":\n\n" + markdown_table(result.labels, s);
    }
  }
  return out;
}

}  // namespace floorcast

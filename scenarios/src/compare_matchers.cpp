#include "floorcast/scenarios/compare_matchers.hpp"
#include "floorcast/core/format.hpp"
#include "floorcast/core/math.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>

namespace floorcast {
namespace {



std::string markdown_table(const std::vector<std::string>& labels, const std::map<std::string, MatcherSummary>& s) {
  std::ostringstream out;
  out << "| matcher | n | @0.5 m | @1 m | @1 m 30 deg | @2 m | top-5 @1 m | median pos. err (m) | median yaw err (deg) | mean time (s) |\n";
  out << "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const std::string& l : labels) {
    auto it = s.find(l);
    if (it == s.end()) continue;
    const MatcherSummary& m = it->second;
    out << "| " << l << " | " << m.count << " | " << format_fixed(100 * m.recall_0_5m, 1) << "% | " << format_fixed(100 * m.recall_1m, 1)
        << "% | " << format_fixed(100 * m.recall_1m_30deg, 1) << "% | " << format_fixed(100 * m.recall_2m, 1) << "% | "
        << format_fixed(100 * m.top5_recall_1m, 1) << "% | " << format_fixed(m.median_position_error_m, 2) << " | "
        << format_fixed(m.median_yaw_error_deg, 1) << " | " << format_fixed(m.mean_time_s, 3) << " |\n";
  }
  return out.str();
}

}  // namespace


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
        progress(np.name + ": " + spec.label + " done (precompute " + format_fixed(pc.precompute_s, 2) + " s, " +
                 format_fixed(pc.precompute_mb, 1) + " MB)");
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
    out << o.plan << "," << o.point << "," << o.matcher << "," << format_fixed(o.truth.x_m, 4) << "," << format_fixed(o.truth.y_m, 4)
        << "," << format_fixed(o.truth.yaw_rad * 180.0 / kPi, 3) << "," << format_fixed(o.estimate.x_m, 4) << ","
        << format_fixed(o.estimate.y_m, 4) << "," << format_fixed(o.estimate.yaw_rad * 180.0 / kPi, 3) << ","
        << format_fixed(o.estimate.score, 8) << "," << format_fixed(o.position_error_m, 4) << "," << format_fixed(o.yaw_error_deg, 3) << ","
        << (o.top_k_hit_1m ? 1 : 0) << "," << format_fixed(o.time_s, 5) << "," << o.num_segments << ","
        << format_fixed(o.mean_range_m, 3) << "\n";
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

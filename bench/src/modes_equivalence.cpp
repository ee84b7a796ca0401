#include "floorcast/bench/modes_equivalence.hpp"

#include "floorcast/core/fields.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "floorcast/core/math.hpp"
#include "floorcast/core/random.hpp"
#include "floorcast/sim/perfect_observation.hpp"

namespace floorcast {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

bool same_pick(const PoseHypothesis& a, const PoseHypothesis& b) {
  return a.slice == b.slice && a.row == b.row && a.col == b.col;
}

std::string describe(const PoseHypothesis& h) {
  std::ostringstream s;
  s << "slice " << h.slice << " cell (" << h.row << ", " << h.col << ") score " << h.score;
  return s.str();
}

}  // namespace

std::vector<Pose2> sample_valid_poses(const KernelMatcher& matcher, int count, std::uint64_t seed) {
  return sample_valid_poses(matcher.valid_mask(), matcher.grid(), count, seed);
}

std::vector<Pose2> sample_valid_poses(const cv::Mat& valid, const GridSpec& g, int count, std::uint64_t seed) {
  std::vector<std::pair<int, int>> cells;
  for (int r = 0; r < valid.rows; ++r)
    for (int c = 0; c < valid.cols; ++c)
      if (valid.at<std::uint8_t>(r, c)) cells.emplace_back(r, c);
  std::vector<Pose2> poses;
  if (cells.empty()) return poses;
  const CounterRng rng(seed, 0x6d6f646573ULL);  // "modes"
  for (int i = 0; i < count; ++i) {
    const CounterRng item = rng.child(static_cast<std::uint64_t>(i));
    const std::size_t k = std::min(cells.size() - 1, static_cast<std::size_t>(item.uniform(0) * cells.size()));
    const auto [r, c] = cells[k];
    // Anywhere inside the cell, any heading.
    const double x = g.origin_x_m + (c + item.uniform(1)) * g.resolution_m_per_px;
    const double y = g.origin_y_m + (r + item.uniform(2)) * g.resolution_m_per_px;
    poses.push_back({x, y, 2.0 * kPi * item.uniform(3)});
  }
  return poses;
}

void compare_modes(const KernelMatcher& matcher, const Observation2D& obs, const MatchResult& bb,
                   const MatchResult& fft, const ModesEquivalenceParams& params, const std::string& label,
                   ModesEquivalenceResult& out) {
  const std::vector<double>& scales = matcher.params().scales;
  ++out.observations;
  // The search's exact value of a pick: max over scales.
  auto exact = [&](const PoseHypothesis& h) {
    double best = -1e300;
    for (double s : scales) best = std::max(best, matcher.cell_score(obs, h.yaw_rad, s, h.row, h.col));
    return best;
  };
  auto fail = [&](const std::string& what) {
    out.failures.push_back(label + ": " + what);
    ++out.mismatches;
  };
  const std::size_t n = std::max(bb.modes.size(), fft.modes.size());
  if (n == 0) {
    ++out.no_pose;
    ++out.estimates_identical;
    ++out.top_k_identical;
    return;
  }
  bool tied = false, bad = false;
  // The posterior's value of a pick (max over scales, clipped, masked).
  auto posterior_value = [&](const PoseHypothesis& h) {
    return static_cast<double>(fft.posterior.scores[static_cast<std::size_t>(h.slice)].at<float>(h.row, h.col));
  };
  for (std::size_t k = 0; k < n && !tied && !bad; ++k) {
    if (k >= bb.modes.size() || k >= fft.modes.size()) {
      fail("mode " + std::to_string(k) + ": search found " + std::to_string(bb.modes.size()) + " modes, posterior " +
           std::to_string(fft.modes.size()));
      bad = true;
      break;
    }
    const PoseHypothesis& a = bb.modes[k];
    const PoseHypothesis& b = fft.modes[k];
    const double ea = exact(a);
    out.max_search_error = std::max(out.max_search_error, std::abs(a.score - ea));
    if (std::abs(a.score - ea) > params.exact_tolerance) {
      fail("mode " + std::to_string(k) + ": search score " + std::to_string(a.score) + " differs from the direct sum " +
           std::to_string(ea));
      bad = true;
      break;
    }
    if (same_pick(a, b)) {
      out.max_fft_error = std::max(out.max_fft_error, std::abs(b.score - ea));
      if (k == 0) ++out.estimates_identical;
      continue;
    }
    const double eb = exact(b);
    const double fa = posterior_value(a);
    out.max_fft_error = std::max({out.max_fft_error, std::abs(b.score - eb), std::abs(fa - ea)});
    // The posterior ordered b before a; in exact values a >= b. Legitimate when a and b are
    // tied, or when the FFT's own errors at the two cells are as large as the gap.
    const double fft_slack = std::abs(fa - ea) + std::abs(b.score - eb);
    if (ea < eb - params.exact_tolerance) {
      fail("mode " + std::to_string(k) + ": search " + describe(a) + " (exact " + std::to_string(ea) +
           ") is worse than posterior " + describe(b) + " (exact " + std::to_string(eb) + ")");
      bad = true;
    } else if (ea - eb <= params.exact_tolerance) {
      tied = true;
      out.max_tie_gap = std::max(out.max_tie_gap, std::abs(ea - eb));
      if (k == 0) ++out.estimates_tied;
    } else if (ea - eb <= fft_slack + params.exact_tolerance) {
      tied = true;
      out.max_fft_order_gap = std::max(out.max_fft_order_gap, ea - eb);
      if (k == 0) ++out.estimates_fft_order;
      ++out.fft_order_differences;
    } else {
      fail("mode " + std::to_string(k) + ": search " + describe(a) + " (exact " + std::to_string(ea) +
           ") vs posterior " + describe(b) + " (exact " + std::to_string(eb) + "): gap beyond the FFT error " +
           std::to_string(fft_slack));
      bad = true;
    }
  }
  if (!bad) {
    if (tied) {
      ++out.top_k_tied;
    } else {
      ++out.top_k_identical;
    }
  }
}

ModesEquivalenceResult compare_modes_with_posterior(const FloorPlan& plan, const KernelMatcher& matcher,
                                                    const ModesEquivalenceParams& params) {
  ModesEquivalenceResult out;
  PerfectObservationParams pp;
  pp.max_range_m = params.max_range_m;
  pp.num_rays = 0;
  pp.blocking = matcher.blocking();
  const PerfectObserver observer(plan, pp);
  const std::vector<Pose2> poses = sample_valid_poses(matcher, params.observations, params.seed);
  MatchRequest full;
  full.output = MatchOutput::kPosterior;
  full.top_k = params.top_k;
  const MatchRequest modes = MatchRequest::modes(params.top_k);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const Observation2D obs = observer.observe(poses[i]);
    auto t = Clock::now();
    const MatchResult bb = matcher.match(obs, modes);
    out.search_s.push_back(seconds_since(t));
    t = Clock::now();
    const MatchResult fft = matcher.match(obs, full);
    out.posterior_s.push_back(seconds_since(t));
    std::ostringstream label;
    label << "observation " << i << " at (" << poses[i].x_m << ", " << poses[i].y_m << ", "
          << rad_to_deg(poses[i].yaw_rad) << " deg)";
    compare_modes(matcher, obs, bb, fft, params, label.str(), out);
  }
  return out;
}

const FieldList<ModesEquivalenceResult>& modes_equivalence_fields() {
  using R = ModesEquivalenceResult;
  constexpr double kAny = 1e300;
  constexpr int kMany = 1 << 30;
  // The wall-time series are written as their medians and read back as one-value series.
  auto median_of = [](const char* key, std::vector<double> R::*m) {
    return [key, m](nlohmann::ordered_json& j, const R& r) { j[key] = (r.*m).empty() ? 0.0 : median(r.*m); };
  };
  auto one_value = [](const char* key, std::vector<double> R::*m) {
    return [key, m](ParamReader& in, R& r) {
      double v = 0.0;
      in.read(key, v, 0.0, kAny);
      r.*m = {v};
    };
  };
  static const FieldList<R> f =
      FieldList<R>("modes equivalence")
          .integer("observations", &R::observations, 0, kMany, "observations compared")
          .integer("estimates_identical", &R::estimates_identical, 0, kMany, "same estimate cell and slice (or both no pose)")
          .integer("estimates_tied", &R::estimates_tied, 0, kMany, "different picks of a tied exact value")
          .integer("top_k_identical", &R::top_k_identical, 0, kMany, "whole top-K lists identical")
          .integer("top_k_tied", &R::top_k_tied, 0, kMany, "identical up to a tie or an FFT-order difference")
          .integer("no_pose", &R::no_pose, 0, kMany, "observations both found no pose for")
          .integer("mismatches", &R::mismatches, 0, kMany, "real differences")
          .integer("estimates_fft_order", &R::estimates_fft_order, 0, kMany, "picks ordered differently by FFT round-off")
          .integer("fft_order_differences", &R::fft_order_differences, 0, kMany, "lists diverging at such a pick")
          .number("max_tie_gap", &R::max_tie_gap, 0.0, kAny, "largest exact-value gap among ties")
          .number("max_fft_order_gap", &R::max_fft_order_gap, 0.0, kAny, "largest gap the FFT's round-off reordered")
          .number("max_search_error", &R::max_search_error, 0.0, kAny, "largest |search score - direct sum|")
          .number("max_fft_error", &R::max_fft_error, 0.0, kAny, "largest |posterior value - direct sum|")
          .custom("search_s_median", median_of("search_s_median", &R::search_s), one_value("search_s_median", &R::search_s),
                  "number", "median wall s per observation, estimate + top-K by the search")
          .custom("posterior_s_median", median_of("posterior_s_median", &R::posterior_s),
                  one_value("posterior_s_median", &R::posterior_s), "number",
                  "median wall s per observation, FFT posterior + top_k")
          .texts("failures", &R::failures, "one line per mismatch");
  return f;
}

nlohmann::ordered_json to_json(const ModesEquivalenceResult& r) { return modes_equivalence_fields().write(r); }

}  // namespace floorcast

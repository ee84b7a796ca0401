#include "floorcast/match/orientation.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/core/params.hpp"

#include <algorithm>
#include <cmath>

namespace floorcast {
namespace {


double wrap_2pi(double a) {
  a = std::fmod(a, 2.0 * kPi);
  if (a < 0.0) a += 2.0 * kPi;
  if (a >= 2.0 * kPi) a -= 2.0 * kPi;
  return a;
}

std::vector<double> dense_candidates(double step_deg) {
  const int n = std::max(1, static_cast<int>(std::lround(360.0 / step_deg)));
  std::vector<double> out;
  out.reserve(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) out.push_back(2.0 * kPi * k / n);
  return out;
}

}  // namespace

const std::vector<std::pair<const char*, OrientationMode>>& orientation_mode_names() {
  static const std::vector<std::pair<const char*, OrientationMode>> names = {
      {"palms", OrientationMode::kPalms}, {"palms+", OrientationMode::kPalmsPlus}, {"dense", OrientationMode::kDense}};
  return names;
}

std::string orientation_mode_name(OrientationMode mode) { return enum_name(mode, orientation_mode_names()); }

std::vector<double> direction_histogram(const std::vector<Segment2>& segments, int bins) {
  std::vector<double> h(static_cast<std::size_t>(std::max(bins, 1)), 0.0);
  const double bin_rad = kPi / bins;
  for (const Segment2& s : segments) {
    const double len = s.length_m();
    if (!(len > 0.0)) continue;
    double a = std::fmod(s.direction_rad(), kPi);
    if (a < 0.0) a += kPi;
    int b = static_cast<int>(std::floor(a / bin_rad));
    if (b >= bins) b = bins - 1;  // a == pi after rounding
    if (b < 0) b = 0;
    h[static_cast<std::size_t>(b)] += len;
  }
  return h;
}

std::vector<double> circular_correlation(const std::vector<double>& plan, const std::vector<double>& obs) {
  const std::size_t B = plan.size();
  std::vector<double> c(B, 0.0);
  if (obs.size() != B) return c;
  for (std::size_t s = 0; s < B; ++s) {
    double sum = 0.0;
    for (std::size_t k = 0; k < B; ++k) {
      if (obs[k] != 0.0) sum += plan[(k + s) % B] * obs[k];
    }
    c[s] = sum;
  }
  return c;
}

std::vector<int> circular_peaks(const std::vector<double>& signal, int radius, int max_peaks) {
  const int B = static_cast<int>(signal.size());
  std::vector<int> peaks;
  std::vector<char> dead(static_cast<std::size_t>(B), 0);
  while (static_cast<int>(peaks.size()) < max_peaks) {
    int best = -1;
    for (int i = 0; i < B; ++i) {
      if (dead[static_cast<std::size_t>(i)] || !(signal[static_cast<std::size_t>(i)] > 0.0)) continue;
      if (best < 0 || signal[static_cast<std::size_t>(i)] > signal[static_cast<std::size_t>(best)]) best = i;
    }
    if (best < 0) break;
    peaks.push_back(best);
    for (int d = -radius; d <= radius; ++d) dead[static_cast<std::size_t>(((best + d) % B + B) % B)] = 1;
  }
  return peaks;
}

double principal_orientation_rad(const std::vector<Segment2>& segments, int bins90) {
  std::vector<double> h(static_cast<std::size_t>(bins90), 0.0);
  const double bin_rad = 0.5 * kPi / bins90;
  for (const Segment2& s : segments) {
    const double len = s.length_m();
    if (!(len > 0.0)) continue;
    double a = std::fmod(s.direction_rad(), 0.5 * kPi);
    if (a < 0.0) a += 0.5 * kPi;
    int b = static_cast<int>(std::floor(a / bin_rad));
    b = std::clamp(b, 0, bins90 - 1);
    h[static_cast<std::size_t>(b)] += len;
  }
  int best = 0;
  double best_v = -1.0;
  for (int i = 0; i < bins90; ++i) {
    const double v = h[static_cast<std::size_t>((i + bins90 - 1) % bins90)] + h[static_cast<std::size_t>(i)] +
                     h[static_cast<std::size_t>((i + 1) % bins90)];
    if (v > best_v) {
      best_v = v;
      best = i;
    }
  }
  // Refine: length-weighted circular mean (period 90 deg) of the directions within two bins of
  // the peak, so exact data gives the exact orientation rather than a bin centre.
  const double centre = (best + 0.5) * bin_rad;
  double sx = 0.0, sy = 0.0;
  for (const Segment2& s : segments) {
    const double len = s.length_m();
    if (!(len > 0.0)) continue;
    const double a = s.direction_rad();
    double d = std::fmod(a - centre, 0.5 * kPi);
    if (d < -0.25 * kPi) d += 0.5 * kPi;
    if (d >= 0.25 * kPi) d -= 0.5 * kPi;
    if (std::abs(d) > 2.5 * bin_rad) continue;
    sx += len * std::cos(4.0 * d);
    sy += len * std::sin(4.0 * d);
  }
  double out = centre + (sx > 0.0 || sy != 0.0 ? 0.25 * std::atan2(sy, sx) : 0.0);
  out = std::fmod(out, 0.5 * kPi);
  if (out < 0.0) out += 0.5 * kPi;
  return out;
}

/// Distinct directions in [0, pi) (merged within 1e-6 rad) with their total length.
std::vector<std::pair<double, double>> distinct_directions(const std::vector<Segment2>& segments) {
  std::vector<std::pair<double, double>> d;
  for (const Segment2& s : segments) {
    const double len = s.length_m();
    if (!(len > 0.0)) continue;
    double a = std::fmod(s.direction_rad(), kPi);
    if (a < 0.0) a += kPi;
    if (a >= kPi) a -= kPi;
    d.emplace_back(a, len);
  }
  std::sort(d.begin(), d.end());
  std::vector<std::pair<double, double>> out;
  for (const auto& [a, l] : d) {
    if (!out.empty() && a - out.back().first < 1e-6) {
      out.back().second += l;
    } else {
      out.emplace_back(a, l);
    }
  }
  return out;
}

double refine_orientation(const std::vector<std::pair<double, double>>& plan, const std::vector<Segment2>& obs,
                          double yaw, double half_window, double kernel) {
  const std::vector<std::pair<double, double>> od = distinct_directions(obs);
  if (od.empty() || plan.empty() || !(kernel > 0.0)) return yaw;
  constexpr double kStep = 0.01 * kPi / 180.0;
  const int n = static_cast<int>(std::floor(half_window / kStep));
  double best_v = -1.0, best = yaw;
  int best_abs = 0;
  for (int k = -n; k <= n; ++k) {
    const double y = yaw + k * kStep;
    double v = 0.0;
    for (const auto& [th, l] : od) {
      for (const auto& [ph, L] : plan) {
        double d = std::fmod(th + y - ph, kPi);
        if (d < 0.0) d += kPi;
        d = std::min(d, kPi - d);  // circular distance in [0, pi/2]
        if (d < kernel) v += l * L * (1.0 - d / kernel);
      }
    }
    if (v > best_v + 1e-12 * std::max(1.0, best_v) || (std::abs(v - best_v) <= 1e-12 * std::max(1.0, best_v) && std::abs(k) < best_abs)) {
      best_v = v;
      best = y;
      best_abs = std::abs(k);
    }
  }
  return best_v > 0.0 ? best : yaw;
}

PlanOrientationCache make_plan_orientation_cache(const OrientationParams& params,
                                                 const std::vector<Segment2>& plan_segments) {
  PlanOrientationCache c;
  c.directions = distinct_directions(plan_segments);
  c.histogram = direction_histogram(plan_segments, params.histogram_bins);
  c.principal_rad = principal_orientation_rad(plan_segments);
  for (double v : c.histogram) c.has_segments = c.has_segments || v > 0.0;
  return c;
}

std::vector<double> orientation_candidates(const OrientationParams& params, const PlanOrientationCache& plan,
                                           const std::vector<Segment2>& obs) {
  if (params.mode == OrientationMode::kDense) return dense_candidates(params.dense_step_deg);
  const std::vector<double> obs_hist = direction_histogram(obs, params.histogram_bins);
  bool obs_has = false;
  for (double v : obs_hist) obs_has = obs_has || v > 0.0;
  if (!obs_has || !plan.has_segments) return dense_candidates(params.dense_step_deg);

  std::vector<double> out;
  if (params.mode == OrientationMode::kPalms) {
    const double obs_principal = principal_orientation_rad(obs);
    // The smallest rotation (in [-45, 45) deg) taking the observation's principal orientation
    // onto the plan's; the other three are its multiples of 90 deg.
    double theta = std::fmod(plan.principal_rad - obs_principal, 0.5 * kPi);
    if (theta < -0.25 * kPi) theta += 0.5 * kPi;
    if (theta >= 0.25 * kPi) theta -= 0.5 * kPi;
    if (params.refine) {
      theta = refine_orientation(plan.directions, obs, theta, 1.0 * kPi / 180.0, 0.5 * kPi / 180.0);
    }
    for (int k = 0; k < 4; ++k) out.push_back(wrap_2pi(theta + k * 0.5 * kPi));
    return out;
  }
  // PALMS+: shifts of the observation histogram that best match the plan's.
  const int B = params.histogram_bins;
  const std::vector<double> corr = circular_correlation(plan.histogram, obs_hist);
  const int half = std::max(1, params.num_orientations / 2);
  const std::vector<int> peaks = circular_peaks(corr, params.nms_radius_bins, half);
  std::vector<double> yaws;
  for (int p : peaks) {
    double y = kPi * p / B;
    // One bin either way covers the quantisation of both histograms.
    if (params.refine) y = refine_orientation(plan.directions, obs, y, kPi / B, 0.5 * kPi / B);
    yaws.push_back(y);
  }
  for (double y : yaws) out.push_back(wrap_2pi(y));
  for (double y : yaws) out.push_back(wrap_2pi(y + kPi));
  return out;
}

std::vector<double> orientation_candidates(const OrientationParams& params, const std::vector<Segment2>& plan_segments,
                                           const std::vector<Segment2>& obs_segments) {
  return orientation_candidates(params, make_plan_orientation_cache(params, plan_segments), obs_segments);
}

}  // namespace floorcast

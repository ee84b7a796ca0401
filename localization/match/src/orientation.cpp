#include "floorcast/match/orientation.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/core/params.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace floorcast {
double wrap_2pi(double a) {
  a = std::fmod(a, 2.0 * kPi);
  if (a < 0.0) a += 2.0 * kPi;
  if (a >= 2.0 * kPi) a -= 2.0 * kPi;
  return a;
}

namespace {

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

const FieldList<OrientationParams>& orientation_fields() {
  using P = OrientationParams;
  static const FieldList<P> f =
      FieldList<P>("orientation")
          .choice("orientations", &P::mode, orientation_mode_names(),
                  "orientation candidates: PALMS principal orientation, PALMS+ histogram correlation, or dense")
          .integer("num_orientations", &P::num_orientations, 2, 720,
                   "PALMS+ O: candidates (O/2 histogram peaks + complements; PALMS+ sec. 3.3: 10)")
          .integer("histogram_bins", &P::histogram_bins, 4, 3600, "direction histogram bins over [0, 180) deg (PALMS+ code: 360)")
          .integer("nms_radius_bins", &P::nms_radius_bins, 0, 1800, "NMS radius on the circular correlation, bins (PALMS+ code: 10)")
          .number("dense_step_deg", &P::dense_step_deg, 0.1, 180.0, "dense mode step, deg (F3Loc: 10)")
          .flag("refine_orientations", &P::refine, "refine each candidate to the best-aligning yaw within one bin");
  return f;
}

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

std::vector<double> main_wall_directions_deg(const std::vector<double>& histogram, int nms_radius_bins, double min_share) {
  const int B = static_cast<int>(histogram.size());
  std::vector<double> out;
  if (B == 0) return out;
  const std::vector<int> peaks = circular_peaks(histogram, nms_radius_bins, B);
  for (int p : peaks) {
    if (histogram[static_cast<std::size_t>(p)] < min_share * histogram[static_cast<std::size_t>(peaks.front())]) continue;
    out.push_back(180.0 * (p + 0.5) / B);
  }
  return out;
}

std::vector<std::string> orientation_notes(const OrientationParams& params, const std::vector<double>& plan_histogram) {
  if (params.mode == OrientationMode::kDense) return {};
  // palms+ tests num_orientations / 2 alignments of the observation with the plan; PALMS'
  // candidates (its principal orientation plus quarter turns) cover one direction and its
  // perpendicular.
  const std::vector<double> main = main_wall_directions_deg(plan_histogram, params.nms_radius_bins);
  const int tested = params.mode == OrientationMode::kPalmsPlus ? std::max(1, params.num_orientations / 2) : 2;
  if (static_cast<int>(main.size()) <= tested) return {};
  std::ostringstream list;
  for (std::size_t i = 0; i < main.size(); ++i) list << (i ? ", " : "") << std::lround(main[i]);
  std::ostringstream note;
  if (params.mode == OrientationMode::kPalmsPlus) {
    note << "the plan's walls run in " << main.size() << " main directions (" << list.str()
         << " deg, each with at least 10% of the largest one's length); orientations palms+ with num_orientations "
         << params.num_orientations << " tests " << tested
         << " alignments per observation, so some observers' true headings are not tested and cannot be localised "
            "(the angled archetype: 22-26% of points); num_orientations "
         << 2 * main.size() << " or more, or orientations dense, tests them all";
  } else {
    note << "the plan's walls run in " << main.size() << " main directions (" << list.str()
         << " deg); orientations palms assumes one direction and its perpendicular, so observers facing the others' "
            "walls are not tested at their true heading; orientations palms+ or dense test them";
  }
  return {note.str()};
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

namespace {

/// Python's divmod for floats (Objects/floatobject.c float_divmod): (a // b, a % b).
std::pair<double, double> python_divmod(double a, double b) {
  double mod = std::fmod(a, b);
  double div = (a - mod) / b;
  if (mod != 0.0) {
    if ((b < 0) != (mod < 0)) {
      mod += b;
      div -= 1.0;
    }
  } else {
    mod = std::copysign(0.0, b);
  }
  double floordiv;
  if (div != 0.0) {
    floordiv = std::floor(div);
    if (div - floordiv > 0.5) floordiv += 1.0;
  } else {
    floordiv = std::copysign(0.0, a / b);
  }
  return {floordiv, mod};
}

/// np.radians(x): x * (pi / 180).
double np_radians(double deg) { return deg * (kPi / 180.0); }

/// PALMS get_segment_orientations: atan2 folded into [-pi/2, pi/2].
double palms_orientation(const Segment2& s) {
  double o = std::atan2(s.b_m.y() - s.a_m.y(), s.b_m.x() - s.a_m.x());
  if (o < -kPi / 2) {
    o += kPi;
  } else if (o > kPi / 2) {
    o -= kPi;
  }
  return o;
}

/// PALMS angular_diff: |a - b| folded into [0, pi], after both are taken mod 2 pi (np.mod).
double palms_angular_diff(double a, double b) {
  a = python_divmod(a, 2 * kPi).second;
  b = python_divmod(b, 2 * kPi).second;
  double d = std::abs(a - b);
  if (d > kPi) d = 2 * kPi - d;
  return d;
}

}  // namespace

std::array<double, 2> palms_principal_orientations(const std::vector<Segment2>& segments, int num_bins,
                                                   double threshold) {
  std::vector<double> ori, len;
  for (const Segment2& s : segments) {
    ori.push_back(palms_orientation(s));
    len.push_back(std::sqrt((s.a_m.x() - s.b_m.x()) * (s.a_m.x() - s.b_m.x()) + (s.a_m.y() - s.b_m.y()) * (s.a_m.y() - s.b_m.y())));
  }
  std::vector<double> bins(static_cast<std::size_t>(num_bins), 0.0);
  const double step = 180.0 / num_bins;
  for (int k = 0; k < num_bins; ++k) {
    const double delta = k * step;  // np.arange(0, 180, 180 / num_bins)
    const double theta = -kPi / 2 + np_radians(delta);
    double t1 = theta - threshold, t2 = theta + threshold;
    if (t1 < -kPi / 2) t1 = python_divmod(t1, -kPi / 2).first * (kPi / 2) - python_divmod(t1, kPi / 2).second;
    if (t2 > kPi / 2) t2 = python_divmod(t2, kPi / 2).first * (-kPi / 2) + python_divmod(t2, kPi / 2).second;
    for (std::size_t i = 0; i < ori.size(); ++i)
      if (t1 <= ori[i] && ori[i] <= t2) bins[static_cast<std::size_t>(k)] += len[i];
  }
  double best = 0.0, best_score = 0.0;
  for (int i1 = 0; i1 < num_bins / 2 + num_bins % 2; ++i1) {
    const int i2 = static_cast<int>(python_divmod(i1 + 90.0 / step, num_bins).second);
    const double score = bins[static_cast<std::size_t>(i1)] + bins[static_cast<std::size_t>(i2)];
    if (score > best_score) {
      best = np_radians(i1 * step) - kPi / 2;
      best_score = score;
    }
  }
  double ortho = best + kPi / 2;
  if (ortho > kPi / 2) ortho = python_divmod(ortho, kPi / 2).first * (-kPi / 2) + python_divmod(ortho, kPi / 2).second;
  return {best, ortho};
}

double palms_landscape_rotation_rad(const std::vector<Segment2>& segments) {
  if (segments.empty()) return 0.0;
  const double original = palms_principal_orientations(segments, 360, np_radians(0.5))[1];
  double theta = 0.0 - original;  // get_R_from_orientations(original, 0)
  auto span = [&](double t, double& sx, double& sy) {
    const double c = std::cos(t), s = std::sin(t);
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (const Segment2& seg : segments)
      for (const Vec2& p : {seg.a_m, seg.b_m}) {
        const double x = c * p.x() - s * p.y(), y = s * p.x() + c * p.y();
        x0 = std::min(x0, x);
        x1 = std::max(x1, x);
        y0 = std::min(y0, y);
        y1 = std::max(y1, y);
      }
    sx = x1 - x0;
    sy = y1 - y0;
  };
  double sx = 0.0, sy = 0.0;
  span(theta, sx, sy);
  if (sy > sx) {
    double final_orientation = kPi / 2;
    if (palms_angular_diff(original, kPi / 2) > kPi / 2) final_orientation *= -1;
    theta = final_orientation - original;
  }
  return theta;
}

}  // namespace floorcast

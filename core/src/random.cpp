#include "floorcast/core/random.hpp"
#include "floorcast/core/math.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace floorcast {

double normal_quantile(double u) {
  // Acklam's rational approximation (relative error 1.15e-9) refined by one Halley step on
  // erfc, which brings it to full double precision.
  static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                             1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                             6.680131188771972e+01,  -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                             -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                             3.754408661907416e+00};
  if (!(u > 0.0)) return -INFINITY;
  if (!(u < 1.0)) return INFINITY;
  const double plow = 0.02425, phigh = 1.0 - plow;
  double x;
  if (u < plow) {
    const double q = std::sqrt(-2.0 * std::log(u));
    x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  } else if (u <= phigh) {
    const double q = u - 0.5, r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
  } else {
    const double q = std::sqrt(-2.0 * std::log(1.0 - u));
    x = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  }
  const double e = 0.5 * std::erfc(-x / std::sqrt(2.0)) - u;
  const double g = e * std::sqrt(2.0 * kPi) * std::exp(0.5 * x * x);
  return x - g / (1.0 + 0.5 * x * g);
}

namespace {

std::array<float, detail::kNormalTableCells + 1> make_table() {
  std::array<float, detail::kNormalTableCells + 1> z{};
  for (int k = 0; k <= detail::kNormalTableCells; ++k) {
    const double u = std::clamp(static_cast<double>(k) / detail::kNormalTableCells, 3.17e-5, 1.0 - 3.17e-5);
    z[static_cast<std::size_t>(k)] = static_cast<float>(normal_quantile(u));
  }
  return z;
}

const std::array<float, detail::kNormalTableCells + 1> g_table = make_table();

}  // namespace

const float* const detail::normal_quantile_table = g_table.data();

}  // namespace floorcast

// Constants and small numeric helpers shared by every floorcast component (one copy each).
#pragma once

#include <vector>

namespace floorcast {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2.0 * kPi;

constexpr double deg_to_rad(double deg) { return deg * (kPi / 180.0); }
constexpr double rad_to_deg(double rad) { return rad * (180.0 / kPi); }

/// Median of the values (mean of the two middle ones for an even count); 0 for none.
double median(std::vector<double> values);

/// Quantile q in [0, 1] of the values by linear interpolation between order statistics
/// (position q (n - 1) in the sorted values: numpy's default); NaN values are left out (ordering
/// them is undefined); 0 when no value is left.
double quantile(std::vector<double> values, double q);

}  // namespace floorcast

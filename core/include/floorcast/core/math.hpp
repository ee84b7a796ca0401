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

}  // namespace floorcast

// Number formatting for messages, tables and reports (one copy each).
#pragma once

#include <string>

namespace floorcast {

/// Fixed-point with `decimals` digits after the point ("%.*f"), e.g. format_fixed(0.5, 2) = "0.50".
std::string format_fixed(double value, int decimals);

/// Shortest general form with up to `precision` significant digits (iostream default style),
/// e.g. format_general(0.25) = "0.25", format_general(1e-7) = "1e-07".
std::string format_general(double value, int precision = 6);

}  // namespace floorcast

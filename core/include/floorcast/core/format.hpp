// Number and text formatting for messages, tables, reports and SVG/HTML (one copy each).
#pragma once

#include <string>

namespace floorcast {

/// Fixed-point with `decimals` digits after the point ("%.*f"), e.g. format_fixed(0.5, 2) = "0.50".
std::string format_fixed(double value, int decimals);

/// Shortest general form with up to `precision` significant digits (iostream default style),
/// e.g. format_general(0.25) = "0.25", format_general(1e-7) = "1e-07".
std::string format_general(double value, int precision = 6);

/// Text safe inside XML/HTML elements and attribute values: & < > " ' escaped, control
/// characters other than tab shown as spaces.
std::string xml_escape(const std::string& text);

}  // namespace floorcast

#include "floorcast/core/format.hpp"

#include <cstdio>
#include <sstream>

namespace floorcast {

std::string format_fixed(double value, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, value);
  return buf;
}

std::string format_general(double value, int precision) {
  std::ostringstream os;
  os.precision(precision);
  os << value;
  return os.str();
}

}  // namespace floorcast

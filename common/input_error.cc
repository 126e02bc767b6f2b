#include "common/input_error.h"

#include <cmath>
#include <sstream>

namespace trackbed {

std::string excerpt(const std::string& value) {
  if (value.size() <= 80) return value;
  return value.substr(0, 60) + "... (" + std::to_string(value.size()) + " characters)";
}

void check_range(const std::string& what, double v, double lo, double hi) {
  if (std::isfinite(v) && v >= lo && v <= hi) return;
  std::ostringstream s;
  s << what << " = " << v << " is out of range; valid: [" << lo << ", " << hi << "]";
  throw InputError(s.str());
}

}  // namespace trackbed

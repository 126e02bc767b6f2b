#include "common/input_error.h"

#include <cmath>
#include <sstream>

namespace trackbed {

void check_range(const std::string& what, double v, double lo, double hi) {
  if (std::isfinite(v) && v >= lo && v <= hi) return;
  std::ostringstream s;
  s << what << " = " << v << " is out of range; valid: [" << lo << ", " << hi << "]";
  throw InputError(s.str());
}

}  // namespace trackbed

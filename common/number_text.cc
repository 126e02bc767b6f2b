#include "common/number_text.h"

#include <charconv>
#include <sstream>

namespace trackbed {

std::string number_text(double value, int significant_digits) {
  std::ostringstream s;
  s.precision(significant_digits);
  s << value;
  return s.str();
}

std::string exact_number_text(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

}  // namespace trackbed

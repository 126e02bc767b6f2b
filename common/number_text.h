// The one way trackbed writes a number into a message or a text file: the shortest general
// notation with the given significant digits (as printf's %g), e.g. 0.35, 1e-06, 2650.
#pragma once

#include <string>

namespace trackbed {

std::string number_text(double value, int significant_digits = 6);

// The shortest text that reads back as exactly `value` (std::to_chars): for values a file stores
// and a later run compares, e.g. a zone's thresholds.
std::string exact_number_text(double value);

}  // namespace trackbed

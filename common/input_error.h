// The one exception type for bad input, shared by every part of trackbed (DEM, FE, coupling,
// cases). Its message is the single line a user sees: what is wrong, where (file and line,
// parameter, or particle), and what would be valid. The trackbed executable turns it into that
// line on standard error and exit code 2.
#pragma once

#include <stdexcept>
#include <string>

namespace trackbed {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

// "FILE:LINE: message" -- the form compilers use, so editors can jump to it.
inline InputError input_error_at(const std::string& file, int line, const std::string& message) {
  return InputError(file + ":" + std::to_string(line) + ": " + message);
}

// A value quoted in an error message: itself, or its first 60 characters and its length when it
// is longer than 80 (a message stays one readable line whatever the input).
std::string excerpt(const std::string& value);

// Throws InputError("<what> = <value> is out of range; valid: [lo, hi]") unless v is finite and
// in [lo, hi].
void check_range(const std::string& what, double v, double lo, double hi);

}  // namespace trackbed

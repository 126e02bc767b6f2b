// The one exception type for bad input. Its message is the single line a user sees: what is
// wrong, where (file and line, parameter, or particle), and what would be valid.
#pragma once

#include <stdexcept>
#include <string>

namespace trackbed::dem {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

// "FILE:LINE: message" -- the form compilers use, so editors can jump to it.
inline InputError input_error_at(const std::string& file, int line, const std::string& message) {
  return InputError(file + ":" + std::to_string(line) + ": " + message);
}

}  // namespace trackbed::dem

// The exceptions of the continuum tier. Their messages are the single line a user sees: what is
// wrong, where (file, parameter, material or boundary), and what would be valid. Bad input (a
// missing or malformed mesh, an unknown material or boundary id, a non-physical parameter) is
// trackbed's one InputError, as in every other part.
#pragma once

#include <stdexcept>
#include <string>

#include "common/input_error.h"

namespace trackbed::fem {

// A linear solver that did not reach its tolerance.
class SolverError : public std::runtime_error {
 public:
  explicit SolverError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace trackbed::fem

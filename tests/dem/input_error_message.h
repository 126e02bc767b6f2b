// What the tests of refused input share: the message of the refusal, to check that it says what
// is wrong, where and what is valid.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "common/input_error.h"

namespace trackbed::dem::testing {

// The message of the InputError that `call` throws; fails the test if it throws none.
template <typename Call>
std::string input_error_message(Call&& call) {
  try {
    call();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError thrown";
  return "";
}

inline bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace trackbed::dem::testing

// Catching the errors of bad input in tests: InputErrorOf(f) returns the InputError that `f`
// throws (file, line, column, key, message), OptionsErrorOf(f) the OptionsProblem of a
// OptionsError. Both fail the test when `f` throws nothing or something else.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

#include <catch2/catch.hpp>

#include "common/error.h"

namespace corridorsim::test {

template <class F>
InputError InputErrorOf(F&& f) {
  try {
    std::forward<F>(f)();
  } catch (const InputError& e) {
    return e;
  }
  FAIL("no InputError thrown");
  throw std::logic_error("unreachable");  // FAIL aborts the test case
}

template <class F>
OptionsProblem OptionsErrorOf(F&& f) {
  try {
    std::forward<F>(f)();
  } catch (const OptionsError& e) {
    return e.problem();
  }
  FAIL("no OptionsError thrown");
  throw std::logic_error("unreachable");
}

/// True when `text` contains `part` (for checking the gist of a message).
inline bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace corridorsim::test

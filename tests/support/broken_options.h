// Breaking options structs in tests (STYLE.md 4: each has a Check() that names the first wrong
// key): the problem Check() finds in the defaults changed one way (ProblemOf), and a table of such
// changes with the key each must name (CheckEachBrokenOption).
#pragma once

#include <vector>

#include <catch2/catch.hpp>

#include "common/error.h"

namespace corridorsim::test {

/// The problem Check() reports for the default options changed by `change`; fails the test when
/// there is none.
template <class Options, class Change>
OptionsProblem ProblemOf(const Change& change) {
  Options options;
  change(options);
  const auto problem = options.Check();
  REQUIRE(problem);
  return *problem;
}

/// One way to break options: the change to the defaults, and the key whose problem Check() must
/// report first.
template <class Options>
struct BrokenOption {
  void (*change)(Options&);
  const char* key;
};

/// Check() passes the default options, and reports each case's key (with a message) first for
/// the defaults changed by the case's change.
template <class Options>
void CheckEachBrokenOption(const std::vector<BrokenOption<Options>>& cases) {
  CHECK_FALSE(Options{}.Check());
  for (const BrokenOption<Options>& c : cases) {
    INFO("expected a problem at " << c.key);
    const OptionsProblem problem = ProblemOf<Options>(c.change);
    CHECK(problem.key == c.key);
    CHECK_FALSE(problem.message.empty());
  }
}

}  // namespace corridorsim::test

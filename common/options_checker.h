#pragma once
// The `Check()` helper of options structs (STYLE item 4): it keeps the first failed requirement,
// in the order the checks are written, as a OptionsProblem {key, message}.

#include <cstdio>
#include <optional>
#include <string>

#include "common/error.h"

namespace corridorsim {

/// A number as a short human-readable string ("%g"), for messages.
inline std::string FormatNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g", v);
  return buf;
}

class OptionsChecker {
 public:
  void Require(bool ok, const std::string& key, const std::string& message) {
    if (!ok && !problem_) problem_ = OptionsProblem{key, message};
  }
  void Positive(double v, const std::string& key) {
    Require(v > 0, key, "must be greater than 0 (got " + FormatNumber(v) + ")");
  }
  void NonNegative(double v, const std::string& key) {
    Require(v >= 0, key, "must not be negative (got " + FormatNumber(v) + ")");
  }
  /// lo <= v <= hi (the upper bound keeps sizes where the generators' cost stays sane).
  void InRange(double v, double lo, double hi, const std::string& key) {
    Require(v >= lo && v <= hi, key,
            "must lie in [" + FormatNumber(lo) + ", " + FormatNumber(hi) + "] (got " +
                FormatNumber(v) + ")");
  }
  void Fraction(double v, const std::string& key) {
    Require(v >= 0 && v <= 1, key, "must lie in [0, 1] (got " + FormatNumber(v) + ")");
  }
  const std::optional<OptionsProblem>& problem() const { return problem_; }

 private:
  std::optional<OptionsProblem> problem_;
};

}  // namespace corridorsim

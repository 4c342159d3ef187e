#pragma once
// Walks an options table (common/options_table.h) and breaks every bound of every number field,
// one at a time: the options' Check() must then name that field's key and give the value it got.

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>

#include <catch2/catch.hpp>

#include "common/error.h"
#include "common/options_table.h"

namespace corridorsim::test {

namespace option_bounds_detail {

inline void SetNumber(const OptionField& f, void* object, double v) {
  void* p = f.member(object);
  switch (f.kind) {
    case OptionKind::kDouble:
      *static_cast<double*>(p) = v;
      break;
    case OptionKind::kFloat:
      *static_cast<float*>(p) = static_cast<float>(v);
      break;
    case OptionKind::kInt:
      *static_cast<int*>(p) = static_cast<int>(v);
      break;
    case OptionKind::kInt64:
      *static_cast<std::int64_t*>(p) = static_cast<std::int64_t>(v);
      break;
    case OptionKind::kUInt64:
      *static_cast<std::uint64_t*>(p) = static_cast<std::uint64_t>(v);
      break;
    default:
      FAIL("not a number field: " << f.key);
  }
}

// A value the field's type holds that breaks `b`, or nothing.
inline std::optional<double> Outside(const OptionField& f, const OptionBound& b) {
  const auto fits = [&](double v) {
    if (!std::isfinite(v) || b.Holds(v)) return false;
    switch (f.kind) {
      case OptionKind::kInt:
        return v >= std::numeric_limits<int>::min() && v <= std::numeric_limits<int>::max();
      case OptionKind::kInt64:
        return std::abs(v) < 9e18;
      case OptionKind::kUInt64:
        return v >= 0 && v < 1.8e19;
      default:
        return true;
    }
  };
  const double step_lo = std::max(1.0, std::abs(b.lo)), step_hi = std::max(1.0, std::abs(b.hi));
  for (const double v : {b.lo_strict ? b.lo : b.lo - step_lo, b.hi_strict ? b.hi : b.hi + step_hi,
                         b.lo - 0.5, b.hi + 0.5}) {
    if (fits(v)) return v;
  }
  return std::nullopt;
}

}  // namespace option_bounds_detail

/// For every bound of every number field of `table` (sections and named sections included) on
/// `object`: breaks it alone, runs `check` (the options' whole Check(), on the object that holds
/// `object`), and requires the problem at `prefix` + the field's key with "got <value>" in its
/// message; then restores the field. `object` must pass `check` as it is.
inline void CheckEveryBoundNamesKeyAndValue(
    const OptionTableBase& table, void* object, const std::string& prefix,
    const std::function<std::optional<OptionsProblem>()>& check) {
  using option_bounds_detail::Outside;
  using option_bounds_detail::SetNumber;
  REQUIRE_FALSE(check());
  for (const OptionField& f : table.fields()) {
    if (f.is_number()) {
      const double original = f.Number(object);
      for (const OptionBound& b : f.bounds) {
        const std::optional<double> v = Outside(f, b);
        if (!v) continue;
        SetNumber(f, object, *v);
        const std::optional<OptionsProblem> problem = check();
        SetNumber(f, object, original);
        INFO(prefix + f.key << " = " << *v);
        REQUIRE(problem);
        CHECK(problem->key == prefix + f.key);
        CHECK_THAT(problem->message, Catch::Contains("got "));
      }
    } else if (f.kind == OptionKind::kSection) {
      CheckEveryBoundNamesKeyAndValue(*f.table, f.member(object),
                                      f.key.empty() ? prefix : prefix + f.key + ".", check);
    } else if (f.kind == OptionKind::kNamedSections) {
      for (std::size_t i = 0; i < f.count(object); ++i) {
        void* element = f.element(object, i);
        const std::string at =
            prefix + (f.key.empty() ? "" : f.key + ".") + f.element_name(element) + ".";
        CheckEveryBoundNamesKeyAndValue(*f.table, element, at, check);
      }
    }
  }
}

}  // namespace corridorsim::test

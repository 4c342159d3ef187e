// Tests common/options_table.cpp: table-driven bound checks (messages as OptionsChecker writes
// them, keys of sections and named sections, table order) and the docs text of bounds.
#include "common/options_table.h"

#include <limits>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

namespace corridorsim {
namespace {

enum class Colour { kRed, kBlue };

struct Inner {
  double size_m = 1.0;
  int count = 2;
};

struct Outer {
  double rate_hz = 10.0;
  double jitter = 0.1;
  Colour colour = Colour::kRed;
  Inner inner;
  std::vector<Inner> named = {Inner{}, Inner{}};
};

const OptionTable<Inner>& InnerTable() {
  static const OptionTable<Inner> table = [] {
    OptionTable<Inner> t;
    t.Add("size_m", &Inner::size_m, "m", "a size").Greater(0).Range(0, 5);
    t.Add("count", &Inner::count, "", "a count").AtLeast(0, "must not be negative");
    return t;
  }();
  return table;
}

const OptionTable<Outer>& OuterTable() {
  static const OptionTable<Outer> table = [] {
    OptionTable<Outer> t;
    t.Add("rate_hz", &Outer::rate_hz, "Hz", "a rate").RangeOpenLow(0, 1000, "(0, 1000] Hz ({})");
    t.Add("jitter", &Outer::jitter, "", "a fraction").RangeOpenHigh(0, 0.5).Note("< rate_hz");
    t.AddEnum("colour", &Outer::colour, {{"red", Colour::kRed}, {"blue", Colour::kBlue}},
              "a colour");
    t.AddSection("inner", &Outer::inner, InnerTable(), "a section");
    t.AddNamedSections(
        "", &Outer::named, InnerTable(),
        [](const Inner& i) { return std::string(i.count == 2 ? "a" : "b0"); }, "named");
    return t;
  }();
  return table;
}

TEST_CASE("bound problems read as OptionsChecker's messages", "[options]") {
  Outer o;
  CHECK_FALSE(CheckOptionBounds(OuterTable(), o));
  o.inner.size_m = -2.5;
  auto p = CheckOptionBounds(OuterTable(), o);
  REQUIRE(p);
  CHECK(p->key == "inner.size_m");
  CHECK(p->message == "must be greater than 0 (got -2.5)");
  o.inner.size_m = 7;
  CHECK(CheckOptionBounds(OuterTable(), o)->message == "must lie in [0, 5] (got 7)");
  o.inner.size_m = 1;
  o.jitter = 0.5;
  CHECK(CheckOptionBounds(OuterTable(), o)->message == "must lie in [0, 0.5) (got 0.5)");
  o.jitter = 0.1;
  o.rate_hz = 0;
  CHECK(CheckOptionBounds(OuterTable(), o)->message == "(0, 1000] Hz (0)");
  o.rate_hz = 10;
  o.named[0].count = -1;
  p = CheckOptionBounds(OuterTable(), o);
  REQUIRE(p);
  CHECK(p->key == "b0.count");
  // A message of its own without "{}" gives the value too.
  CHECK(p->message == "must not be negative (got -1)");
}

TEST_CASE("the first problem in table order is reported", "[options]") {
  Outer o;
  o.inner.size_m = 0;
  o.rate_hz = -1;
  CHECK(CheckOptionBounds(OuterTable(), o)->key == "rate_hz");
}

TEST_CASE("the docs show the intersection of a field's bounds and its note", "[options]") {
  const std::vector<OptionField>& outer = OuterTable().fields();
  CHECK(OptionBoundsText(outer[0]) == "(0, 1000]");
  CHECK(OptionBoundsText(outer[1]) == "[0, 0.5); < rate_hz");
  const std::vector<OptionField>& inner = InnerTable().fields();
  CHECK(OptionBoundsText(inner[0]) == "(0, 5]");
  CHECK(OptionBoundsText(inner[1]) == ">= 0");
}

TEST_CASE("standard messages for one-sided bounds", "[options]") {
  OptionBound b;
  b.lo = 0.1;
  CHECK(b.Message("0") == "must be at least 0.1 (got 0)");
  b.lo = 0;
  CHECK(b.Message("-1") == "must not be negative (got -1)");
  OptionBound h;
  h.hi = 3;
  h.hi_strict = true;
  CHECK_FALSE(h.Holds(3));
  CHECK(h.Message("3") == "must be less than 3 (got 3)");
}

// A duration whose 0 means "off" and whose other values must not round to 0 ns.
struct Timed {
  double duration_s = 0.0;
};

const OptionTable<Timed>& TimedTable() {
  static const OptionTable<Timed> table = [] {
    OptionTable<Timed> t;
    t.Add("duration_s", &Timed::duration_s, "s", "0 = off").ZeroOr(1e-3, 1e6);
    return t;
  }();
  return table;
}

TEST_CASE("a ZeroOr bound passes 0 and its interval, nothing between or beyond", "[options]") {
  Timed o;
  for (const double ok : {0.0, 1e-3, 1.0, 1e6}) {
    o.duration_s = ok;
    CHECK_FALSE(CheckOptionBounds(TimedTable(), o));
  }
  for (const double bad :
       {1e-12, -1e-12, 5e-4, -1.0, 1e6 * (1 + 1e-12), 1e300,
        std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    o.duration_s = bad;
    const auto p = CheckOptionBounds(TimedTable(), o);
    REQUIRE(p);
    CHECK(p->key == "duration_s");
  }
  o.duration_s = 1e-12;
  CHECK(CheckOptionBounds(TimedTable(), o)->message ==
        "must be 0 or lie in [0.001, 1e+06] (got 1e-12)");
  CHECK(OptionBoundsText(TimedTable().fields()[0]) == "0 or [0.001, 1e+06]");
}

}  // namespace
}  // namespace corridorsim

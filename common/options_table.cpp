#include "common/options_table.h"

#include <cmath>

#include "common/options_checker.h"

namespace corridorsim {
namespace {

const auto& Num = FormatNumber;  // "%g", as OptionsChecker's messages

std::string Interval(const OptionBound& b) {
  return std::string(b.lo_strict ? "(" : "[") + Num(b.lo) + ", " + Num(b.hi) +
         (b.hi_strict ? ")" : "]");
}

std::string Join(const std::string& prefix, const std::string& key) {
  if (prefix.empty()) return key;
  if (key.empty()) return prefix;
  return prefix + "." + key;
}

std::optional<OptionsProblem> CheckFields(const OptionTableBase& table, const void* object,
                                          const std::string& prefix) {
  for (const OptionField& f : table.fields()) {
    if (f.is_number()) {
      const double v = f.Number(object);
      for (const OptionBound& b : f.bounds) {
        if (b.Holds(v)) continue;
        const std::string text =
            f.is_integer() ? std::to_string(static_cast<long long>(v)) : Num(v);
        return OptionsProblem{Join(prefix, f.key), b.Message(text)};
      }
    } else if (f.kind == OptionKind::kSection) {
      const void* section = f.member(const_cast<void*>(object));
      std::optional<OptionsProblem> p =
          f.check ? f.check(section) : CheckFields(*f.table, section, "");
      if (p) return OptionsProblem{Join(Join(prefix, f.key), p->key), p->message};
    } else if (f.kind == OptionKind::kNamedSections) {
      for (std::size_t i = 0; i < f.count(object); ++i) {
        const void* e = f.element(const_cast<void*>(object), i);
        const std::string at = Join(Join(prefix, f.key), f.element_name(e));
        if (auto p = CheckFields(*f.table, e, at)) return p;
      }
    }
  }
  return std::nullopt;
}

}  // namespace

bool OptionBound::Holds(double v) const {
  if (or_zero && v == 0) return true;
  const bool above = lo_strict ? v > lo : v >= lo;
  const bool below = hi_strict ? v < hi : v <= hi;
  return above && below;  // false for NaN
}

std::string OptionBound::Message(const std::string& value) const {
  if (!message.empty()) {
    // Every bound message gives the value: where the text has no place for it, it follows.
    std::string m = message;
    if (const auto at = m.find("{}"); at != std::string::npos) return m.replace(at, 2, value);
    return m + " (got " + value + ")";
  }
  const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  std::string what;
  if (or_zero) {
    what = "must be 0 or lie in " + Interval(*this);
  } else if (has_lo && has_hi) {
    what = "must lie in " + Interval(*this);
  } else if (has_lo) {
    what = lo_strict ? "must be greater than " + Num(lo)
           : lo == 0 ? std::string("must not be negative")
                     : "must be at least " + Num(lo);
  } else {
    what = (hi_strict ? "must be less than " : "must be at most ") + Num(hi);
  }
  return what + " (got " + value + ")";
}

double OptionField::Number(const void* object) const {
  void* p = member(const_cast<void*>(object));
  switch (kind) {
    case OptionKind::kDouble:
      return *static_cast<const double*>(p);
    case OptionKind::kFloat:
      return *static_cast<const float*>(p);
    case OptionKind::kInt:
      return *static_cast<const int*>(p);
    case OptionKind::kInt64:
      return static_cast<double>(*static_cast<const std::int64_t*>(p));
    case OptionKind::kUInt64:
      return static_cast<double>(*static_cast<const std::uint64_t*>(p));
    default:
      return 0.0;
  }
}

OptionField& OptionField::Greater(double lo, std::string message) {
  bounds.push_back({lo, std::numeric_limits<double>::infinity(), true, false, std::move(message)});
  return *this;
}

OptionField& OptionField::AtLeast(double lo, std::string message) {
  bounds.push_back({lo, std::numeric_limits<double>::infinity(), false, false, std::move(message)});
  return *this;
}

OptionField& OptionField::AtMost(double hi, std::string message) {
  bounds.push_back(
      {-std::numeric_limits<double>::infinity(), hi, false, false, std::move(message)});
  return *this;
}

OptionField& OptionField::Range(double lo, double hi, std::string message) {
  bounds.push_back({lo, hi, false, false, std::move(message)});
  return *this;
}

OptionField& OptionField::RangeOpenHigh(double lo, double hi, std::string message) {
  bounds.push_back({lo, hi, false, true, std::move(message)});
  return *this;
}

OptionField& OptionField::RangeOpenLow(double lo, double hi, std::string message) {
  bounds.push_back({lo, hi, true, false, std::move(message)});
  return *this;
}

OptionField& OptionField::ZeroOr(double lo, double hi, std::string message) {
  OptionBound b{lo, hi, false, false, std::move(message)};
  b.or_zero = true;
  bounds.push_back(std::move(b));
  return *this;
}

OptionField& OptionField::Note(std::string bounds_text) {
  bounds_note = std::move(bounds_text);
  return *this;
}

std::optional<OptionsProblem> CheckOptionBounds(const OptionTableBase& table, const void* object) {
  return CheckFields(table, object, "");
}

std::string OptionBoundsText(const OptionField& field) {
  std::string text;
  if (!field.bounds.empty()) {
    // The intersection of the bounds: the values that pass every check (0 among them when every
    // bound lets it pass).
    OptionBound all;
    bool zero = true, or_zero = false;
    for (const OptionBound& b : field.bounds) {
      zero = zero && b.Holds(0.0);
      or_zero = or_zero || b.or_zero;
      if (b.lo > all.lo || (b.lo == all.lo && b.lo_strict))
        all.lo = b.lo, all.lo_strict = b.lo_strict;
      if (b.hi < all.hi || (b.hi == all.hi && b.hi_strict))
        all.hi = b.hi, all.hi_strict = b.hi_strict;
    }
    const bool has_lo = std::isfinite(all.lo), has_hi = std::isfinite(all.hi);
    if (has_lo && has_hi) {
      text = (or_zero && zero && !all.Holds(0.0) ? "0 or " : "") + Interval(all);
    } else if (has_lo) {
      text = (all.lo_strict ? "> " : ">= ") + Num(all.lo);
    } else if (has_hi) {
      text = (all.hi_strict ? "< " : "<= ") + Num(all.hi);
    }
  }
  if (!field.bounds_note.empty()) text += (text.empty() ? "" : "; ") + field.bounds_note;
  return text;
}

}  // namespace corridorsim

#pragma once
// Enum <-> name tables, one per enum: the names outputs write (events.json, ground_truth.json,
// metrics keys) and input reads. A table lists every enumerator once, so adding one means adding
// its name in one place.

#include <cstddef>
#include <string>
#include <string_view>

namespace corridorsim {

template <class E>
struct EnumName {
  E value;
  std::string_view name;
};

/// The name of `value` ("unknown" for a value the table lacks: a bug its tests catch).
template <class E, std::size_t N>
std::string NameOf(const EnumName<E> (&names)[N], E value) {
  for (const EnumName<E>& n : names) {
    if (n.value == value) return std::string(n.name);
  }
  return "unknown";
}

}  // namespace corridorsim

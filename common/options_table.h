#pragma once
// Options declared once (STYLE item 4; COLMAP's OptionManager, Cartographer's options
// dictionaries): each options struct has one OptionTable listing every key with its member, unit,
// bounds and a one-line doc. Parsing and the echoed resolved scenario (common/io/options_yaml.h),
// the bound checks (CheckOptionBounds, here) and the key tables of docs/scenarios.md all come from
// it, so a key can never be documented but not read, or read but not documented.
//
// A table is built once per struct by a function returning a static const table:
//
//   const OptionTable<DoorOptions>& DoorOptionsTable() {
//     return StaticOptionTable<DoorOptions>([](OptionTable<DoorOptions>& t) {
//       t.Add("width_m", &DoorOptions::width_m, "m", "clear opening").Greater(0).Range(0, 5);
//     });
//   }
//
// Defaults are those of the struct's default-constructed object (or its container's). Rules that
// relate several fields stay in the struct's Check(), which runs CheckOptionBounds first.

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "common/enum_names.h"
#include "common/error.h"

namespace corridorsim {

class YamlMap;            // common/io/yaml_reader.h: what custom fields' parse hooks read
class OptionsYamlWriter;  // common/io/options_yaml.h: what custom fields' echo hooks write to

enum class OptionKind {
  kDouble,
  kFloat,
  kInt,
  kInt64,
  kUInt64,
  kBool,
  kString,
  kEnum,
  kDoubleList,
  kSection,        // a member struct with its own table, under its key ("" = inline, same map)
  kNamedSections,  // a std::vector of structs, each under its own name ("" = in this map)
  kCustom,         // parse, echo and doc hooks (keys whose meaning depends on each other)
};

/// A bound on a numeric field: lo < v or lo <= v, v < hi or v <= hi (either side may be open).
struct OptionBound {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_strict = false;  // v > lo rather than v >= lo
  bool hi_strict = false;  // v < hi rather than v <= hi
  // The problem's message; "{}" stands for the value, and without one " (got <value>)" follows
  // it. Empty: the standard message ("must be greater than 0 (got -1)", "must lie in [0, 5]
  // (got 7)", ...).
  std::string message;
  bool or_zero = false;  // 0 passes too (0 = off or automatic; the interval bounds the rest)

  bool Holds(double v) const;
  std::string Message(const std::string& value) const;
};

/// One row of a docs key table.
struct OptionDocRow {
  std::string key, unit, default_value, bounds, doc;
};

class OptionTableBase;

/// One key of a table. The accessors take the containing object as void*; OptionTable<T> builds
/// them from a member pointer (or a lambda T& -> member&), so they are never written by hand.
struct OptionField {
  std::string key;
  OptionKind kind = OptionKind::kDouble;
  std::string unit;                 // "m", "Hz", "deg", "px", ... ("" for none)
  std::string doc;                  // one line for the docs table
  std::vector<OptionBound> bounds;  // checked in this order; the first that fails is reported
  std::string bounds_note;          // bounds Check() tests across fields, for the docs

  std::function<void*(void*)> member;  // the member (its type by kind); not for kEnum, kCustom
  std::vector<std::string> choices;    // kEnum: the names, in order
  std::function<int(const void*)> get_choice;  // kEnum: index of the value in choices
  std::function<void(void*, int)> set_choice;  // kEnum
  const OptionTableBase* table = nullptr;      // kSection, kNamedSections: the struct's table
  // kSection: the struct's whole Check() (bounds and its own cross-field rules), else its bounds.
  std::function<std::optional<OptionsProblem>(const void*)> check;
  // kNamedSections: the vector's size, its element i, an element's name.
  std::function<std::size_t(const void*)> count;
  std::function<void*(void*, std::size_t)> element;
  std::function<std::string(const void*)> element_name;
  // kCustom: reads its keys from the map of the containing object, writes them, documents them.
  std::function<void(YamlMap&, void*)> parse;
  std::function<void(const void*, OptionsYamlWriter&)> echo;
  std::function<std::vector<OptionDocRow>(const void*)> doc_rows;

  bool is_integer() const {
    return kind == OptionKind::kInt || kind == OptionKind::kInt64 || kind == OptionKind::kUInt64;
  }
  bool is_number() const {
    return is_integer() || kind == OptionKind::kDouble || kind == OptionKind::kFloat;
  }
  /// The numeric value of a number field of `object`.
  double Number(const void* object) const;

  // Bounds, in the order they are checked. `message` as in OptionBound.
  OptionField& Greater(double lo, std::string message = "");                   // v > lo
  OptionField& AtLeast(double lo, std::string message = "");                   // v >= lo
  OptionField& AtMost(double hi, std::string message = "");                    // v <= hi
  OptionField& Range(double lo, double hi, std::string message = "");          // [lo, hi]
  OptionField& RangeOpenHigh(double lo, double hi, std::string message = "");  // [lo, hi)
  OptionField& RangeOpenLow(double lo, double hi, std::string message = "");   // (lo, hi]
  /// v == 0 or lo <= v <= hi: a value whose 0 means off or automatic, and whose other values
  /// must keep away from 0 (a duration that would round to 0 ns, a size of 1 px).
  OptionField& ZeroOr(double lo, double hi, std::string message = "");  // 0 or [lo, hi]
  /// Bounds that Check() tests because they depend on other fields (docs only).
  OptionField& Note(std::string bounds_text);
};

class OptionTableBase {
 public:
  const std::vector<OptionField>& fields() const { return fields_; }

 protected:
  std::vector<OptionField> fields_;
};

namespace detail {
template <class M>
constexpr OptionKind OptionKindOf() {
  if constexpr (std::is_same_v<M, double>) {
    return OptionKind::kDouble;
  } else if constexpr (std::is_same_v<M, float>) {
    return OptionKind::kFloat;
  } else if constexpr (std::is_same_v<M, int>) {
    return OptionKind::kInt;
  } else if constexpr (std::is_same_v<M, std::int64_t>) {
    return OptionKind::kInt64;
  } else if constexpr (std::is_same_v<M, std::uint64_t>) {
    return OptionKind::kUInt64;
  } else if constexpr (std::is_same_v<M, bool>) {
    return OptionKind::kBool;
  } else if constexpr (std::is_same_v<M, std::string>) {
    return OptionKind::kString;
  } else {
    static_assert(std::is_same_v<M, std::vector<double>>, "no option kind for this member type");
    return OptionKind::kDoubleList;
  }
}
}  // namespace detail

/// The table of options struct T. `access` is a member pointer (&T::width_m) or a lambda
/// returning a reference to the member (for members of members: [](T& t) -> auto& { ... }).
/// Each Add returns the new field, to chain its bounds; it stays valid until the next Add.
template <class T>
class OptionTable : public OptionTableBase {
  template <class Access>
  using Member = std::remove_reference_t<std::invoke_result_t<Access, T&>>;

 public:
  template <class Access>
  OptionField& Add(std::string key, Access access, std::string unit, std::string doc) {
    using M = Member<Access>;
    OptionField& f =
        New(std::move(key), detail::OptionKindOf<M>(), std::move(unit), std::move(doc));
    f.member = Pointer(access);
    return f;
  }

  /// An enum member and its names: {{"straight", Layout::kStraight}, ...}.
  template <class Access>
  OptionField& AddEnum(std::string key, Access access,
                       std::vector<std::pair<std::string, Member<Access>>> choices,
                       std::string doc) {
    using E = Member<Access>;
    OptionField& f = New(std::move(key), OptionKind::kEnum, "", std::move(doc));
    std::vector<E> values;
    for (auto& [name, value] : choices) {
      f.choices.push_back(name);
      values.push_back(value);
    }
    f.get_choice = [access, values](const void* object) {
      const E v = std::invoke(access, *static_cast<T*>(const_cast<void*>(object)));
      for (std::size_t i = 0; i < values.size(); ++i) {
        if (values[i] == v) return static_cast<int>(i);
      }
      return -1;
    };
    f.set_choice = [access, values](void* object, int i) {
      std::invoke(access, *static_cast<T*>(object)) = values.at(static_cast<std::size_t>(i));
    };
    return f;
  }

  /// An enum member named by its enum's name table (common/enum_names.h).
  template <class Access, std::size_t N>
  OptionField& AddEnum(std::string key, Access access, const EnumName<Member<Access>> (&names)[N],
                       std::string doc) {
    std::vector<std::pair<std::string, Member<Access>>> choices;
    for (const auto& n : names) choices.emplace_back(std::string(n.name), n.value);
    return AddEnum(std::move(key), access, std::move(choices), std::move(doc));
  }

  /// A member struct with its own table under `key` ("" reads its keys from this map). `check`
  /// (the struct's Check()) replaces its bound checks where the struct has rules of its own.
  template <class Access, class S>
  OptionField& AddSection(std::string key, Access access, const OptionTable<S>& table,
                          std::string doc,
                          std::optional<OptionsProblem> (S::*check)() const = nullptr) {
    static_assert(std::is_same_v<Member<Access>, S>);
    OptionField& f = New(std::move(key), OptionKind::kSection, "", std::move(doc));
    f.member = Pointer(access);
    f.table = &table;
    if (check) {
      f.check = [check](const void* s) { return (static_cast<const S*>(s)->*check)(); };
    }
    return f;
  }

  /// A std::vector<S> member whose elements sit under their names (`name(element)`) in the map
  /// under `key` ("" = in this map). The elements come from the defaults; a name that no element
  /// has is an unknown key.
  template <class Access, class S, class Name>
  OptionField& AddNamedSections(std::string key, Access access, const OptionTable<S>& table,
                                Name name, std::string doc) {
    static_assert(std::is_same_v<Member<Access>, std::vector<S>>);
    OptionField& f = New(std::move(key), OptionKind::kNamedSections, "", std::move(doc));
    f.table = &table;
    f.count = [access](const void* object) {
      return std::invoke(access, *static_cast<T*>(const_cast<void*>(object))).size();
    };
    f.element = [access](void* object, std::size_t i) -> void* {
      return &std::invoke(access, *static_cast<T*>(object)).at(i);
    };
    f.element_name = [name](const void* element) {
      return std::string(name(*static_cast<const S*>(element)));
    };
    return f;
  }

  /// Keys handled by hooks: `parse` reads them from the containing map (it must ask for each key
  /// it accepts), `echo` writes them, `doc_rows` documents them (one row per key).
  OptionField& AddCustom(std::string key, std::string doc, std::function<void(YamlMap&, T&)> parse,
                         std::function<void(const T&, OptionsYamlWriter&)> echo,
                         std::function<std::vector<OptionDocRow>(const T&)> doc_rows) {
    OptionField& f = New(std::move(key), OptionKind::kCustom, "", std::move(doc));
    f.parse = [parse](YamlMap& map, void* object) { parse(map, *static_cast<T*>(object)); };
    f.echo = [echo](const void* object, OptionsYamlWriter& out) {
      echo(*static_cast<const T*>(object), out);
    };
    f.doc_rows = [doc_rows](const void* object) {
      return doc_rows(*static_cast<const T*>(object));
    };
    return f;
  }

 private:
  template <class Access>
  static std::function<void*(void*)> Pointer(Access access) {
    return
        [access](void* object) -> void* { return &std::invoke(access, *static_cast<T*>(object)); };
  }

  OptionField& New(std::string key, OptionKind kind, std::string unit, std::string doc) {
    OptionField& f = fields_.emplace_back();
    f.key = std::move(key);
    f.kind = kind;
    f.unit = std::move(unit);
    f.doc = std::move(doc);
    return f;
  }
};

/// The table `build` fills, built on first use and kept: the body of a XxxOptionsTable() function
/// (each lambda has its own type, so each call site its own table).
template <class T, class Build>
const OptionTable<T>& StaticOptionTable(Build build) {
  static const OptionTable<T> table = [&] {
    OptionTable<T> t;
    build(t);
    return t;
  }();
  return table;
}

/// The first bound that a field of `object` (recursively, sections included) breaks, with its key
/// relative to the table's struct ("doors.width_m", "front.noise.rgb.exposure"), in table order.
std::optional<OptionsProblem> CheckOptionBounds(const OptionTableBase& table, const void* object);

template <class T>
std::optional<OptionsProblem> CheckOptionBounds(const OptionTable<T>& table, const T& object) {
  return CheckOptionBounds(static_cast<const OptionTableBase&>(table), &object);
}

/// A field's bounds for the docs: "> 0", "[0, 5]", "(0, 1000]", "0 or [1, 10]", the note, or "".
std::string OptionBoundsText(const OptionField& field);

}  // namespace corridorsim

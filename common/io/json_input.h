#pragma once
// Reading JSON that a user hands in (a dataset's files, detections): parse errors and every
// missing or mistyped field become an InputError naming the file and the field's path
// (`.images[3].width`), so that the command exits 2 with one clear message.

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace corridorsim {

/// Throws InputError at (file, field).
[[noreturn]] void FailInFile(const std::string& file, const std::string& field,
                             const std::string& message);

/// Bounds of a JSON document a user hands in, checked before it is parsed (CheckJsonInputBounds),
/// so that a hostile file can neither exhaust the stack nor memory: nesting (arrays and objects
/// inside each other) as the scenario loader bounds YAML, and values (every object, array,
/// string, number and literal, object keys included). A parsed value costs up to about 100 bytes
/// of memory, so kMaxJsonValues keeps a document under about 1 GB.
inline constexpr int kMaxJsonDepth = 64;
inline constexpr std::size_t kMaxJsonValues = 10'000'000;

/// Scans `text` (the contents of `file`) without parsing it: more than kMaxJsonDepth nested
/// arrays and objects, or more than `max_values` values (in the whole document, or with
/// `per_element` in each element of a top-level array), throws InputError at the line and column
/// where the bound is passed. Malformed text is left to the parser.
void CheckJsonInputBounds(std::string_view text, const std::string& file, std::size_t max_values,
                          bool per_element = false);

/// Parses `text` (the contents of `file`) after CheckJsonInputBounds; malformed JSON throws
/// InputError naming the byte.
nlohmann::ordered_json ParseJsonInput(std::string_view text, const std::string& file,
                                      std::size_t max_values = kMaxJsonValues);

/// Parses a document whose top level is an array one element at a time: `each(index, element)`
/// gets every element as soon as it is parsed, which is then dropped, so that memory holds one
/// element (of at most kMaxJsonValues values) however long the array. A top level that is not
/// an array throws InputError at `file` with `not_array`; bounds and malformed JSON as
/// ParseJsonInput (elements before a syntax error have been handed to `each`).
void ParseJsonArrayInput(
    std::string_view text, const std::string& file, const std::string& not_array,
    const std::function<void(std::size_t, const nlohmann::ordered_json&)>& each);

/// Typed access to a value of a parsed document, with the value's path in every message.
/// `file` and `value` must outlive it.
struct JsonField {
  const std::string& file;
  std::string path;
  const nlohmann::ordered_json& value;

  [[noreturn]] void Fail(const std::string& message) const;
  JsonField At(const char* key) const;    // missing: InputError
  JsonField At(std::size_t index) const;  // of an array; out of range: InputError
  bool Has(const char* key) const { return value.contains(key); }
  double Number() const;           // finite
  std::int64_t Integer() const;    // fits an int64
  std::uint64_t Unsigned() const;  // a non-negative integer that fits a uint64
  std::string String() const;
  bool Bool() const;
  std::size_t ArraySize() const;  // the value must be an array
  template <std::size_t N>
  std::array<double, N> Numbers() const {
    if (!value.is_array() || value.size() != N) {
      Fail("expected an array of " + std::to_string(N) + " numbers");
    }
    std::array<double, N> out{};
    for (std::size_t i = 0; i < N; ++i) out[i] = At(i).Number();
    return out;
  }
};

}  // namespace corridorsim

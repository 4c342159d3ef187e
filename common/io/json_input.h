#pragma once
// Reading JSON that a user hands in (a dataset's files, detections): parse errors and every
// missing or mistyped field become an InputError naming the file and the field's path
// (`.images[3].width`), so that the command exits 2 with one clear message.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace corridorsim {

/// Throws InputError at (file, field).
[[noreturn]] void FailInFile(const std::string& file, const std::string& field,
                             const std::string& message);

/// Parses `text` (the contents of `file`); malformed JSON throws InputError naming the byte.
nlohmann::ordered_json ParseJsonInput(std::string_view text, const std::string& file);

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

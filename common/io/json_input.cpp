#include "common/io/json_input.h"

#include <cmath>
#include <limits>

#include "common/error.h"

namespace corridorsim {

using Json = nlohmann::ordered_json;

void FailInFile(const std::string& file, const std::string& field, const std::string& message) {
  throw InputError(SourceLocation{file, 0, 0}, field, message);
}

Json ParseJsonInput(std::string_view text, const std::string& file) {
  try {
    return Json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    // nlohmann's message repeats the byte; ours names it once.
    std::string what = e.what();
    const std::size_t colon = what.rfind(": ");
    if (colon != std::string::npos) what = what.substr(colon + 2);
    FailInFile(file, "", "malformed JSON at byte " + std::to_string(e.byte) + ": " + what);
  } catch (const nlohmann::json::exception& e) {
    // Numbers a double cannot hold (1e999: JSON has no infinities) and the like.
    std::string what = e.what();
    const std::size_t bracket = what.find("] ");
    if (bracket != std::string::npos) what = what.substr(bracket + 2);
    FailInFile(file, "", "malformed JSON: " + what);
  }
}

void JsonField::Fail(const std::string& message) const { FailInFile(file, path, message); }

JsonField JsonField::At(const char* key) const {
  if (!value.is_object()) Fail("expected an object (got " + std::string(value.type_name()) + ")");
  if (!value.contains(key)) FailInFile(file, path + "." + key, "missing");
  return JsonField{file, path + "." + key, value[key]};
}

JsonField JsonField::At(std::size_t index) const {
  const std::string at = path + "[" + std::to_string(index) + "]";
  if (!value.is_array() || index >= value.size()) FailInFile(file, at, "missing");
  return JsonField{file, at, value[index]};
}

double JsonField::Number() const {
  if (!value.is_number()) Fail("expected a number (got " + std::string(value.type_name()) + ")");
  const double v = value.get<double>();
  if (!std::isfinite(v)) Fail("not a finite number");
  return v;
}

std::int64_t JsonField::Integer() const {
  if (!value.is_number_integer()) {
    Fail("expected an integer (got " + std::string(value.type_name()) + ")");
  }
  if (value.is_number_unsigned() &&
      value.get<std::uint64_t>() > std::uint64_t(std::numeric_limits<std::int64_t>::max())) {
    Fail("too large");
  }
  return value.get<std::int64_t>();
}

std::uint64_t JsonField::Unsigned() const {
  if (!value.is_number_integer()) {
    Fail("expected an integer (got " + std::string(value.type_name()) + ")");
  }
  if (!value.is_number_unsigned() && value.get<std::int64_t>() < 0) Fail("negative");
  return value.get<std::uint64_t>();
}

std::string JsonField::String() const {
  if (!value.is_string()) Fail("expected a string (got " + std::string(value.type_name()) + ")");
  return value.get<std::string>();
}

bool JsonField::Bool() const {
  if (!value.is_boolean())
    Fail("expected true or false (got " + std::string(value.type_name()) + ")");
  return value.get<bool>();
}

std::size_t JsonField::ArraySize() const {
  if (!value.is_array()) Fail("expected an array (got " + std::string(value.type_name()) + ")");
  return value.size();
}

}  // namespace corridorsim

#include "common/io/json_input.h"

#include <cmath>
#include <limits>

#include "common/error.h"

namespace corridorsim {

using Json = nlohmann::ordered_json;

void FailInFile(const std::string& file, const std::string& field, const std::string& message) {
  throw InputError(SourceLocation{file, 0, 0}, field, message);
}

namespace {

// Json::parse with `callback` (may be empty); nlohmann's errors become InputError at `file`.
Json ParseWith(std::string_view text, const std::string& file,
               const Json::parser_callback_t& callback) {
  try {
    return Json::parse(text, callback);
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

}  // namespace

void CheckJsonInputBounds(std::string_view text, const std::string& file, std::size_t max_values,
                          bool per_element) {
  int depth = 0, line = 1;
  std::size_t line_start = 0, values = 0;
  bool in_string = false, escaped = false, in_scalar = false;
  const auto fail = [&](std::size_t at, const std::string& message) {
    throw InputError(SourceLocation{file, line, static_cast<int>(at - line_start + 1)}, "",
                     message);
  };
  // A value starts at byte `at`: an element of the top-level array starts a new count.
  const auto count = [&](std::size_t at) {
    if (per_element && depth == 1) values = 0;
    if (++values > max_values) {
      fail(at, "more than " + std::to_string(max_values) + " values" +
                   (per_element ? " in one element of the top-level array" : "") +
                   " (numbers, strings, arrays and objects)");
    }
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      line_start = i + 1;
    }
    if (in_string) {
      if (escaped) {
        escaped = false;
      } else if (c == '\\') {
        escaped = true;
      } else if (c == '"') {
        in_string = false;
      }
      continue;
    }
    switch (c) {
      case '"':
        in_scalar = false;
        in_string = true;
        count(i);
        break;
      case '[':
      case '{':
        in_scalar = false;
        count(i);
        if (++depth > kMaxJsonDepth) {
          fail(i, "more than " + std::to_string(kMaxJsonDepth) + " nested arrays and objects");
        }
        break;
      case ']':
      case '}':
        in_scalar = false;
        if (depth > 0) --depth;
        break;
      case ',':
      case ':':
      case ' ':
      case '\t':
      case '\r':
      case '\n':
        in_scalar = false;
        break;
      default:  // a number or literal (or text the parser refuses)
        if (!in_scalar) count(i);
        in_scalar = true;
    }
  }
}

Json ParseJsonInput(std::string_view text, const std::string& file, std::size_t max_values) {
  CheckJsonInputBounds(text, file, max_values);
  return ParseWith(text, file, nullptr);
}

void ParseJsonArrayInput(
    std::string_view text, const std::string& file, const std::string& not_array,
    const std::function<void(std::size_t, const nlohmann::ordered_json&)>& each) {
  CheckJsonInputBounds(text, file, kMaxJsonValues, /*per_element=*/true);
  std::size_t index = 0;
  // Depth 0 is the top level, 1 its elements: each element is handed over when it ends and
  // dropped (returning false discards it, and nlohmann removes it from the array).
  const Json::parser_callback_t callback = [&](int depth, Json::parse_event_t event, Json& parsed) {
    using Event = Json::parse_event_t;
    if (depth == 0 && (event == Event::object_start || event == Event::value)) {
      FailInFile(file, "", not_array);
    }
    if (depth == 1 &&
        (event == Event::value || event == Event::object_end || event == Event::array_end)) {
      each(index++, parsed);
      return false;
    }
    return true;
  };
  ParseWith(text, file, callback);
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

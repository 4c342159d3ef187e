// YamlMap::ReadJson (common/io/yaml_reader.h): any YAML value as typed JSON, for options passed on
// as given (an external pipeline's `options:`, docs/protocol.md).

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>

#include "common/error.h"
#include "common/io/yaml_reader.h"

namespace corridorsim {

namespace {

// A plain YAML scalar as JSON: YAML 1.2's core schema (null, booleans, integers, floats), else
// the text as a string. Empty with *non_finite when it is .inf or .nan.
nlohmann::ordered_json PlainScalarJson(const std::string& text, bool* non_finite) {
  if (text.empty() || text == "~" || text == "null" || text == "Null" || text == "NULL") {
    return nullptr;
  }
  if (text == "true" || text == "True" || text == "TRUE") return true;
  if (text == "false" || text == "False" || text == "FALSE") return false;
  const char* begin = text.data();
  const char* end = begin + text.size();
  const char* digits = *begin == '+' ? begin + 1 : begin;
  std::int64_t integer = 0;
  if (auto [ptr, ec] = std::from_chars(digits, end, integer); ec == std::errc() && ptr == end) {
    return integer;
  }
  std::string lower = text;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const char* special : {".inf", "+.inf", "-.inf", ".nan"}) {
    if (lower == special) {
      *non_finite = true;
      return nullptr;
    }
  }
  double number = 0;
  if (auto [ptr, ec] = std::from_chars(digits, end, number);
      ec == std::errc() && ptr == end && std::isfinite(number) &&
      text.find_first_of("0123456789") != std::string::npos) {
    return number;
  }
  return text;
}

}  // namespace

bool YamlMap::ReadJson(const std::string& key, nlohmann::ordered_json& value) {
  const YAML::Node node = Get(key);
  if (!node) return false;
  // The document's own bounds (kMaxYamlNodes, kMaxYamlDepth) bound this recursion.
  const std::function<nlohmann::ordered_json(const YAML::Node&)> convert =
      [&](const YAML::Node& n) -> nlohmann::ordered_json {
    if (n.IsMap()) {
      nlohmann::ordered_json object = nlohmann::ordered_json::object();
      for (const auto& kv : n) {
        if (!kv.first.IsScalar()) {
          throw InputError(doc_->LocationOf(kv.first), KeyExcerpt(FullKey(key)),
                           "a key must be a plain string");
        }
        object[kv.first.Scalar()] = convert(kv.second);
      }
      return object;
    }
    if (n.IsSequence()) {
      nlohmann::ordered_json array = nlohmann::ordered_json::array();
      for (const auto& item : n) array.push_back(convert(item));
      return array;
    }
    if (n.IsNull()) return nullptr;
    if (n.Tag() == "!") return n.Scalar();  // quoted: a string, whatever it reads like
    bool non_finite = false;
    nlohmann::ordered_json scalar = PlainScalarJson(n.Scalar(), &non_finite);
    if (non_finite) {
      throw InputError(doc_->LocationOf(n), KeyExcerpt(FullKey(key)),
                       "'" + InputExcerpt(n.Scalar()) + "' is not a finite number (JSON has none)");
    }
    return scalar;
  };
  value = convert(node);
  return true;
}

}  // namespace corridorsim

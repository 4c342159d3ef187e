#include "harness/external/reply_values.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "common/io/stable_json.h"
#include "common/io/yaml_reader.h"
#include "harness/external/reply_keys.h"

namespace corridorsim::external::reply_values {

[[noreturn]] void Fail(const std::string& where, const std::string& what) {
  throw ProtocolError(where + ": " + what);
}

std::string Excerpt(const nlohmann::json& value) { return InputExcerpt(JsonText(value), 80); }

const nlohmann::json* Find(const nlohmann::json& object, const char* key) {
  const auto it = object.find(key);
  return it == object.end() || it->is_null() ? nullptr : &*it;
}

double Number(const nlohmann::json& value, const std::string& where) {
  if (!value.is_number()) Fail(where, "expected a number, got " + Excerpt(value));
  const double v = value.get<double>();
  if (!std::isfinite(v)) Fail(where, "a non-finite number (" + Excerpt(value) + ")");
  return v;
}

std::int64_t Integer(const nlohmann::json& value, const std::string& where, std::int64_t lo,
                     std::int64_t hi) {
  if (!value.is_number_integer()) Fail(where, "expected an integer, got " + Excerpt(value));
  if (value.is_number_unsigned() &&
      value.get<std::uint64_t>() >
          static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
    Fail(where, "out of range (" + Excerpt(value) + ")");
  }
  const std::int64_t v = value.get<std::int64_t>();
  if (v < lo || v > hi) {
    Fail(where, "must lie in [" + std::to_string(lo) + ", " + std::to_string(hi) + "] (got " +
                    std::to_string(v) + ")");
  }
  return v;
}

bool Boolean(const nlohmann::json& value, const std::string& where) {
  if (!value.is_boolean()) Fail(where, "expected true or false, got " + Excerpt(value));
  return value.get<bool>();
}

std::string String(const nlohmann::json& value, const std::string& where, std::size_t max_bytes) {
  if (!value.is_string()) Fail(where, "expected a string, got " + Excerpt(value));
  const std::string& s = value.get_ref<const std::string&>();
  if (s.size() > max_bytes) Fail(where, "longer than " + std::to_string(max_bytes) + " bytes");
  return s;
}
const nlohmann::json& Array(const nlohmann::json& value, const std::string& where,
                            std::size_t max_items) {
  if (!value.is_array()) Fail(where, "expected an array, got " + Excerpt(value));
  if (value.size() > max_items) {
    Fail(where, "more than " + std::to_string(max_items) + " items (" +
                    std::to_string(value.size()) + ")");
  }
  return value;
}

Eigen::Matrix3d Matrix3(const nlohmann::json& value, const std::string& where) {
  const Eigen::Matrix<double, 9, 1> v = Vector<9>(value, where);
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m(r, c) = v[3 * r + c];
  }
  return m;
}
void OnlyKeys(const nlohmann::json& object, const std::string& where,
              std::initializer_list<const char*> known) {
  if (!object.is_object()) Fail(where, "expected an object, got " + Excerpt(object));
  const std::vector<std::string> keys(known.begin(), known.end());
  for (const auto& [key, value] : object.items()) {
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
      throw ProtocolError(UnknownKeyText(where, key, keys));
    }
  }
}

}  // namespace corridorsim::external::reply_values

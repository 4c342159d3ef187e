#pragma once
// The checks of the JSON values in a program's replies (docs/protocol.md): each names where the
// value is ("estimate.pose[2]") and what is wrong with it, by throwing ProtocolError. Shared by
// the reply readers (replies.cpp); not part of the protocol's interface (protocol.h).

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <utility>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "harness/external/protocol.h"

namespace corridorsim::external::reply_values {

[[noreturn]] void Fail(const std::string& where, const std::string& what);

// A JSON value's text for a message: short and printable.
std::string Excerpt(const nlohmann::json& value);

// `object[key]` unless it is absent or null.
const nlohmann::json* Find(const nlohmann::json& object, const char* key);

// A finite number.
double Number(const nlohmann::json& value, const std::string& where);
// An integer in [lo, hi].
std::int64_t Integer(const nlohmann::json& value, const std::string& where, std::int64_t lo,
                     std::int64_t hi);
bool Boolean(const nlohmann::json& value, const std::string& where);
// A string of at most `max_bytes`.
std::string String(const nlohmann::json& value, const std::string& where, std::size_t max_bytes);
// An array of at most `max_items`.
const nlohmann::json& Array(const nlohmann::json& value, const std::string& where,
                            std::size_t max_items);
// 9 finite numbers, row-major.
Eigen::Matrix3d Matrix3(const nlohmann::json& value, const std::string& where);

// Checks that `object` has only keys of `known` (a typo in a reply is a bug to report, not a
// field to drop silently): the message names the key and every valid key.
void OnlyKeys(const nlohmann::json& object, const std::string& where,
              std::initializer_list<const char*> known);

// One of two names (a string of at most 32 bytes) as its value: "expected <a> or <b>" else.
template <class E>
E OneOf(const nlohmann::json& value, const std::string& where, std::pair<const char*, E> a,
        std::pair<const char*, E> b) {
  const std::string name = String(value, where, 32);
  if (name == a.first) return a.second;
  if (name == b.first) return b.second;
  Fail(where, std::string("expected ") + a.first + " or " + b.first);
}

// The items of the array `object[key]`, when it is there (at most `max_items`): calls
// `parse(item, "<where>[i]")` for each.
template <class F>
void ForEachItem(const nlohmann::json& object, const char* key, const std::string& where,
                 std::size_t max_items, F parse) {
  if (const nlohmann::json* list = Find(object, key)) {
    Array(*list, where, max_items);
    for (std::size_t i = 0; i < list->size(); ++i) {
      parse((*list)[i], where + "[" + std::to_string(i) + "]");
    }
  }
}

template <int N>
Eigen::Matrix<double, N, 1> Vector(const nlohmann::json& value, const std::string& where) {
  if (!value.is_array() || value.size() != N) {
    Fail(where, "expected " + std::to_string(N) + " numbers, got " + Excerpt(value));
  }
  Eigen::Matrix<double, N, 1> v;
  for (int i = 0; i < N; ++i) v[i] = Number(value[i], where + "[" + std::to_string(i) + "]");
  return v;
}

}  // namespace corridorsim::external::reply_values

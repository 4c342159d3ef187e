#include "common/io/yaml_reader.h"

#include <charconv>
#include <cmath>
#include <limits>

#include "common/io/input_text.h"

// The strict reading of a document's keys into options structs (YamlMap), and where each key was
// set (SourceMap). The documents themselves: yaml_document.cpp; files and include chains:
// yaml_includes.cpp.

namespace corridorsim {

void SourceMap::Record(const std::string& key, const SourceLocation& location) {
  locations_[key] = location;
}

SourceLocation SourceMap::Find(const std::string& key, const SourceLocation& fallback) const {
  std::string k = key;
  while (true) {
    if (auto it = locations_.find(k); it != locations_.end()) return it->second;
    const auto dot = k.rfind('.');
    if (dot == std::string::npos) return fallback;
    k.resize(dot);
  }
}

YamlMap::YamlMap(const YamlDocument& doc, YAML::Node node, std::string key_prefix,
                 SourceMap* sources)
    : doc_(&doc), node_(std::move(node)), prefix_(std::move(key_prefix)), sources_(sources) {}

std::string YamlMap::FullKey(const std::string& key) const {
  return prefix_.empty() ? key : prefix_ + "." + key;
}

SourceLocation YamlMap::Location() const { return doc_->LocationOf(node_); }

SourceLocation YamlMap::LocationOfKey(const std::string& key) const {
  if (node_.IsMap()) {
    for (const auto& kv : node_) {
      if (kv.first.IsScalar() && kv.first.Scalar() == key) return doc_->LocationOf(kv.first);
    }
  }
  return Location();
}

bool YamlMap::Has(const std::string& key) const {
  return node_.IsMap() && static_cast<bool>(node_[key]);
}

void YamlMap::Fail(const std::string& key, const std::string& message) const {
  throw InputError(LocationOfKey(key), KeyExcerpt(FullKey(key)), message);
}

YAML::Node YamlMap::Get(const std::string& key) {
  read_keys_.insert(key);
  if (!node_.IsMap()) return YAML::Node();
  const YAML::Node& map = node_;  // const access: a missing key must not be inserted
  YAML::Node value = map[key];
  if (value && sources_) sources_->Record(FullKey(key), LocationOfKey(key));
  return value;
}

void YamlMap::Accept(const std::string& key) { read_keys_.insert(key); }

std::string YamlMap::ScalarOrFail(const std::string& key, const YAML::Node& value,
                                  const char* expected) const {
  if (!value.IsScalar()) {
    Fail(key, std::string("expected ") + expected + ", got " +
                  (value.IsMap()        ? "a map"
                   : value.IsSequence() ? "a list"
                                        : "nothing"));
  }
  return value.Scalar();
}

bool YamlMap::Read(const std::string& key, double& value) {
  const YAML::Node node = Get(key);
  if (!node) return false;
  const std::string text = ScalarOrFail(key, node, "a number");
  double parsed = 0.0;
  if (!YAML::convert<double>::decode(node, parsed) || !std::isfinite(parsed)) {
    Fail(key, "expected a finite number, got '" + InputExcerpt(text) + "'");
  }
  value = parsed;
  return true;
}

template <class Integer>
bool YamlMap::ReadInteger(const std::string& key, Integer& value, const char* what) {
  const YAML::Node node = Get(key);
  if (!node) return false;
  const std::string text = ScalarOrFail(key, node, what);
  Integer parsed = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), parsed);
  if (ec != std::errc() || end != text.data() + text.size()) {
    Fail(key, std::string("expected ") + what + ", got '" + InputExcerpt(text) + "'");
  }
  value = parsed;
  return true;
}

bool YamlMap::Read(const std::string& key, std::int64_t& value) {
  return ReadInteger(key, value, "an integer");
}

bool YamlMap::Read(const std::string& key, int& value) {
  std::int64_t wide = value;
  if (!Read(key, wide)) return false;
  if (wide < std::numeric_limits<int>::min() || wide > std::numeric_limits<int>::max()) {
    Fail(key, "integer " + std::to_string(wide) + " is out of range");
  }
  value = static_cast<int>(wide);
  return true;
}

bool YamlMap::Read(const std::string& key, std::uint64_t& value) {
  return ReadInteger(key, value, "a non-negative integer");
}

bool YamlMap::Read(const std::string& key, bool& value) {
  const YAML::Node node = Get(key);
  if (!node) return false;
  const std::string text = ScalarOrFail(key, node, "true or false");
  if (text == "true") {
    value = true;
  } else if (text == "false") {
    value = false;
  } else {
    Fail(key, "expected true or false, got '" + InputExcerpt(text) + "'");
  }
  return true;
}

bool YamlMap::Read(const std::string& key, std::string& value) {
  const YAML::Node node = Get(key);
  if (!node) return false;
  value = ScalarOrFail(key, node, "a string");
  return true;
}

bool YamlMap::Read(const std::string& key, std::vector<double>& values) {
  const YAML::Node node = Get(key);
  if (!node) return false;
  if (!node.IsSequence()) Fail(key, "expected a list of numbers, e.g. [1.0, 2.0]");
  std::vector<double> parsed;
  for (const auto& item : node) {
    double v = 0.0;
    if (!item.IsScalar() || !YAML::convert<double>::decode(item, v) || !std::isfinite(v)) {
      throw InputError(doc_->LocationOf(item), KeyExcerpt(FullKey(key)),
                       "expected a finite number in the list");
    }
    parsed.push_back(v);
  }
  values = std::move(parsed);
  return true;
}

bool YamlMap::Read(const std::string& key, std::vector<std::vector<double>>& rows,
                   std::size_t columns) {
  const YAML::Node node = Get(key);
  if (!node) return false;
  const std::string example = "expected a list of rows of " + std::to_string(columns) + " numbers";
  if (!node.IsSequence()) Fail(key, example + ", e.g. [[1.0, 2.0, ...], ...]");
  std::vector<std::vector<double>> parsed;
  for (const auto& row : node) {
    const std::string where = "row " + std::to_string(parsed.size() + 1) + ": ";
    if (!row.IsSequence() || row.size() != columns) {
      throw InputError(doc_->LocationOf(row), KeyExcerpt(FullKey(key)), where + example);
    }
    std::vector<double> values;
    for (const auto& item : row) {
      double v = 0.0;
      if (!item.IsScalar() || !YAML::convert<double>::decode(item, v) || !std::isfinite(v)) {
        throw InputError(doc_->LocationOf(item), KeyExcerpt(FullKey(key)),
                         where + "expected a finite number");
      }
      values.push_back(v);
    }
    parsed.push_back(std::move(values));
  }
  rows = std::move(parsed);
  return true;
}

bool YamlMap::Read(const std::string& key, std::vector<std::string>& values,
                   std::vector<SourceLocation>* locations) {
  const YAML::Node node = Get(key);
  if (!node) return false;
  if (!node.IsSequence()) Fail(key, "expected a list of strings, e.g. [\"a\", \"b\"]");
  std::vector<std::string> parsed;
  std::vector<SourceLocation> where;
  for (const auto& item : node) {
    if (!item.IsScalar()) {
      throw InputError(doc_->LocationOf(item), KeyExcerpt(FullKey(key)),
                       "item " + std::to_string(parsed.size() + 1) + ": expected a string");
    }
    parsed.push_back(item.Scalar());
    where.push_back(doc_->LocationOf(item));
  }
  values = std::move(parsed);
  if (locations) *locations = std::move(where);
  return true;
}

std::vector<std::string> YamlMap::Keys() const {
  std::vector<std::string> keys;
  if (!node_.IsMap()) return keys;
  for (const auto& kv : node_) keys.push_back(kv.first.Scalar());
  return keys;
}

YamlMap YamlMap::Map(const std::string& key) {
  // yaml-cpp nodes have reference semantics (assignment writes into the node), so never assign
  // to the result of a lookup: build the returned map from a fresh node instead.
  const YAML::Node node = Get(key);
  if (node && node.IsMap()) return YamlMap(*doc_, node, FullKey(key), sources_);
  // `key:` with nothing after it is an empty section, not an error.
  if (node && !node.IsNull()) Fail(key, "expected a map of keys");
  return YamlMap(*doc_, YAML::Node(YAML::NodeType::Map), FullKey(key), sources_);
}

void YamlMap::RejectUnknownKeys() const {
  if (!node_.IsMap()) return;
  for (const auto& kv : node_) {
    const std::string key = kv.first.Scalar();
    if (!read_keys_.count(key)) {
      std::string known;
      for (const auto& k : read_keys_) known += (known.empty() ? "" : ", ") + k;
      throw InputError(doc_->LocationOf(kv.first), KeyExcerpt(FullKey(key)),
                       "unknown key (known keys here: " + known + ")");
    }
  }
}

}  // namespace corridorsim

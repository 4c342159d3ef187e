#include "common/io/yaml_reader.h"

#include <charconv>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace corridorsim {
namespace {

SourceLocation FromMark(const std::string& file, const YAML::Mark& mark) {
  SourceLocation loc{file, 0, 0};
  if (mark.line >= 0) loc.line = mark.line + 1;  // yaml-cpp marks are 0-based
  if (mark.column >= 0) loc.column = mark.column + 1;
  return loc;
}

// yaml-cpp keeps the first of two equal keys and drops nothing from iteration: walk every map
// and reject a key seen twice.
void RejectDuplicateKeys(const YamlDocument& doc, const YAML::Node& node, const std::string& prefix,
                         int depth) {
  if (depth > 64) {
    throw InputError(doc.LocationOf(node), prefix, "nesting is deeper than 64 levels");
  }
  if (node.IsMap()) {
    std::set<std::string> seen;
    for (const auto& kv : node) {
      const std::string key =
          kv.first.IsScalar() ? kv.first.Scalar() : std::string("<complex key>");
      const std::string full = prefix.empty() ? key : prefix + "." + key;
      if (!seen.insert(key).second) {
        throw InputError(doc.LocationOf(kv.first), full, "duplicate key");
      }
      RejectDuplicateKeys(doc, kv.second, full, depth + 1);
    }
  } else if (node.IsSequence()) {
    std::size_t i = 0;
    for (const auto& item : node) {
      RejectDuplicateKeys(doc, item, prefix + "[" + std::to_string(i++) + "]", depth + 1);
    }
  }
}

YamlDocument Parse(std::istream& in, const std::string& name) {
  YamlDocument doc;
  doc.file = name;
  try {
    doc.root = YAML::Load(in);
  } catch (const YAML::Exception& e) {
    throw InputError(FromMark(name, e.mark), "", "invalid YAML: " + e.msg);
  }
  if (doc.root.IsNull()) doc.root = YAML::Node(YAML::NodeType::Map);  // empty file: all defaults
  if (!doc.root.IsMap()) {
    throw InputError(doc.LocationOf(doc.root), "", "the document must be a map of keys");
  }
  RejectDuplicateKeys(doc, doc.root, "", 0);
  return doc;
}

}  // namespace

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

YamlDocument YamlDocument::Load(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw InputError(SourceLocation{path, 0, 0}, "", "is a folder, not a YAML file");
  }
  std::ifstream in(path);
  if (!in) throw InputError(SourceLocation{path, 0, 0}, "", "cannot open the file");
  return Parse(in, path);
}

YamlDocument YamlDocument::FromString(const std::string& text, const std::string& name) {
  std::istringstream in(text);
  return Parse(in, name);
}

SourceLocation YamlDocument::LocationOf(const YAML::Node& node) const {
  return FromMark(file, node.Mark());
}

std::vector<YamlDocument> LoadWithIncludes(const std::string& path) {
  std::vector<YamlDocument> chain;
  chain.push_back(YamlDocument::Load(path));
  std::set<std::string> visited{std::filesystem::weakly_canonical(path).string()};
  while (true) {
    const YamlDocument& current = chain.back();
    const YAML::Node include = current.root["include"];
    if (!include) break;
    SourceLocation where = current.LocationOf(include);
    if (!include.IsScalar() || include.Scalar().empty()) {
      throw InputError(where, "include", "expected the path of a scenario file");
    }
    std::filesystem::path target(include.Scalar());
    if (target.is_relative()) target = std::filesystem::path(current.file).parent_path() / target;
    if (!std::filesystem::exists(target)) {
      throw InputError(where, "include", "included file '" + target.string() + "' does not exist");
    }
    if (std::filesystem::is_directory(target)) {
      throw InputError(where, "include", "included path '" + target.string() + "' is a folder");
    }
    if (!visited.insert(std::filesystem::weakly_canonical(target).string()).second) {
      throw InputError(where, "include", "include cycle through '" + target.string() + "'");
    }
    chain.push_back(YamlDocument::Load(target.string()));
  }
  return {std::make_move_iterator(chain.rbegin()), std::make_move_iterator(chain.rend())};
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
  throw InputError(LocationOfKey(key), FullKey(key), message);
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
    Fail(key, "expected a finite number, got '" + text + "'");
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
    Fail(key, std::string("expected ") + what + ", got '" + text + "'");
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
    Fail(key, "expected true or false, got '" + text + "'");
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
      throw InputError(doc_->LocationOf(item), FullKey(key),
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
      throw InputError(doc_->LocationOf(row), FullKey(key), where + example);
    }
    std::vector<double> values;
    for (const auto& item : row) {
      double v = 0.0;
      if (!item.IsScalar() || !YAML::convert<double>::decode(item, v) || !std::isfinite(v)) {
        throw InputError(doc_->LocationOf(item), FullKey(key), where + "expected a finite number");
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
      throw InputError(doc_->LocationOf(item), FullKey(key),
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
      throw InputError(doc_->LocationOf(kv.first), FullKey(key),
                       "unknown key (known keys here: " + known + ")");
    }
  }
}

}  // namespace corridorsim

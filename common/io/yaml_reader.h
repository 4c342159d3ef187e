#pragma once
// Strict YAML reading for options structs (STYLE item 4): every key read is recorded with its
// position, unknown and duplicate keys are errors, wrong types are errors, and every error names
// `file:line:column: key`. Options are applied on top of code defaults, so a file only sets what
// it names, and `include:` chains apply base files first.
//
// Three files implement it: yaml_document.cpp (one document: text, bounds, duplicate keys),
// yaml_includes.cpp (files read safely and their include chains), yaml_reader.cpp (YamlMap's
// strict key reading and the SourceMap).

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/io/input_text.h"  // Utf8Length, InputExcerpt: user text in messages

namespace corridorsim {

// Bounds on what one input file can make the reader do (docs/scenarios.md, "Files"). Each is far
// above what a scenario needs (the shipped ones are < 2 KiB, < 300 nodes, < 6 levels deep) and
// low enough that no file within them takes more than a fraction of a second or a few MiB.
inline constexpr std::size_t kMaxYamlFileBytes = std::size_t{1} << 20;  // 1 MiB per file
// Nodes of one document counted as a walk over it sees them: an alias (`*name`) counts every
// node of what it names, so nested aliases ("billion laughs") cannot multiply the work.
inline constexpr std::size_t kMaxYamlNodes = 100000;
// Bytes of scalar text of one document, aliases expanded the same way.
inline constexpr std::size_t kMaxYamlTextBytes = std::size_t{4} << 20;  // 4 MiB
inline constexpr int kMaxYamlDepth = 64;                                // nested maps and lists
inline constexpr int kMaxIncludeChain = 16;  // files in one `include:` chain

/// Where each dotted key (e.g. "world.doors.width_m") was last set, so that a `Check()` problem
/// found after parsing can be reported at the line that caused it.
class SourceMap {
 public:
  void Record(const std::string& key, const SourceLocation& location);
  /// The location of `key`, else of its closest recorded parent, else `fallback`.
  SourceLocation Find(const std::string& key, const SourceLocation& fallback) const;

 private:
  std::map<std::string, SourceLocation> locations_;
};

/// One parsed YAML file. Loading rejects syntax errors and duplicate keys at any depth, and
/// anything outside the bounds above.
struct YamlDocument {
  std::string file;
  YAML::Node root;
  // false for a document built from the command line (`--set KEY=VALUE`): its locations name
  // `file` only, since the line and column of a value's text would point at nothing.
  bool has_positions = true;

  /// Reads `path` once into memory: it must be a regular file of at most kMaxYamlFileBytes (a
  /// FIFO, a device, a folder, a dangling link or a link loop is an error; opening never blocks).
  /// The text must be UTF-8 without control characters and hold one YAML document, a map.
  /// Errors never quote the file's content beyond a short, sanitised key or value.
  static YamlDocument Load(const std::string& path);
  static YamlDocument FromString(const std::string& text, const std::string& name);
  SourceLocation LocationOf(const YAML::Node& node) const;
};

/// Loads `path` and, recursively, the file named by its top-level `include:` key (relative to the
/// including file). Returns the chain base-first, ending with `path` itself. An include that is
/// missing, cyclic, not a regular file (as YamlDocument::Load), or one more than
/// kMaxIncludeChain files deep is an InputError at the `include:` line.
std::vector<YamlDocument> LoadWithIncludes(const std::string& path);

/// A map node being read into an options struct.
class YamlMap {
 public:
  /// `key_prefix` is the dotted path of this map ("" for the document root).
  YamlMap(const YamlDocument& doc, YAML::Node node, std::string key_prefix, SourceMap* sources);

  bool Has(const std::string& key) const;

  /// Reads `key` into `value` if present (returns true); leaves `value` untouched if absent.
  bool Read(const std::string& key, double& value);
  bool Read(const std::string& key, int& value);
  bool Read(const std::string& key, std::int64_t& value);
  bool Read(const std::string& key, std::uint64_t& value);
  bool Read(const std::string& key, bool& value);
  bool Read(const std::string& key, std::string& value);
  /// A list of numbers, e.g. `distortion: [-0.28, 0.07, 0, 0, 0]`.
  bool Read(const std::string& key, std::vector<double>& values);
  /// A list of rows of exactly `columns` numbers each, e.g. `commands: [[2.0, 0.3, 0], [1, 0,
  /// 30]]`; a bad row is an error at that row.
  bool Read(const std::string& key, std::vector<std::vector<double>>& rows, std::size_t columns);

  /// A list of strings, e.g. `expectations: ["odometry.ate_rmse_m < 1"]`, with the location of
  /// each item (for errors found when the items are interpreted).
  bool Read(const std::string& key, std::vector<std::string>& values,
            std::vector<SourceLocation>* locations = nullptr);

  /// Any value (a map, a list, a scalar; nested) as typed JSON, for options passed on as given
  /// (an external pipeline's `options:`): a quoted scalar is a string; a plain one is null (`~`,
  /// `null`), a boolean (`true`, `false`), an integer (fits int64), a finite number, else a
  /// string. A non-finite number (`.inf`, `.nan`) is an error: JSON has none.
  bool ReadJson(const std::string& key, nlohmann::ordered_json& value);

  /// The keys of this map in document order (for maps keyed by name, e.g. `pipelines:`).
  std::vector<std::string> Keys() const;

  /// Reads a string key and maps it through `choices` (name -> value); anything else is an error
  /// that lists the valid names.
  template <class E>
  bool ReadEnum(const std::string& key, E& value,
                const std::vector<std::pair<std::string, E>>& choices) {
    std::string name;
    if (!Read(key, name)) return false;
    std::string valid;
    for (const auto& [choice_name, choice_value] : choices) {
      if (choice_name == name) {
        value = choice_value;
        return true;
      }
      valid += (valid.empty() ? "" : ", ") + choice_name;
    }
    Fail(key, "unknown value '" + InputExcerpt(name) + "' (expected one of: " + valid + ")");
  }

  /// The nested map under `key`; an absent key gives an empty map (nothing overrides defaults).
  YamlMap Map(const std::string& key);

  /// Marks `key` as handled by the caller (e.g. `include`), so it is not reported as unknown.
  void Accept(const std::string& key);

  /// Throws an InputError for the first key (in document order) that no Read/Map/Accept asked for.
  void RejectUnknownKeys() const;

  /// Throws an InputError for `key` (at the key if present, else at this map); the key is put
  /// into the message through InputExcerpt.
  [[noreturn]] void Fail(const std::string& key, const std::string& message) const;

  std::string FullKey(const std::string& key) const;
  SourceLocation Location() const;
  SourceLocation LocationOfKey(const std::string& key) const;
  const YamlDocument& document() const { return *doc_; }

 private:
  /// The value node of `key`, or an invalid node; records the key as read.
  YAML::Node Get(const std::string& key);
  std::string ScalarOrFail(const std::string& key, const YAML::Node& value,
                           const char* expected) const;
  /// An integer scalar parsed exactly (std::from_chars); `what` names the type in messages.
  template <class Integer>
  bool ReadInteger(const std::string& key, Integer& value, const char* what);

  const YamlDocument* doc_;
  YAML::Node node_;
  std::string prefix_;
  SourceMap* sources_;
  std::set<std::string> read_keys_;
};

}  // namespace corridorsim

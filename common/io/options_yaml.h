#pragma once
// Options tables (common/options_table.h) meet YAML: reading a map through a table (unknown keys
// and wrong types are InputErrors at `file:line:column: key`, via YamlMap), writing an options
// struct back as YAML (the resolved scenario.yaml a run writes), and the Markdown key tables of
// docs/scenarios.md.

#include <string>
#include <vector>

#include "common/io/yaml_reader.h"
#include "common/options_table.h"

namespace corridorsim {

/// Reads the keys of `table` present in `map` onto `object`, without rejecting other keys (for a
/// caller that reads more keys from the same map).
void ReadOptionFields(YamlMap& map, const OptionTableBase& table, void* object);

/// Reads the keys of `table` present in `map` onto `object`; any other key is an InputError.
template <class T>
void ReadOptions(YamlMap& map, const OptionTable<T>& table, T& object) {
  ReadOptionFields(map, table, &object);
  map.RejectUnknownKeys();
}

/// Block-style YAML text, written key by key (keys are never quoted: they are identifiers).
class OptionsYamlWriter {
 public:
  /// `key: value`, the value already YAML text (see YamlNumber, YamlString, YamlList).
  void Scalar(const std::string& key, const std::string& value);
  /// `key:` and a nested map, until EndMap (an empty one is written `key: {}`).
  void BeginMap(const std::string& key);
  void EndMap();
  const std::string& text() const { return text_; }

 private:
  void Flush();
  std::string text_;
  std::vector<std::string> pending_;  // opened maps not written yet (nothing in them so far)
  int depth_ = 0;                     // maps written
};

/// The shortest text that reads back as the same number.
std::string YamlNumber(double v);
std::string YamlNumber(float v);
/// A double-quoted YAML string.
std::string YamlString(const std::string& s);
/// A flow list of numbers, `[1, 2.5]`.
std::string YamlList(const std::vector<double>& values);

/// Writes every key of `table` with its value in `object` (sections as nested maps).
void WriteOptions(OptionsYamlWriter& out, const OptionTableBase& table, const void* object);

template <class T>
std::string OptionsYaml(const OptionTable<T>& table, const T& object) {
  OptionsYamlWriter out;
  WriteOptions(out, table, &object);
  return out.text();
}

/// The docs rows of `table`'s own keys (inline sections included, other sections left to their
/// own tables) with the defaults of `objects`: one object, or the elements of a named-sections
/// field with their names (defaults that differ read `front: 58, upward: 110`).
std::vector<OptionDocRow> OptionDocRows(const OptionTableBase& table,
                                        const std::vector<const void*>& objects,
                                        const std::vector<std::string>& names = {});

/// A Markdown table `| key | unit | default | bounds | meaning |` of `rows`.
std::string OptionsMarkdown(const std::vector<OptionDocRow>& rows);

/// One generated block of a docs file: `<!-- options:NAME -->` ... `<!-- /options -->`.
struct OptionsDocBlock {
  std::string name;  // the dotted section, e.g. "world.doors"
  std::string text;  // the Markdown between the markers
};

/// Every section reachable from `table` as a docs block named by its dotted key (`root_name`
/// for the table itself; named sections by their key, their elements' defaults side by side).
/// `key_prefix` (e.g. "pipelines.p1_harris") goes before the keys of the nested sections.
std::vector<OptionsDocBlock> OptionsDocBlocks(const OptionTableBase& table, const void* defaults,
                                              const std::string& root_name,
                                              const std::string& key_prefix = "");

/// `doc` with the text of every block replaced by the one of the same name in `blocks`.
/// `problems`, if given, receives what disagrees: a block in `blocks` without markers in `doc`,
/// markers naming no block, or a block whose text differs.
std::string ReplaceOptionsDocBlocks(const std::string& doc,
                                    const std::vector<OptionsDocBlock>& blocks,
                                    std::vector<std::string>* problems = nullptr);

}  // namespace corridorsim

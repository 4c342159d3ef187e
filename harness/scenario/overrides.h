#pragma once
// `--set KEY=VALUE`: scenario and study keys given on the command line (docs/scenarios.md,
// "Keys on the command line"). Each setting becomes one more document of the include chain,
// applied after the files in the order given (a later one wins), so that the loader checks its
// key and value as strictly as a file's, and the echo of the scenario (scenario.yaml) holds the
// value: rerunning that file repeats the run.

#include <cstddef>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "common/io/yaml_reader.h"

namespace corridorsim {

// Bounds of the --set options of one command.
inline constexpr std::size_t kMaxSettings = 64;             // --set options
inline constexpr std::size_t kMaxSettingKeyBytes = 256;     // KEY
inline constexpr std::size_t kMaxSettingKeyParts = 16;      // dotted parts of KEY
inline constexpr std::size_t kMaxSettingValueBytes = 4096;  // VALUE
inline constexpr std::size_t kMaxSettingListIndex = 99999;  // an index part of KEY

// The `file` of every problem a setting causes: "command line: --set: <key>: <message>".
inline constexpr const char* kSetLocation = "command line: --set";

/// One `--set KEY=VALUE`.
struct Setting {
  std::string key;                 // KEY as given
  std::vector<std::string> parts;  // KEY split at its dots
  YAML::Node value;                // VALUE parsed as YAML (a scalar, a flow list or map, ...)
};

/// Parses `--set` arguments in order. KEY is dotted names ([A-Za-z0-9_-], 1 to 64 characters
/// each; a part of digits only is a list index); VALUE is one line of YAML (`20`, `true`,
/// `text`, `'0.10'`, `[a, b]`, `{count: 4}`; nothing is YAML null). `include` cannot be set (it
/// names a file). Throws InputError at kSetLocation naming the key for anything else, and for
/// more than the bounds above.
std::vector<Setting> ParseSettings(const std::vector<std::string>& texts);

/// The settings as YAML documents, one each in order, to be applied after `chain` (an include
/// chain, base first): a map nesting down the key's parts to the value. A list index
/// (`path.commands.1.0`, `expectations.2`) takes the list from the last document that writes it
/// (an earlier setting, else the last file of the chain; a `study.*` list only from the chain's
/// last file, the one `study` reads) and replaces that item, or appends one at the list's length.
/// Throws InputError at kSetLocation for an index into a list that no document writes, beyond its
/// length, or into `plugins` (whose lists add up over the chain).
std::vector<YamlDocument> SettingDocuments(const std::vector<Setting>& settings,
                                           const std::vector<YamlDocument>& chain);

}  // namespace corridorsim

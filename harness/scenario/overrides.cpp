#include "harness/scenario/overrides.h"

#include <algorithm>
#include <charconv>

#include "common/error.h"

namespace corridorsim {
namespace {

const SourceLocation kAt{kSetLocation, 0, 0};

[[noreturn]] void Fail(const std::string& key, const std::string& message) {
  throw InputError(kAt, InputExcerpt(key), message);
}

bool IsIndex(const std::string& part) {
  return std::all_of(part.begin(), part.end(), [](char c) { return c >= '0' && c <= '9'; });
}

bool IsKeyPart(const std::string& part) {
  return !part.empty() && part.size() <= 64 && std::all_of(part.begin(), part.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
  });
}

std::string Join(const std::vector<std::string>& parts, std::size_t count) {
  std::string key;
  for (std::size_t i = 0; i < count; ++i) key += (i == 0 ? "" : ".") + parts[i];
  return key;
}

Setting ParseSetting(const std::string& text) {
  const std::size_t equals = text.find('=');
  if (equals == std::string::npos) {
    Fail("", "expected KEY=VALUE, e.g. --set duration_s=20 (got '" + InputExcerpt(text) + "')");
  }
  Setting setting;
  setting.key = text.substr(0, equals);
  const std::string value = text.substr(equals + 1);
  if (setting.key.size() > kMaxSettingKeyBytes) {
    Fail(setting.key, "a key is at most " + std::to_string(kMaxSettingKeyBytes) + " bytes (got " +
                          std::to_string(setting.key.size()) + ")");
  }
  if (value.size() > kMaxSettingValueBytes) {
    Fail(setting.key, "a value is at most " + std::to_string(kMaxSettingValueBytes) +
                          " bytes (got " + std::to_string(value.size()) + ")");
  }
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = setting.key.find('.', start);
    setting.parts.push_back(
        setting.key.substr(start, dot == std::string::npos ? dot : dot - start));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  if (setting.parts.size() > kMaxSettingKeyParts) {
    Fail(setting.key, "a key has at most " + std::to_string(kMaxSettingKeyParts) + " parts");
  }
  for (const std::string& part : setting.parts) {
    if (!IsKeyPart(part)) {
      Fail(setting.key,
           "a key is dotted names of 1 to 64 letters, digits, '_' or '-' (e.g. "
           "world.doors.count; a part of digits is a list index)");
    }
  }
  if (IsIndex(setting.parts.front())) Fail(setting.key, "a key starts with a name, not an index");
  if (setting.parts.front() == "include") {
    Fail(setting.key, "cannot be set on the command line (it names a file): give that file");
  }
  if (value.find_first_of("\r\n") != std::string::npos) {
    Fail(setting.key, "a value is one line of YAML (a list as [a, b], a map as {k: v})");
  }
  // The value is read as a file's would be (UTF-8, no control characters, the bounds on nodes,
  // no duplicate keys), as the value of one key.
  try {
    const YamlDocument doc = YamlDocument::FromString("value: " + value, kSetLocation);
    setting.value.reset(doc.root["value"]);  // reset: operator= would write into the node
  } catch (const InputError& e) {
    Fail(setting.key, "the value '" + InputExcerpt(value) + "' is not YAML: " + e.message());
  }
  return setting;
}

// The node at `parts[0, count)` of `root` through maps only, or an invalid node.
YAML::Node Find(const YAML::Node& root, const std::vector<std::string>& parts, std::size_t count) {
  YAML::Node node = root;
  for (std::size_t i = 0; i < count; ++i) {
    if (!node.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    const YAML::Node& map = node;  // const: a look-up never adds the key
    const YAML::Node child = map[parts[i]];
    if (!child.IsDefined()) return YAML::Node(YAML::NodeType::Undefined);
    node.reset(child);  // rebinds; `node = child` would write child into the document
  }
  return node;
}

// `leaf` under the maps of `parts[0, count)`.
YAML::Node Wrap(const std::vector<std::string>& parts, std::size_t count, const YAML::Node& leaf) {
  if (count == 0) return leaf;
  YAML::Node map(YAML::NodeType::Map);
  map[parts[count - 1]] = leaf;
  return Wrap(parts, count - 1, map);
}

// Sets `parts[k, end)` below `node` (a clone, a list or a map) to `value`.
void SetBelow(YAML::Node node, const Setting& setting, std::size_t k) {
  const std::string& part = setting.parts[k];
  const bool last = k + 1 == setting.parts.size();
  const std::string here = Join(setting.parts, k);
  if (IsIndex(part)) {
    if (!node.IsSequence())
      Fail(setting.key, "'" + here + "' is not a list: " + part + " is no key");
    std::size_t index = 0;
    const auto [end, error] = std::from_chars(part.data(), part.data() + part.size(), index);
    const std::size_t size = node.size();
    if (error != std::errc() || end != part.data() + part.size() || index > size ||
        index > kMaxSettingListIndex || (index == size && !last)) {
      Fail(setting.key, "index " + InputExcerpt(part) + " is beyond the list '" + here + "' of " +
                            std::to_string(size) + " item(s) (" +
                            (size == 0 ? std::string("0") : "0 to " + std::to_string(size - 1)) +
                            ", or " + std::to_string(size) + " to append as the last part)");
    }
    if (index == size) {
      node.push_back(setting.value);
    } else if (last) {
      node[index] = setting.value;
    } else {
      SetBelow(node[index], setting, k + 1);
    }
    return;
  }
  if (!node.IsMap()) {
    Fail(setting.key, "'" + here + "' is not a map: it has no key '" + part + "'");
  }
  if (last) {
    node[part] = setting.value;
  } else {
    const YAML::Node& map = node;
    if (!map[part].IsDefined()) node[part] = YAML::Node(YAML::NodeType::Map);
    SetBelow(node[part], setting, k + 1);
  }
}

}  // namespace

std::vector<Setting> ParseSettings(const std::vector<std::string>& texts) {
  if (texts.size() > kMaxSettings) {
    Fail("", "at most " + std::to_string(kMaxSettings) + " --set options (got " +
                 std::to_string(texts.size()) + ")");
  }
  std::vector<Setting> settings;
  for (const std::string& text : texts) settings.push_back(ParseSetting(text));
  return settings;
}

std::vector<YamlDocument> SettingDocuments(const std::vector<Setting>& settings,
                                           const std::vector<YamlDocument>& chain) {
  std::vector<YamlDocument> docs;
  for (const Setting& setting : settings) {
    const auto first_index =
        std::find_if(setting.parts.begin(), setting.parts.end(), IsIndex) - setting.parts.begin();
    const std::size_t split = static_cast<std::size_t>(first_index);
    YAML::Node leaf;
    leaf.reset(setting.value);
    if (split < setting.parts.size()) {
      // The list that the index goes into, as the documents before this one leave it.
      const std::string list_key = Join(setting.parts, split);
      if (setting.parts.front() == "plugins") {
        Fail(setting.key,
             "the lists of `plugins` add up over the include chain: add a library "
             "with --set plugins=[path]");
      }
      YAML::Node list(YAML::NodeType::Undefined);
      for (auto doc = docs.rbegin(); doc != docs.rend() && !list.IsDefined(); ++doc) {
        list.reset(Find(doc->root, setting.parts, split));
      }
      const bool study_key = setting.parts.front() == "study";
      for (auto doc = chain.rbegin(); doc != chain.rend() && !list.IsDefined(); ++doc) {
        list.reset(Find(doc->root, setting.parts, split));
        if (study_key) break;  // `study` reads the study section of the file it is given only
      }
      if (!list.IsDefined() || !list.IsSequence()) {
        Fail(setting.key, "'" + list_key + "' is not a list written in the scenario's files" +
                              (list.IsDefined() ? "" : " (its value is the code default)") +
                              ": set it whole, e.g. --set '" + list_key + "=[...]'");
      }
      leaf.reset(YAML::Clone(list));  // the documents' own list stays as it is
      SetBelow(leaf, setting, split);
    }
    YamlDocument doc;
    doc.file = kSetLocation;
    doc.root = Wrap(setting.parts, split, leaf);
    doc.has_positions = false;
    docs.push_back(std::move(doc));
  }
  return docs;
}

}  // namespace corridorsim

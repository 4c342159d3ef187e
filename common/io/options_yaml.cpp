#include "common/io/options_yaml.h"

#include <charconv>
#include <cstdio>

#include "common/options_checker.h"

namespace corridorsim {
namespace {

std::string Join(const std::string& prefix, const std::string& key) {
  if (prefix.empty()) return key;
  if (key.empty()) return prefix;
  return prefix + "." + key;
}

template <class M>
M& At(const OptionField& f, const void* object) {
  return *static_cast<M*>(f.member(const_cast<void*>(object)));
}

// A number for the docs: short ("%g"), as the messages write it.
std::string DocNumber(double v) { return FormatNumber(v); }

// Calls `fn` with the member of a field whose kind is one YamlMap reads and writes as it is
// (not kFloat, kEnum, sections or custom fields); returns false for the others.
template <class F>
bool VisitPlainMember(const OptionField& f, const void* object, F&& fn) {
  switch (f.kind) {
    case OptionKind::kDouble:
      return fn(At<double>(f, object)), true;
    case OptionKind::kInt:
      return fn(At<int>(f, object)), true;
    case OptionKind::kInt64:
      return fn(At<std::int64_t>(f, object)), true;
    case OptionKind::kUInt64:
      return fn(At<std::uint64_t>(f, object)), true;
    case OptionKind::kBool:
      return fn(At<bool>(f, object)), true;
    case OptionKind::kString:
      return fn(At<std::string>(f, object)), true;
    case OptionKind::kDoubleList:
      return fn(At<std::vector<double>>(f, object)), true;
    default:
      return false;
  }
}

std::string ToYaml(double v) { return YamlNumber(v); }
std::string ToYaml(int v) { return std::to_string(v); }
std::string ToYaml(std::int64_t v) { return std::to_string(v); }
std::string ToYaml(std::uint64_t v) { return std::to_string(v); }
std::string ToYaml(bool v) { return v ? "true" : "false"; }
std::string ToYaml(const std::string& v) { return YamlString(v); }
std::string ToYaml(const std::vector<double>& v) { return YamlList(v); }

std::string Code(const std::string& s) { return "`" + s + "`"; }

// The default of one field of `object` as the docs show it.
std::string DocValue(const OptionField& f, const void* object) {
  switch (f.kind) {
    case OptionKind::kInt:
      return std::to_string(At<int>(f, object));
    case OptionKind::kInt64:
      return std::to_string(At<std::int64_t>(f, object));
    case OptionKind::kUInt64:
      return std::to_string(At<std::uint64_t>(f, object));
    case OptionKind::kDouble:
    case OptionKind::kFloat:
      return DocNumber(f.Number(object));
    case OptionKind::kBool:
      return At<bool>(f, object) ? "true" : "false";
    case OptionKind::kString:
      return Code(YamlString(At<std::string>(f, object)));
    case OptionKind::kEnum: {
      const int i = f.get_choice(object);
      return i < 0 ? "?" : Code(f.choices[static_cast<std::size_t>(i)]);
    }
    case OptionKind::kDoubleList: {
      std::string s;
      for (const double v : At<std::vector<double>>(f, object)) {
        s += (s.empty() ? "" : ", ") + DocNumber(v);
      }
      return Code("[" + s + "]");
    }
    default:
      return "";
  }
}

// The rows of one object (inline sections flattened, with their keys as they are written).
std::vector<OptionDocRow> RowsOf(const OptionTableBase& table, const void* object) {
  std::vector<OptionDocRow> rows;
  for (const OptionField& f : table.fields()) {
    if (f.kind == OptionKind::kSection && f.key.empty()) {
      const std::vector<OptionDocRow> inner = RowsOf(*f.table, f.member(const_cast<void*>(object)));
      rows.insert(rows.end(), inner.begin(), inner.end());
    } else if (f.kind == OptionKind::kSection || f.kind == OptionKind::kNamedSections) {
      if (!f.key.empty()) rows.push_back({f.key, "", "", "", f.doc + " (its own table)"});
    } else if (f.kind == OptionKind::kCustom) {
      const std::vector<OptionDocRow> custom = f.doc_rows(object);
      rows.insert(rows.end(), custom.begin(), custom.end());
    } else {
      std::string bounds = OptionBoundsText(f);
      if (f.kind == OptionKind::kEnum) {
        for (const std::string& c : f.choices) bounds += (bounds.empty() ? "" : ", ") + Code(c);
      }
      rows.push_back({f.key, f.unit, DocValue(f, object), bounds, f.doc});
    }
  }
  return rows;
}

std::string Cell(const std::string& s) {
  std::string out;
  for (const char c : s) {
    if (c == '|') out += '\\';
    out += c;
  }
  return out;
}

bool HasOwnRows(const OptionTableBase& table) {
  for (const OptionField& f : table.fields()) {
    if (f.kind == OptionKind::kSection && f.key.empty() && HasOwnRows(*f.table)) return true;
    if (f.kind == OptionKind::kCustom && f.key.empty()) continue;  // a hook with no key of its own
    if (f.kind != OptionKind::kSection && f.kind != OptionKind::kNamedSections) return true;
  }
  return false;
}

void CollectBlocks(const OptionTableBase& table, const std::vector<const void*>& objects,
                   const std::vector<std::string>& names, const std::string& block_name,
                   const std::string& prefix, std::vector<OptionsDocBlock>* blocks) {
  if (HasOwnRows(table)) {
    blocks->push_back({block_name, OptionsMarkdown(OptionDocRows(table, objects, names))});
  }
  for (const OptionField& f : table.fields()) {
    if (f.kind == OptionKind::kSection) {
      std::vector<const void*> sections;
      for (const void* o : objects) sections.push_back(f.member(const_cast<void*>(o)));
      if (f.key.empty()) {
        // Inline: its rows are in this block; its own sections go on under this prefix.
        for (const OptionField& g : f.table->fields()) {
          if (g.kind != OptionKind::kSection || g.key.empty()) continue;
          std::vector<const void*> inner;
          for (const void* s : sections) inner.push_back(g.member(const_cast<void*>(s)));
          CollectBlocks(*g.table, inner, names, Join(prefix, g.key), Join(prefix, g.key), blocks);
        }
        continue;
      }
      CollectBlocks(*f.table, sections, names, Join(prefix, f.key), Join(prefix, f.key), blocks);
    } else if (f.kind == OptionKind::kNamedSections && !objects.empty()) {
      const void* first = objects.front();
      if (f.count(first) == 0) continue;  // no defaults to show: the caller documents the kind
      std::vector<const void*> elements;
      std::vector<std::string> element_names;
      for (std::size_t i = 0; i < f.count(first); ++i) {
        elements.push_back(f.element(const_cast<void*>(first), i));
        element_names.push_back(f.element_name(elements.back()));
      }
      const std::string name = Join(prefix, f.key).empty() ? block_name : Join(prefix, f.key);
      CollectBlocks(*f.table, elements, element_names, name, name, blocks);
    }
  }
}

}  // namespace

void ReadOptionFields(YamlMap& map, const OptionTableBase& table, void* object) {
  for (const OptionField& f : table.fields()) {
    if (VisitPlainMember(f, object, [&](auto& value) { map.Read(f.key, value); })) continue;
    switch (f.kind) {
      case OptionKind::kFloat: {
        float& value = At<float>(f, object);
        double wide = value;
        if (map.Read(f.key, wide)) value = static_cast<float>(wide);
        break;
      }
      case OptionKind::kEnum: {
        std::vector<std::pair<std::string, int>> choices;
        for (std::size_t i = 0; i < f.choices.size(); ++i) {
          choices.emplace_back(f.choices[i], static_cast<int>(i));
        }
        int choice = 0;
        if (map.ReadEnum(f.key, choice, choices)) f.set_choice(object, choice);
        break;
      }
      case OptionKind::kSection: {
        void* section = f.member(object);
        if (f.key.empty()) {
          ReadOptionFields(map, *f.table, section);
        } else {
          YamlMap sub = map.Map(f.key);
          ReadOptionFields(sub, *f.table, section);
          sub.RejectUnknownKeys();
        }
        break;
      }
      case OptionKind::kNamedSections: {
        auto read_elements = [&](YamlMap& container) {
          for (std::size_t i = 0; i < f.count(object); ++i) {
            void* element = f.element(object, i);
            YamlMap sub = container.Map(f.element_name(element));
            ReadOptionFields(sub, *f.table, element);
            sub.RejectUnknownKeys();
          }
        };
        if (f.key.empty()) {
          read_elements(map);
        } else {
          YamlMap container = map.Map(f.key);
          read_elements(container);
          container.RejectUnknownKeys();
        }
        break;
      }
      case OptionKind::kCustom:
        f.parse(map, object);
        break;
      default:  // read by VisitPlainMember
        break;
    }
  }
}

void OptionsYamlWriter::Flush() {
  for (const std::string& key : pending_) {
    text_ += std::string(static_cast<std::size_t>(2 * depth_), ' ') + key + ":\n";
    ++depth_;
  }
  pending_.clear();
}

void OptionsYamlWriter::Scalar(const std::string& key, const std::string& value) {
  Flush();
  text_ += std::string(static_cast<std::size_t>(2 * depth_), ' ') + key + ": " + value + "\n";
}

void OptionsYamlWriter::BeginMap(const std::string& key) { pending_.push_back(key); }

void OptionsYamlWriter::EndMap() {
  if (pending_.empty()) {
    --depth_;
    return;
  }
  const std::string key = pending_.back();
  pending_.pop_back();
  Scalar(key, "{}");
}

// Shortest round-trip digits; plain decimals (0.0002, not 2e-04) where they stay short.
template <class F>
std::string ShortestNumber(F v) {
  char buf[400];
  const F magnitude = v < 0 ? -v : v;
  const bool plain = magnitude == 0 || (magnitude >= F(1e-5) && magnitude < F(1e15));
  const auto result = plain ? std::to_chars(buf, buf + sizeof(buf), v, std::chars_format::fixed)
                            : std::to_chars(buf, buf + sizeof(buf), v);
  return std::string(buf, result.ptr);
}

std::string YamlNumber(double v) { return ShortestNumber(v); }

std::string YamlNumber(float v) { return ShortestNumber(v); }

std::string YamlString(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof(buf), "\\x%02x", static_cast<unsigned>(c));
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

std::string YamlList(const std::vector<double>& values) {
  std::string s;
  for (const double v : values) s += (s.empty() ? "" : ", ") + YamlNumber(v);
  return "[" + s + "]";
}

void WriteOptions(OptionsYamlWriter& out, const OptionTableBase& table, const void* object) {
  for (const OptionField& f : table.fields()) {
    if (VisitPlainMember(f, object, [&](const auto& value) { out.Scalar(f.key, ToYaml(value)); })) {
      continue;
    }
    switch (f.kind) {
      case OptionKind::kFloat:
        out.Scalar(f.key, YamlNumber(At<float>(f, object)));
        break;
      case OptionKind::kEnum:
        out.Scalar(f.key, f.choices.at(static_cast<std::size_t>(f.get_choice(object))));
        break;
      case OptionKind::kSection: {
        const void* section = f.member(const_cast<void*>(object));
        if (!f.key.empty()) out.BeginMap(f.key);
        WriteOptions(out, *f.table, section);
        if (!f.key.empty()) out.EndMap();
        break;
      }
      case OptionKind::kNamedSections:
        if (!f.key.empty()) out.BeginMap(f.key);
        for (std::size_t i = 0; i < f.count(object); ++i) {
          const void* element = f.element(const_cast<void*>(object), i);
          out.BeginMap(f.element_name(element));
          WriteOptions(out, *f.table, element);
          out.EndMap();
        }
        if (!f.key.empty()) out.EndMap();
        break;
      case OptionKind::kCustom:
        f.echo(object, out);
        break;
      default:  // written by VisitPlainMember
        break;
    }
  }
}

std::vector<OptionDocRow> OptionDocRows(const OptionTableBase& table,
                                        const std::vector<const void*>& objects,
                                        const std::vector<std::string>& names) {
  if (objects.empty()) return {};
  std::vector<OptionDocRow> rows = RowsOf(table, objects.front());
  if (objects.size() == 1) return rows;
  std::vector<std::vector<OptionDocRow>> each;
  for (const void* o : objects) each.push_back(RowsOf(table, o));
  for (std::size_t r = 0; r < rows.size(); ++r) {
    bool same = true;
    for (const auto& e : each) same = same && e.at(r).default_value == rows[r].default_value;
    if (same) continue;
    std::string all;
    for (std::size_t k = 0; k < each.size(); ++k) {
      const std::string name = k < names.size() ? names[k] : std::to_string(k);
      all += (all.empty() ? "" : ", ") + name + ": " + each[k][r].default_value;
    }
    rows[r].default_value = all;
  }
  return rows;
}

std::string OptionsMarkdown(const std::vector<OptionDocRow>& rows) {
  std::string md = "| key | unit | default | bounds | meaning |\n|---|---|---|---|---|\n";
  for (const OptionDocRow& r : rows) {
    md += "| " + Code(r.key) + " | " + Cell(r.unit) + " | " + Cell(r.default_value) + " | " +
          Cell(r.bounds) + " | " + Cell(r.doc) + " |\n";
  }
  return md;
}

std::vector<OptionsDocBlock> OptionsDocBlocks(const OptionTableBase& table, const void* defaults,
                                              const std::string& root_name,
                                              const std::string& key_prefix) {
  std::vector<OptionsDocBlock> blocks;
  CollectBlocks(table, {defaults}, {}, root_name, key_prefix, &blocks);
  return blocks;
}

std::string ReplaceOptionsDocBlocks(const std::string& doc,
                                    const std::vector<OptionsDocBlock>& blocks,
                                    std::vector<std::string>* problems) {
  const std::string open = "<!-- options:", close = "<!-- /options -->";
  std::string out;
  std::vector<bool> used(blocks.size(), false);
  std::size_t at = 0;
  while (true) {
    const std::size_t begin = doc.find(open, at);
    if (begin == std::string::npos) break;
    const std::size_t name_end = doc.find(" -->", begin);
    const std::size_t line_end = doc.find('\n', begin);
    const std::size_t end = doc.find(close, begin);
    if (name_end == std::string::npos || line_end == std::string::npos ||
        end == std::string::npos || name_end > line_end) {
      if (problems) problems->push_back("an unclosed options marker");
      break;
    }
    const std::string name = doc.substr(begin + open.size(), name_end - begin - open.size());
    const std::string current = doc.substr(line_end + 1, end - line_end - 1);
    out += doc.substr(at, line_end + 1 - at);
    std::string text = current;
    bool found = false;
    for (std::size_t i = 0; i < blocks.size(); ++i) {
      if (blocks[i].name != name) continue;
      found = true;
      used[i] = true;
      text = blocks[i].text;
      if (problems && text != current) {
        problems->push_back("the table of '" + name + "' differs from its options table");
      }
    }
    if (!found && problems) problems->push_back("no options table named '" + name + "'");
    out += text + close;
    at = end + close.size();
  }
  out += doc.substr(at);
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    if (!used[i] && problems) {
      problems->push_back("no <!-- options:" + blocks[i].name + " --> block for its options table");
    }
  }
  return out;
}

}  // namespace corridorsim

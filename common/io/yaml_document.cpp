#include "common/io/yaml_reader.h"

#include <map>
#include <set>
#include <sstream>
#include <string_view>
#include <vector>

#include <yaml-cpp/eventhandler.h>

#include "common/io/input_text.h"

// One YAML document (yaml_reader.h: YamlDocument::FromString, LocationOf): the text checked
// (UTF-8 without control characters), the parser's events bounded before any node is built
// (BoundsCheck: one document, depth, nodes and text with aliases counted as copies), then the
// nodes walked for duplicate keys.

namespace corridorsim {
namespace {

SourceLocation FromMark(const std::string& file, const YAML::Mark& mark) {
  SourceLocation loc{file, 0, 0};
  if (mark.line >= 0) loc.line = mark.line + 1;  // yaml-cpp marks are 0-based
  if (mark.column >= 0) loc.column = mark.column + 1;
  return loc;
}

// ---- Text ---------------------------------------------------------------------------------------

// A scenario is UTF-8 text without control characters (YAML's printable set): anything else,
// a binary file most likely, is reported by position, never by content.
void CheckText(const std::string& text, const std::string& name) {
  if (text.size() > kMaxYamlFileBytes) {
    throw InputError(SourceLocation{name, 0, 0}, "",
                     "the text is larger than the limit of " + std::to_string(kMaxYamlFileBytes) +
                         " bytes (1 MiB)");
  }
  int line = 1, column = 1;
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c == '\n') {
      ++line;
      column = 1;
      ++i;
      continue;
    }
    if ((c < 0x20 && c != '\t' && c != '\r') || c == 0x7F) {
      throw InputError(SourceLocation{name, line, column}, "",
                       "not a YAML text file: control character " + ByteHex(c));
    }
    const std::size_t n = Utf8Length(text, i);
    if (n == 0) {
      throw InputError(SourceLocation{name, line, column}, "",
                       "not a YAML text file: byte " + ByteHex(c) + " is not UTF-8");
    }
    i += n;
    ++column;
  }
}

// ---- Bounds, before any node is built -----------------------------------------------------------

// A first pass over the parser's events: one document, at most kMaxYamlDepth levels, and at most
// kMaxYamlNodes nodes and kMaxYamlTextBytes of scalar text counting every alias as a copy of what
// it names. yaml-cpp's nodes share an aliased subtree, so building them is cheap, but every walk
// over them (duplicate keys, reads) sees the copies: nine nested levels of ten aliases each are
// 10^9 nodes. The pass holds one counter pair per anchor and one frame per open collection.
class BoundsCheck : public YAML::EventHandler {
 public:
  explicit BoundsCheck(std::string name) : name_(std::move(name)) {}

  void OnDocumentStart(const YAML::Mark& mark) override {
    if (++documents_ > 1) {
      Fail(mark,
           "a second YAML document starts here; a scenario file holds one (remove the "
           "'---' or '...' line)");
    }
  }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override { Node(mark, anchor, ""); }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                const std::string& value) override {
    Node(mark, anchor, value);
  }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    const auto it = anchors_.find(anchor);
    if (it == anchors_.end()) Fail(mark, "the alias names no anchor");  // yaml-cpp throws first
    if (!it->second.complete) Fail(mark, "the alias names a node that contains it");
    BeforeValue();
    Add(mark, it->second.nodes, it->second.bytes, true);
    AfterValue();
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                       YAML::EmitterStyle::value) override {
    Open(mark, anchor, false);
  }
  void OnSequenceEnd() override { Close(); }
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                  YAML::EmitterStyle::value) override {
    Open(mark, anchor, true);
  }
  void OnMapEnd() override { Close(); }

 private:
  struct Anchor {
    std::size_t nodes = 0;
    std::size_t bytes = 0;
    bool complete = false;
  };
  struct Frame {
    bool is_map = false;
    bool at_key = true;     // maps: the next event is a key
    std::string key;        // maps: the current key (cut short only in a message)
    std::size_t index = 0;  // lists: the current item
    YAML::anchor_t anchor = 0;
    std::size_t nodes_before = 0;
    std::size_t bytes_before = 0;
  };

  [[noreturn]] void Fail(const YAML::Mark& mark, const std::string& message) const {
    throw InputError(FromMark(name_, mark), KeyExcerpt(Key()), message);
  }

  // The dotted key of the node being read ("a.b[2].c"), from the open frames.
  std::string Key() const {
    std::string key;
    for (const Frame& f : frames_) {
      if (f.is_map) {
        if (!f.at_key) key += (key.empty() ? "" : ".") + f.key;
      } else {
        key += "[" + std::to_string(f.index) + "]";
      }
    }
    return key;
  }

  void BeforeValue() {
    if (frames_.empty()) return;
    Frame& f = frames_.back();
    if (f.is_map && f.at_key) f.key.clear();
  }
  void AfterValue() {
    if (frames_.empty()) return;
    Frame& f = frames_.back();
    if (f.is_map) {
      f.at_key = !f.at_key;
    } else {
      ++f.index;
    }
  }

  void Add(const YAML::Mark& mark, std::size_t nodes, std::size_t bytes, bool alias) {
    // Each total stays below its limit before the addition, and an anchor's totals below theirs,
    // so the sums cannot overflow.
    nodes_ += nodes;
    bytes_ += bytes;
    const std::string what = alias ? "this alias makes the document" : "the document is";
    const std::string why = alias ? " (an alias counts as a copy of what its anchor names)" : "";
    if (nodes_ > kMaxYamlNodes) {
      Fail(mark,
           what + " larger than " + std::to_string(kMaxYamlNodes) + " nodes, the limit" + why);
    }
    if (bytes_ > kMaxYamlTextBytes) {
      Fail(mark, what + " larger than " + std::to_string(kMaxYamlTextBytes) +
                     " bytes of text, the limit" + why);
    }
  }

  void Node(const YAML::Mark& mark, YAML::anchor_t anchor, const std::string& value) {
    Frame* frame = frames_.empty() ? nullptr : &frames_.back();
    if (frame && frame->is_map && frame->at_key) frame->key = value;
    Add(mark, 1, value.size(), false);
    if (anchor) anchors_[anchor] = Anchor{1, value.size(), true};
    AfterValue();
  }

  void Open(const YAML::Mark& mark, YAML::anchor_t anchor, bool is_map) {
    BeforeValue();
    if (!frames_.empty() && frames_.back().is_map && frames_.back().at_key) {
      frames_.back().key = "<complex key>";
    }
    Add(mark, 1, 0, false);
    if (static_cast<int>(frames_.size()) >= kMaxYamlDepth) {
      Fail(mark, "nesting is deeper than " + std::to_string(kMaxYamlDepth) + " levels");
    }
    if (anchor) anchors_[anchor] = Anchor{};  // incomplete: an alias inside it is a cycle
    frames_.push_back(Frame{is_map, true, "", 0, anchor, nodes_ - 1, bytes_});
  }

  void Close() {
    const Frame f = frames_.back();
    frames_.pop_back();
    if (f.anchor)
      anchors_[f.anchor] = Anchor{nodes_ - f.nodes_before, bytes_ - f.bytes_before, true};
    AfterValue();
  }

  std::string name_;
  int documents_ = 0;
  std::size_t nodes_ = 0;
  std::size_t bytes_ = 0;
  std::vector<Frame> frames_;
  std::map<YAML::anchor_t, Anchor> anchors_;
};

// A YAML message in an error: yaml-cpp's wording, which may quote a character of the input.
std::string YamlMessage(const std::string& msg) { return InputExcerpt(msg, 160); }

// ---- Walks over the nodes -----------------------------------------------------------------------

// The dotted key of a node in a walk, built only when an error needs it: the walk's keys may be
// long, and copying a prefix into every child would cost the prefix's length per node.
struct KeyPath {
  struct Part {
    const std::string* key = nullptr;  // a map key, or
    std::size_t index = 0;             // a list index
  };
  std::vector<Part> parts;

  std::string Text() const {
    std::string text;
    for (const Part& p : parts) {
      if (p.key) {
        text += (text.empty() ? "" : ".") + *p.key;
      } else {
        text += "[" + std::to_string(p.index) + "]";
      }
    }
    return text;
  }
};

// yaml-cpp keeps the first of two equal keys and drops nothing from iteration: walk every map
// and reject a key seen twice, or a key that is not a plain scalar. BoundsCheck has bounded the
// walk (no cycles, kMaxYamlDepth levels, kMaxYamlNodes nodes and kMaxYamlTextBytes of keys); the
// depth is checked again so that the walk stays bounded on its own.
void RejectDuplicateKeys(const YamlDocument& doc, const YAML::Node& node, KeyPath& path) {
  if (static_cast<int>(path.parts.size()) > kMaxYamlDepth) {
    throw InputError(doc.LocationOf(node), KeyExcerpt(path.Text()),
                     "nesting is deeper than " + std::to_string(kMaxYamlDepth) + " levels");
  }
  if (node.IsMap()) {
    std::set<std::string_view> seen;
    for (const auto& kv : node) {
      if (!kv.first.IsScalar()) {
        throw InputError(doc.LocationOf(kv.first), KeyExcerpt(path.Text()),
                         "a key must be a name, not a map, a list or nothing");
      }
      const std::string& key = kv.first.Scalar();
      path.parts.push_back({&key, 0});
      if (!seen.insert(key).second) {
        throw InputError(doc.LocationOf(kv.first), KeyExcerpt(path.Text()), "duplicate key");
      }
      RejectDuplicateKeys(doc, kv.second, path);
      path.parts.pop_back();
    }
  } else if (node.IsSequence()) {
    std::size_t i = 0;
    for (const auto& item : node) {
      path.parts.push_back({nullptr, i++});
      RejectDuplicateKeys(doc, item, path);
      path.parts.pop_back();
    }
  }
}

YamlDocument Parse(const std::string& text, const std::string& name) {
  CheckText(text, name);
  YamlDocument doc;
  doc.file = name;
  try {
    {
      std::istringstream in(text);
      YAML::Parser parser(in);
      BoundsCheck bounds(name);
      while (parser.HandleNextDocument(bounds)) {
      }
    }
    doc.root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(FromMark(name, e.mark), "", "invalid YAML: " + YamlMessage(e.msg));
  }
  if (doc.root.IsNull()) doc.root = YAML::Node(YAML::NodeType::Map);  // empty file: all defaults
  if (!doc.root.IsMap()) {
    // Never quote it: a text file that is not a scenario is one scalar document.
    throw InputError(doc.LocationOf(doc.root), "", "the document must be a map of keys");
  }
  KeyPath path;
  RejectDuplicateKeys(doc, doc.root, path);
  return doc;
}

}  // namespace

YamlDocument YamlDocument::FromString(const std::string& text, const std::string& name) {
  return Parse(text, name);
}

SourceLocation YamlDocument::LocationOf(const YAML::Node& node) const {
  if (!has_positions) return SourceLocation{file, 0, 0};
  return FromMark(file, node.Mark());
}

}  // namespace corridorsim

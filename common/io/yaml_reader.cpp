#include "common/io/yaml_reader.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <sstream>

#include <yaml-cpp/eventhandler.h>

namespace corridorsim {
namespace {

// A path in a message: as typed, unless it is absurdly long or holds control characters.
constexpr std::size_t kMaxPathInMessage = 240;  // longer: head...tail

SourceLocation FromMark(const std::string& file, const YAML::Mark& mark) {
  SourceLocation loc{file, 0, 0};
  if (mark.line >= 0) loc.line = mark.line + 1;  // yaml-cpp marks are 0-based
  if (mark.column >= 0) loc.column = mark.column + 1;
  return loc;
}

std::string Hex(unsigned char byte) {
  static const char* digits = "0123456789abcdef";
  return std::string("0x") + digits[byte >> 4] + digits[byte & 15];
}

// A dotted key put into a message (it may hold user text: map keys, camera names).
std::string MessageKey(const std::string& key) { return InputExcerpt(key, 120); }

// ---- Files --------------------------------------------------------------------------------------

// The identity of an opened file, for include cycles: a link or another spelling of the same
// path is the same file.
struct FileId {
  dev_t device = 0;
  ino_t inode = 0;
  bool operator<(const FileId& o) const {
    return device != o.device ? device < o.device : inode < o.inode;
  }
};

constexpr const char* kDoesNotExist = "does not exist";

std::string KindOf(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

// Why open(2) failed, as the rest of "included file 'x' ..." (never the file's content).
std::string OpenProblem(const std::string& path, int error) {
  switch (error) {
    case ENOENT: {
      struct stat link {};
      if (::lstat(path.c_str(), &link) == 0 && S_ISLNK(link.st_mode)) {
        return "is a symbolic link to nothing (dangling)";
      }
      return kDoesNotExist;
    }
    case ELOOP:
      return "cannot be opened: too many levels of symbolic links (a link loop?)";
    case ENAMETOOLONG:
      return "cannot be opened: its name is longer than the system allows";
    case ENOTDIR:
      return "cannot be opened: a part of its path is not a folder";
    case EACCES:
    case EPERM:
      return "cannot be opened: permission denied";
    case EISDIR:
      return "is a folder, not a regular file";
    default:
      return std::string("cannot be opened: ") + std::strerror(error);
  }
}

// Reads a regular file of at most kMaxYamlFileBytes into `text`, once. Opening never blocks
// (O_NONBLOCK: a FIFO without a writer would otherwise wait forever in open()), and the opened
// descriptor is what is checked, so the file cannot be swapped between the check and the read.
// On failure returns false with `why` set.
bool ReadRegularFile(const std::string& path, std::string& text, FileId& id, std::string& why) {
  if (path.find('\0') != std::string::npos) {
    why = "cannot be opened: its name contains a NUL character";
    return false;
  }
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    why = OpenProblem(path, errno);
    return false;
  }
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    why = std::string("cannot be read: ") + std::strerror(errno);
    return false;
  }
  if (!S_ISREG(st.st_mode)) {
    why = "is " + KindOf(st.st_mode) + ", not a regular file";
    return false;
  }
  const std::string too_large =
      "is larger than the limit of " + std::to_string(kMaxYamlFileBytes) + " bytes (1 MiB)";
  if (st.st_size < 0 || static_cast<std::uint64_t>(st.st_size) > kMaxYamlFileBytes) {
    why = too_large;
    return false;
  }
  id = FileId{st.st_dev, st.st_ino};
  // The size fstat reports is a hint (it may grow, /proc files say 0): read until the end, but
  // never more than the limit plus one byte.
  text.clear();
  text.reserve(static_cast<std::size_t>(st.st_size));
  char buffer[1 << 16];
  while (true) {
    const ssize_t n = ::read(fd, buffer, sizeof(buffer));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      why = std::string("cannot be read: ") + std::strerror(errno);
      return false;
    }
    if (n == 0) break;
    text.append(buffer, static_cast<std::size_t>(n));
    if (text.size() > kMaxYamlFileBytes) {
      why = too_large;
      return false;
    }
  }
  return true;
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
                       "not a YAML text file: control character " + Hex(c));
    }
    const std::size_t n = Utf8Length(text, i);
    if (n == 0) {
      throw InputError(SourceLocation{name, line, column}, "",
                       "not a YAML text file: byte " + Hex(c) + " is not UTF-8");
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
    throw InputError(FromMark(name_, mark), MessageKey(Key()), message);
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
    throw InputError(doc.LocationOf(node), MessageKey(path.Text()),
                     "nesting is deeper than " + std::to_string(kMaxYamlDepth) + " levels");
  }
  if (node.IsMap()) {
    std::set<std::string_view> seen;
    for (const auto& kv : node) {
      if (!kv.first.IsScalar()) {
        throw InputError(doc.LocationOf(kv.first), MessageKey(path.Text()),
                         "a key must be a name, not a map, a list or nothing");
      }
      const std::string& key = kv.first.Scalar();
      path.parts.push_back({&key, 0});
      if (!seen.insert(key).second) {
        throw InputError(doc.LocationOf(kv.first), MessageKey(path.Text()), "duplicate key");
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

// Reads and parses `path`; a file problem is an error at `include_at` (the `include:` line of the
// including file) when given, else at the file itself.
YamlDocument LoadFile(const std::string& path, const SourceLocation* include_at, FileId& id) {
  std::string text, why;
  if (!ReadRegularFile(path, text, id, why)) {
    if (include_at) {
      throw InputError(*include_at, "include",
                       "included file '" + InputExcerpt(path, kMaxPathInMessage) + "' " + why);
    }
    throw InputError(
        SourceLocation{InputExcerpt(path, kMaxPathInMessage), 0, 0}, "",
        why == kDoesNotExist ? "cannot open the file" : "cannot open the file: it " + why);
  }
  return Parse(text, path);
}

}  // namespace

std::size_t Utf8Length(std::string_view text, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char b0 = byte(i);
  if (b0 < 0x80) return 1;
  std::size_t n = 0;
  unsigned char low = 0x80, high = 0xBF;  // the range of the second byte
  if (b0 >= 0xC2 && b0 <= 0xDF) {
    n = 2;
  } else if (b0 >= 0xE0 && b0 <= 0xEF) {
    n = 3;
    if (b0 == 0xE0) low = 0xA0;
    if (b0 == 0xED) high = 0x9F;
  } else if (b0 >= 0xF0 && b0 <= 0xF4) {
    n = 4;
    if (b0 == 0xF0) low = 0x90;
    if (b0 == 0xF4) high = 0x8F;
  } else {
    return 0;
  }
  if (i + n > text.size()) return 0;
  if (byte(i + 1) < low || byte(i + 1) > high) return 0;
  for (std::size_t k = 2; k < n; ++k) {
    if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) return 0;
  }
  return n;
}

std::string InputExcerpt(std::string_view text, std::size_t max_bytes) {
  // Control characters become \xNN; cuts fall between characters, never inside a UTF-8
  // sequence or an escape. Only a window at each end of a long text is looked at.
  const auto escape = [](std::string_view part) {
    std::vector<std::string> chars;  // one entry per character of `part`
    for (std::size_t i = 0; i < part.size();) {
      const auto c = static_cast<unsigned char>(part[i]);
      if (c < 0x20 || c == 0x7F) {
        chars.push_back("\\x" + Hex(c).substr(2));
        ++i;
        continue;
      }
      std::size_t n = 1;
      while (i + n < part.size() && (static_cast<unsigned char>(part[i + n]) & 0xC0) == 0x80) ++n;
      chars.emplace_back(part.substr(i, n));
      i += n;
    }
    return chars;
  };
  const std::size_t window = max_bytes + 4;
  if (text.size() <= window) {
    std::string whole;
    for (const std::string& ch : escape(text)) whole += ch;
    if (whole.size() <= max_bytes) return whole;
  }
  const std::size_t room = max_bytes > 3 ? max_bytes - 3 : 0;
  const std::size_t head_room = room * 2 / 3, tail_room = room - head_room;
  std::string head;
  for (const std::string& ch : escape(text.substr(0, std::min(text.size(), window)))) {
    if (head.size() + ch.size() > head_room) break;
    head += ch;
  }
  std::string tail;
  const std::vector<std::string> tail_chars =
      escape(text.substr(text.size() > window ? text.size() - window : 0));
  for (auto it = tail_chars.rbegin(); it != tail_chars.rend(); ++it) {
    if (tail.size() + it->size() > tail_room) break;
    tail.insert(0, *it);
  }
  return head + "..." + tail;
}

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
  FileId id;
  return LoadFile(path, nullptr, id);
}

YamlDocument YamlDocument::FromString(const std::string& text, const std::string& name) {
  return Parse(text, name);
}

SourceLocation YamlDocument::LocationOf(const YAML::Node& node) const {
  if (!has_positions) return SourceLocation{file, 0, 0};
  return FromMark(file, node.Mark());
}

std::vector<YamlDocument> LoadWithIncludes(const std::string& path) {
  std::vector<YamlDocument> chain;
  FileId id;
  chain.push_back(LoadFile(path, nullptr, id));
  std::set<FileId> visited{id};
  while (true) {
    const YamlDocument& current = chain.back();
    const YAML::Node include = current.root["include"];
    if (!include) break;
    SourceLocation where = current.LocationOf(include);
    if (!include.IsScalar() || include.Scalar().empty()) {
      throw InputError(where, "include", "expected the path of a scenario file");
    }
    const std::string& name = include.Scalar();
    for (const char ch : name) {
      if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7F) {
        throw InputError(where, "include",
                         "the path '" + InputExcerpt(name, kMaxPathInMessage) +
                             "' contains a control character");
      }
    }
    if (static_cast<int>(chain.size()) >= kMaxIncludeChain) {
      throw InputError(where, "include",
                       "the include chain is longer than " + std::to_string(kMaxIncludeChain) +
                           " files, the limit");
    }
    std::filesystem::path target(name);
    if (target.is_relative()) target = std::filesystem::path(current.file).parent_path() / target;
    YamlDocument next = LoadFile(target.string(), &where, id);
    if (!visited.insert(id).second) {
      throw InputError(
          where, "include",
          "include cycle through '" + InputExcerpt(target.string(), kMaxPathInMessage) + "'");
    }
    chain.push_back(std::move(next));
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
  throw InputError(LocationOfKey(key), MessageKey(FullKey(key)), message);
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
      throw InputError(doc_->LocationOf(item), MessageKey(FullKey(key)),
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
      throw InputError(doc_->LocationOf(row), MessageKey(FullKey(key)), where + example);
    }
    std::vector<double> values;
    for (const auto& item : row) {
      double v = 0.0;
      if (!item.IsScalar() || !YAML::convert<double>::decode(item, v) || !std::isfinite(v)) {
        throw InputError(doc_->LocationOf(item), MessageKey(FullKey(key)),
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
      throw InputError(doc_->LocationOf(item), MessageKey(FullKey(key)),
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
      throw InputError(doc_->LocationOf(kv.first), MessageKey(FullKey(key)),
                       "unknown key (known keys here: " + known + ")");
    }
  }
}

}  // namespace corridorsim

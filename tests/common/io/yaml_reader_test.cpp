#include "common/io/yaml_reader.h"

#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/support/expect_input_error.h"
#include "tests/support/scratch_dir.h"

namespace corridorsim {
namespace {

namespace fs = std::filesystem;
using test::Contains;
using test::InputErrorOf;

// The message of the InputError `f` throws (fails the test if it throws nothing).
template <class F>
std::string ErrorOf(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  FAIL("no InputError thrown");
  return "";
}

const std::string kData = CORRIDORSIM_TEST_DATA_DIR;

TEST_CASE("duplicate keys are rejected at the second occurrence", "[yaml]") {
  const auto msg =
      ErrorOf([] { YamlDocument::FromString("a: 1\nb:\n  c: 2\n  c: 3\n", "dup.yaml"); });
  CHECK(msg == "dup.yaml:4:3: b.c: duplicate key");
}

TEST_CASE("a syntax error names the file and position", "[yaml]") {
  const auto msg = ErrorOf([] { YamlDocument::FromString("a: [1, 2\nb: 3\n", "syntax.yaml"); });
  CHECK(msg.rfind("syntax.yaml:", 0) == 0);
  CHECK(msg.find("invalid YAML") != std::string::npos);
}

TEST_CASE("a document that is not a map is rejected", "[yaml]") {
  const auto msg = ErrorOf([] { YamlDocument::FromString("- 1\n- 2\n", "list.yaml"); });
  CHECK(msg.find("list.yaml:1:1: the document must be a map") == 0);
}

TEST_CASE("typed reads accept good values and leave absent keys at their defaults", "[yaml]") {
  const auto doc =
      YamlDocument::FromString("x: 2.5\nn: 7\nflag: true\nname: hello\nsub:\n  y: -1\n", "ok.yaml");
  SourceMap sources;
  YamlMap map(doc, doc.root, "", &sources);
  double x = 0, absent = 9.0;
  int n = 0;
  bool flag = false;
  std::string name;
  CHECK(map.Read("x", x));
  CHECK(map.Read("n", n));
  CHECK(map.Read("flag", flag));
  CHECK(map.Read("name", name));
  CHECK_FALSE(map.Read("absent", absent));
  YamlMap sub = map.Map("sub");
  double y = 0;
  CHECK(sub.Read("y", y));
  CHECK(x == 2.5);
  CHECK(n == 7);
  CHECK(flag);
  CHECK(name == "hello");
  CHECK(absent == 9.0);
  CHECK(y == -1.0);
  CHECK_NOTHROW(sub.RejectUnknownKeys());
  CHECK_NOTHROW(map.RejectUnknownKeys());
  const auto where = sources.Find("sub.y", SourceLocation{});
  CHECK(where.file == "ok.yaml");
  CHECK(where.line == 6);
  CHECK(where.column == 3);
}

TEST_CASE("wrong types are errors naming the key", "[yaml]") {
  const auto doc = YamlDocument::FromString(
      "x: abc\nn: 1.5\nflag: maybe\nm: [1]\nbig: 99999999999\ninf: .inf\n", "types.yaml");
  YamlMap map(doc, doc.root, "world", nullptr);
  double x = 0, inf = 0;
  int n = 0, big = 0;
  bool flag = false;
  CHECK(ErrorOf([&] { map.Read("x", x); }) ==
        "types.yaml:1:1: world.x: expected a finite number, got 'abc'");
  CHECK(ErrorOf([&] { map.Read("n", n); }) ==
        "types.yaml:2:1: world.n: expected an integer, got '1.5'");
  CHECK(ErrorOf([&] { map.Read("flag", flag); }) ==
        "types.yaml:3:1: world.flag: expected true or false, got 'maybe'");
  CHECK(ErrorOf([&] { map.Read("m", x); }) ==
        "types.yaml:4:1: world.m: expected a number, got a list");
  CHECK(ErrorOf([&] { map.Read("big", big); }).find("out of range") != std::string::npos);
  CHECK(ErrorOf([&] { map.Read("inf", inf); }).find("finite") != std::string::npos);
}

TEST_CASE("lists of rows read row by row and name the bad row", "[yaml]") {
  const auto doc = YamlDocument::FromString(
      "ok: [[1, 2.5, -3], [4, 5, 6]]\nempty: []\nshort:\n  - [1, 2, 3]\n  - [1, 2]\n"
      "text: [[1, x, 3]]\nflat: [1, 2, 3]\nscalar: 4\n",
      "rows.yaml");
  YamlMap map(doc, doc.root, "path", nullptr);
  std::vector<std::vector<double>> rows = {{9, 9, 9}};
  REQUIRE(map.Read("ok", rows, 3));
  CHECK(rows == std::vector<std::vector<double>>{{1, 2.5, -3}, {4, 5, 6}});
  REQUIRE(map.Read("empty", rows, 3));
  CHECK(rows.empty());
  CHECK_FALSE(map.Read("absent", rows, 3));
  CHECK(ErrorOf([&] { map.Read("short", rows, 3); }) ==
        "rows.yaml:5:5: path.short: row 2: expected a list of rows of 3 numbers");
  CHECK(ErrorOf([&] { map.Read("text", rows, 3); }) ==
        "rows.yaml:6:12: path.text: row 1: expected a finite number");
  CHECK(ErrorOf([&] { map.Read("flat", rows, 3); }) ==
        "rows.yaml:7:8: path.flat: row 1: expected a list of rows of 3 numbers");
  CHECK(ErrorOf([&] { map.Read("scalar", rows, 3); }).find("expected a list of rows of 3") !=
        std::string::npos);
}

TEST_CASE("unknown keys are errors listing the known ones", "[yaml]") {
  const auto doc = YamlDocument::FromString("lenght_m: 3\n", "typo.yaml");
  YamlMap map(doc, doc.root, "world", nullptr);
  double length = 0;
  map.Read("length_m", length);
  const auto msg = ErrorOf([&] { map.RejectUnknownKeys(); });
  CHECK(msg == "typo.yaml:1:1: world.lenght_m: unknown key (known keys here: length_m)");
}

TEST_CASE("enums accept only their names", "[yaml]") {
  enum class Colour { kRed, kBlue };
  const auto doc = YamlDocument::FromString("c: green\n", "enum.yaml");
  YamlMap map(doc, doc.root, "", nullptr);
  Colour c = Colour::kRed;
  const auto msg = ErrorOf([&] {
    map.ReadEnum("c", c, {{"red", Colour::kRed}, {"blue", Colour::kBlue}});
  });
  CHECK(msg == "enum.yaml:1:1: c: unknown value 'green' (expected one of: red, blue)");
}

TEST_CASE("include chains load base first", "[yaml]") {
  const auto chain = LoadWithIncludes(kData + "/includes/child.yaml");
  REQUIRE(chain.size() == 2);
  CHECK(chain[0].file.find("base.yaml") != std::string::npos);
  CHECK(chain[1].file.find("child.yaml") != std::string::npos);
}

TEST_CASE("a missing included file is an error at the include line", "[yaml]") {
  const auto msg = ErrorOf([] { LoadWithIncludes(kData + "/includes/missing_include.yaml"); });
  CHECK(msg.find("missing_include.yaml:2:10: include: included file") != std::string::npos);
  CHECK(msg.find("does not exist") != std::string::npos);
}

TEST_CASE("an include cycle is an error", "[yaml]") {
  const auto msg = ErrorOf([] { LoadWithIncludes(kData + "/includes/cycle_a.yaml"); });
  CHECK(msg.find("include cycle") != std::string::npos);
}

TEST_CASE("a missing file is an error naming it", "[yaml]") {
  const auto msg = ErrorOf([] { YamlDocument::Load("/nonexistent/x.yaml"); });
  CHECK(msg == "/nonexistent/x.yaml: cannot open the file");
}

TEST_CASE("absurdly deep nesting is rejected with a clear message", "[yaml]") {
  std::string text;
  for (int i = 0; i < 80; ++i) text += "[";
  for (int i = 0; i < 80; ++i) text += "]";
  const auto msg = ErrorOf([&] { YamlDocument::FromString("a: " + text + "\n", "deep.yaml"); });
  CHECK(msg.find("deep.yaml") == 0);
  CHECK(msg.find("nesting") != std::string::npos);
}

// ---- Files: only regular files of bounded size, read without blocking ------------------------

// A folder for the file tests; Write puts `text` (any bytes) into a file there.
struct Files {
  test::ScratchDir dir{"yaml_reader_files"};
  std::string Path(const std::string& name) const { return (dir.path() / name).string(); }
  std::string Write(const std::string& name, const std::string& text) const {
    std::ofstream(Path(name), std::ios::binary) << text;
    return Path(name);
  }
  // `child.yaml` holding `seed: 1` and `include: <target>` (line 2, column 10).
  std::string Including(const std::string& target) const {
    return Write("child.yaml", "seed: 1\ninclude: " + target + "\n");
  }
};

// The error of loading `path` as a scenario and, separately, as an include.
InputError LoadErrorOf(const std::string& path) {
  return InputErrorOf([&] { LoadWithIncludes(path); });
}

void CheckIncludeError(const Files& files, const std::string& target, const std::string& gist) {
  const InputError e = LoadErrorOf(files.Including(target));
  CAPTURE(e.what());
  CHECK(e.location().file == files.Path("child.yaml"));
  CHECK(e.location().line == 2);
  CHECK(e.location().column == 10);
  CHECK(e.key() == "include");
  CHECK(Contains(e.message(), gist));
}

TEST_CASE("a FIFO is refused without blocking, as scenario and as include", "[yaml][files]") {
  const Files files;
  const std::string fifo = files.Path("pipe.yaml");
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  // Opening a FIFO without a writer blocks forever unless it is opened non-blocking.
  const InputError e = LoadErrorOf(fifo);
  CHECK(std::string(e.what()) ==
        fifo + ": cannot open the file: it is a FIFO (named pipe), not a regular file");
  CheckIncludeError(files, "pipe.yaml", "included file '" + fifo + "' is a FIFO");
}

TEST_CASE("a device is refused without reading it", "[yaml][files]") {
  const Files files;
  for (const std::string device : {"/dev/zero", "/dev/null", "/dev/urandom"}) {
    CAPTURE(device);
    CHECK(Contains(LoadErrorOf(device).message(), "is a character device, not a regular file"));
    CheckIncludeError(files, device, "is a character device");
  }
}

TEST_CASE("a folder is refused, as scenario and as include", "[yaml][files]") {
  const Files files;
  fs::create_directories(files.Path("sub.yaml"));
  CHECK(Contains(LoadErrorOf(files.Path("sub.yaml")).message(), "is a folder"));
  CheckIncludeError(files, "sub.yaml", "is a folder, not a regular file");
}

TEST_CASE("a symbolic link loop and a dangling link are named as such", "[yaml][files]") {
  const Files files;
  fs::create_symlink(files.Path("loop_b.yaml"), files.Path("loop_a.yaml"));
  fs::create_symlink(files.Path("loop_a.yaml"), files.Path("loop_b.yaml"));
  fs::create_symlink(files.Path("nowhere.yaml"), files.Path("dangling.yaml"));
  CHECK(Contains(LoadErrorOf(files.Path("loop_a.yaml")).message(), "too many levels of symbolic"));
  CheckIncludeError(files, "loop_a.yaml", "too many levels of symbolic links");
  CHECK(Contains(LoadErrorOf(files.Path("dangling.yaml")).message(), "dangling"));
  CheckIncludeError(files, "dangling.yaml", "is a symbolic link to nothing (dangling)");
}

TEST_CASE("a link to a regular file loads, and including it again is a cycle", "[yaml][files]") {
  const Files files;
  files.Write("real.yaml", "seed: 3\ninclude: alias.yaml\n");
  fs::create_symlink(files.Path("real.yaml"), files.Path("alias.yaml"));
  // real.yaml includes itself through the link: the same file, however it is spelled.
  const InputError e = LoadErrorOf(files.Path("real.yaml"));
  CHECK(e.location().line == 2);
  CHECK(Contains(e.message(), "include cycle through '" + files.Path("alias.yaml") + "'"));
}

TEST_CASE("an over-long file name is an error with a bounded message", "[yaml][files]") {
  const Files files;
  const std::string component(300, 'n');  // NAME_MAX is 255
  CHECK(Contains(LoadErrorOf(files.Path(component + ".yaml")).message(),
                 "its name is longer than the system allows"));
  CheckIncludeError(files, component + ".yaml", "longer than the system allows");
  // Longer than PATH_MAX: the message keeps the head and tail of the name, not all of it.
  std::string deep;
  for (int i = 0; i < 100; ++i) deep += "/" + std::string(100, 'd');
  const InputError e = LoadErrorOf(deep + ".yaml");
  CHECK(Contains(e.message(), "longer than the system allows"));
  CHECK(std::string(e.what()).size() < 1200);
  CHECK(Contains(e.location().file, "..."));
}

TEST_CASE("a long include path is quoted as head...tail only", "[yaml][files]") {
  // Found by scenario_loader_fuzzer: a 1000-character include was quoted whole.
  const Files files;
  const std::string name = std::string(600, 'a') + "/" + std::string(400, 'b') + ".yaml";
  const InputError e = LoadErrorOf(files.Including(name));
  CHECK(e.key() == "include");
  CHECK(Contains(e.message(), "aaa...bbb"));
  CHECK_FALSE(Contains(e.message(), std::string(200, 'a')));
  CHECK(e.message().size() < 400);
}

TEST_CASE("a file larger than the limit is refused, one at the limit loads", "[yaml][files]") {
  const Files files;
  const std::string line = "# " + std::string(1022, 'c') + "\n";  // 1 KiB of comment
  std::string at_limit;
  while (at_limit.size() + line.size() <= kMaxYamlFileBytes) at_limit += line;
  at_limit.resize(kMaxYamlFileBytes - 8, 'c');
  at_limit += "\nseed: 1";  // exactly kMaxYamlFileBytes
  REQUIRE(at_limit.size() == kMaxYamlFileBytes);
  CHECK(LoadWithIncludes(files.Write("big.yaml", at_limit)).back().root["seed"].as<int>() == 1);
  files.Write("huge.yaml", at_limit + "\n");
  CHECK(std::string(LoadErrorOf(files.Path("huge.yaml")).what()) ==
        files.Path("huge.yaml") +
            ": cannot open the file: it is larger than the limit of 1048576 bytes (1 MiB)");
  CheckIncludeError(files, "huge.yaml", "is larger than the limit of 1048576 bytes");
  CHECK(
      Contains(InputErrorOf([&] { YamlDocument::FromString(at_limit + "\n", "t.yaml"); }).message(),
               "larger than the limit"));
}

TEST_CASE("an unreadable file is an error naming it", "[yaml][files]") {
  if (::geteuid() == 0) {
    SUCCEED("root reads any file: nothing to check");
    return;
  }
  const Files files;
  const std::string path = files.Write("secret.yaml", "seed: 1\n");
  fs::permissions(path, fs::perms::none);
  CHECK(Contains(LoadErrorOf(path).message(), "permission denied"));
  CheckIncludeError(files, "secret.yaml", "permission denied");
}

TEST_CASE("an include path with a NUL or control character is refused", "[yaml][files]") {
  const Files files;
  files.Write("base.yaml", "seed: 2\n");
  // "base.yaml\0x" would open base.yaml: the path must be refused, not cut at the NUL.
  CheckIncludeError(files, "\"base.yaml\\0x\"", "contains a control character");
  CheckIncludeError(files, "\"base\\n.yaml\"", "contains a control character");
}

TEST_CASE("an include chain longer than the limit is an error at the include", "[yaml][files]") {
  const Files files;
  for (int i = 0; i < kMaxIncludeChain; ++i) {
    files.Write("f" + std::to_string(i) + ".yaml",
                "include: f" + std::to_string(i + 1) + ".yaml\n");
  }
  files.Write("f" + std::to_string(kMaxIncludeChain) + ".yaml", "seed: 1\n");
  const InputError e = LoadErrorOf(files.Path("f0.yaml"));
  CHECK(e.location().file == files.Path("f" + std::to_string(kMaxIncludeChain - 1) + ".yaml"));
  CHECK(e.key() == "include");
  CHECK(Contains(e.message(), "longer than 16 files"));
  files.Write("f" + std::to_string(kMaxIncludeChain - 1) + ".yaml", "seed: 1\n");
  CHECK(LoadWithIncludes(files.Path("f0.yaml")).size() == std::size_t(kMaxIncludeChain));
}

// ---- Content that is not a scenario is never echoed ---------------------------------------------

TEST_CASE("a binary file is refused by position, without its content", "[yaml][files]") {
  const Files files;
  std::string bytes = "PASSWORD=hunter2 ";
  bytes += std::string(
      "\x7f"
      "ELF\x02\x01\x01\0\0",
      9);
  const std::string path = files.Write("program.yaml", bytes);
  const InputError e = LoadErrorOf(path);
  CHECK(std::string(e.what()) == path + ":1:18: not a YAML text file: control character 0x7f");
  CHECK_FALSE(Contains(e.what(), "hunter2"));
  const InputError latin1 =
      InputErrorOf([] { YamlDocument::FromString("a: caf\xe9\n", "l.yaml"); });
  CHECK(std::string(latin1.what()) == "l.yaml:1:7: not a YAML text file: byte 0xe9 is not UTF-8");
  // UTF-8 itself is fine, and so is a byte order mark.
  CHECK_NOTHROW(YamlDocument::FromString("\xef\xbb\xbfname: caf\xc3\xa9\n", "u.yaml"));
}

TEST_CASE("a text file that is not a YAML map is refused without quoting it", "[yaml][files]") {
  std::string prose;
  for (int i = 0; i < 2000; ++i)
    prose += "The quick brown fox jumps over the lazy dog " + std::to_string(i) + "\n";
  const InputError e = InputErrorOf([&] { YamlDocument::FromString(prose, "notes.txt"); });
  CHECK(std::string(e.what()) == "notes.txt:1:1: the document must be a map of keys");
}

TEST_CASE("keys and values put into messages are sanitised and cut short", "[yaml][files]") {
  const std::string long_key(100000, 'k');
  const auto doc = YamlDocument::FromString(
      "? " + long_key + "\n: 1\n\"bell\\a\\x1b[31mred\": 2\nx: " + std::string(50000, '9') + "e\n",
      "k.yaml");
  YamlMap map(doc, doc.root, "world", nullptr);
  double x = 0;
  const std::string value_error = ErrorOf([&] { map.Read("x", x); });
  CHECK(value_error.size() < 200);
  CHECK(Contains(value_error, "expected a finite number, got '999"));
  CHECK(Contains(value_error, "99...99"));
  CHECK(value_error.substr(value_error.size() - 4) == "99e'");  // the head and tail of the value
  map.Accept(long_key);
  const InputError control = InputErrorOf([&] { map.RejectUnknownKeys(); });
  CHECK(control.key() == "world.bell\\x07\\x1b[31mred");
  YamlMap other(doc, doc.root, "", nullptr);
  other.Accept("x");
  const InputError long_error = InputErrorOf([&] { other.RejectUnknownKeys(); });
  CHECK(long_error.key().size() <= 120);
  CHECK(std::string(long_error.what()).size() < 300);
}

TEST_CASE("InputExcerpt keeps short text, escapes controls and cuts between characters", "[yaml]") {
  CHECK(InputExcerpt("plain") == "plain");
  CHECK(InputExcerpt(std::string("a\0b\n", 4)) == "a\\x00b\\x0a");
  const std::string accents = std::string(200, 'a') + std::string(100, '\xc3');
  std::string e;
  for (int i = 0; i < 100; ++i) e += "\xc3\xa9";  // 100 x U+00E9
  const std::string cut = InputExcerpt(e, 21);
  CHECK(cut.size() <= 21);
  CHECK(cut == "\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9...\xc3\xa9\xc3\xa9\xc3\xa9");
  (void)accents;
}

// ---- One document, bounded work -----------------------------------------------------------------

TEST_CASE("a second YAML document is an error where it starts", "[yaml]") {
  CHECK(ErrorOf([] {
          YamlDocument::FromString("a: 1\n---\nb: 2\n", "two.yaml");
        }).rfind("two.yaml:2:1: a second YAML document starts here", 0) == 0);
  CHECK(ErrorOf([] {
          YamlDocument::FromString("a: 1\n...\nb: 2\n", "end.yaml");
        }).rfind("end.yaml:3:1: a second YAML document", 0) == 0);
  CHECK(ErrorOf([] {
          YamlDocument::FromString("a: 1\n---\n", "empty.yaml");
        }).rfind("empty.yaml:2:1: a second YAML document", 0) == 0);
  // One document with its markers is fine.
  CHECK(YamlDocument::FromString("---\na: 1\n...\n", "one.yaml").root["a"].as<int>() == 1);
}

// Nine levels of ten aliases each: 10^9 nodes for a walk, from a 1 KiB file.
std::string BillionLaughs() {
  std::string text = "a0: &a0 [lol, lol, lol, lol, lol, lol, lol, lol, lol, lol]\n";
  for (int i = 1; i <= 9; ++i) {
    const std::string prev = "*a" + std::to_string(i - 1);
    text += "a" + std::to_string(i) + ": &a" + std::to_string(i) + " [";
    for (int k = 0; k < 10; ++k) text += (k ? ", " : "") + prev;
    text += "]\n";
  }
  return "unknown_key:\n" + [&] {
    std::string indented;
    std::size_t start = 0;
    while (start < text.size()) {
      const std::size_t end = text.find('\n', start);
      indented += "  " + text.substr(start, end - start + 1);
      start = end + 1;
    }
    return indented;
  }();
}

TEST_CASE("billion laughs fails fast at the alias that crosses the node limit", "[yaml]") {
  const auto start = std::chrono::steady_clock::now();
  const InputError e = InputErrorOf([] { YamlDocument::FromString(BillionLaughs(), "lol.yaml"); });
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  CAPTURE(e.what());
  // a4 alone is 111111 nodes: the alias of a3 that crosses 100000 nodes is refused, in a4's line.
  CHECK(e.location().line == 6);
  CHECK(e.key() == "unknown_key.a4[7]");
  CHECK(e.message() ==
        "this alias makes the document larger than 100000 nodes, the limit (an alias counts as a "
        "copy of what its anchor names)");
  CHECK(seconds < 1.0);  // microseconds in fact; it hung before the bound
}

TEST_CASE("aliases of long text are bounded by the expanded text size", "[yaml]") {
  std::string text = "big: &big " + std::string(500000, 'b') + "\nlist: [";
  for (int i = 0; i < 20; ++i) text += (i ? ", " : "") + std::string("*big");
  text += "]\n";
  const InputError e = InputErrorOf([&] { YamlDocument::FromString(text, "text.yaml"); });
  CHECK(e.key() == "list[7]");
  CHECK(Contains(e.message(), "this alias makes the document larger than 4194304 bytes"));
}

TEST_CASE("an alias inside the node it names is refused", "[yaml]") {
  const InputError e =
      InputErrorOf([] { YamlDocument::FromString("a: &x [1, *x]\n", "self.yaml"); });
  CHECK(std::string(e.what()) == "self.yaml:1:11: a[1]: the alias names a node that contains it");
}

TEST_CASE("a huge list is refused before its nodes are built", "[yaml]") {
  std::string text = "distortion: [";
  for (std::size_t i = 0; i < kMaxYamlNodes; ++i) text += "1,";
  text += "1]\n";
  const InputError e = InputErrorOf([&] { YamlDocument::FromString(text, "list.yaml"); });
  CHECK(e.key() == "distortion[99997]");  // the 100001st node: map, key, list, 99998 items
  CHECK(e.message() == "the document is larger than 100000 nodes, the limit");
}

TEST_CASE("deep nesting of any kind is refused without exhausting the stack", "[yaml]") {
  const std::string flow(200000, '[');
  CHECK(Contains(ErrorOf([&] { YamlDocument::FromString("a: " + flow, "flow.yaml"); }),
                 "nesting is deeper than 64 levels"));
  std::string block;
  for (int i = 0; i < 100; ++i) block += std::string(static_cast<std::size_t>(i), ' ') + "k:\n";
  const InputError e = InputErrorOf([&] { YamlDocument::FromString(block, "block.yaml"); });
  CHECK(e.location().line == 65);  // the 65th map
  CHECK(Contains(e.message(), "nesting is deeper than 64 levels"));
  // 64 levels are allowed.
  std::string ok;
  for (int i = 0; i < 63; ++i) ok += "[";
  for (int i = 0; i < 63; ++i) ok += "]";
  CHECK_NOTHROW(YamlDocument::FromString("a: " + ok + "\n", "ok.yaml"));
}

TEST_CASE("a key that is not a plain name is refused", "[yaml]") {
  CHECK(ErrorOf([] { YamlDocument::FromString("? [a, b]\n: 1\n", "complex.yaml"); }) ==
        "complex.yaml:1:3: a key must be a name, not a map, a list or nothing");
  CHECK(ErrorOf([] { YamlDocument::FromString("w:\n  ~: 1\n", "null.yaml"); }) ==
        "null.yaml:2:3: w: a key must be a name, not a map, a list or nothing");
}

}  // namespace
}  // namespace corridorsim

#include "common/io/yaml_reader.h"

#include <string>
#include <vector>

#include <catch2/catch.hpp>

namespace corridorsim {
namespace {

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

}  // namespace
}  // namespace corridorsim

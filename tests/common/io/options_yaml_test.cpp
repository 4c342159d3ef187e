// Tests common/io/options_yaml.cpp: reading through a table (every kind, unknown keys, sections,
// named sections), the YAML echo (reads back as itself), docs rows and block replacement.
#include "common/io/options_yaml.h"

#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/support/expect_input_error.h"

namespace corridorsim {
namespace {

enum class Shape { kRound, kSquare };

struct Part {
  std::string id;
  double size_m = 0.5;
  bool on = true;
};

struct Thing {
  double length_m = 2.5;
  float gain = 0.35f;
  int count = 3;
  std::uint64_t seed = 7;
  std::string name = "a \"quoted\" name";
  Shape shape = Shape::kRound;
  std::vector<double> weights = {0.1, 0.2};
  Part part{"main", 0.25, false};
  std::vector<Part> parts = {Part{"left"}, Part{"right", 0.75}};
};

const OptionTable<Part>& PartTable() {
  static const OptionTable<Part> table = [] {
    OptionTable<Part> t;
    t.Add("size_m", &Part::size_m, "m", "its size").Greater(0);
    t.Add("on", &Part::on, "", "switched on");
    return t;
  }();
  return table;
}

const OptionTable<Thing>& ThingTable() {
  static const OptionTable<Thing> table = [] {
    OptionTable<Thing> t;
    t.Add("length_m", &Thing::length_m, "m", "a length").Range(0, 10);
    t.Add("gain", &Thing::gain, "", "a float");
    t.Add("count", &Thing::count, "", "a count");
    t.Add("seed", &Thing::seed, "", "a seed");
    t.Add("name", &Thing::name, "", "a | name");
    t.AddEnum("shape", &Thing::shape, {{"round", Shape::kRound}, {"square", Shape::kSquare}},
              "a shape");
    t.Add("weights", &Thing::weights, "", "a list");
    t.AddSection("part", &Thing::part, PartTable(), "a section");
    t.AddNamedSections(
        "parts", &Thing::parts, PartTable(), [](const Part& p) { return p.id; }, "named parts");
    return t;
  }();
  return table;
}

Thing Read(const std::string& text) {
  const YamlDocument doc = YamlDocument::FromString(text, "t.yaml");
  YamlMap map(doc, doc.root, "thing", nullptr);
  Thing t;
  ReadOptions(map, ThingTable(), t);
  return t;
}

TEST_CASE("a table reads every kind of key and leaves absent ones at their defaults",
          "[options][yaml]") {
  const Thing t = Read(
      "length_m: 4\ngain: 0.5\ncount: -2\nseed: 12\nname: x\nshape: square\nweights: [1, 2, 3]\n"
      "part: {on: true}\nparts:\n  right: {size_m: 0.125}\n");
  CHECK(t.length_m == 4);
  CHECK(t.gain == 0.5f);
  CHECK(t.count == -2);
  CHECK(t.seed == 12);
  CHECK(t.name == "x");
  CHECK(t.shape == Shape::kSquare);
  CHECK(t.weights == std::vector<double>{1, 2, 3});
  CHECK(t.part.on);
  CHECK(t.part.size_m == 0.25);
  CHECK(t.parts[0].size_m == 0.5);
  CHECK(t.parts[1].size_m == 0.125);
}

TEST_CASE("a table rejects unknown keys and wrong types at their key", "[options][yaml]") {
  CHECK(std::string(test::InputErrorOf([] { Read("lenght_m: 3\n"); }).what())
            .rfind("t.yaml:1:1: thing.lenght_m: unknown key (known keys here: count, gain, ", 0) ==
        0);
  CHECK(std::string(test::InputErrorOf([] { Read("part:\n  size: 3\n"); }).what())
            .rfind("t.yaml:2:3: thing.part.size: unknown key", 0) == 0);
  CHECK(std::string(test::InputErrorOf([] { Read("parts:\n  middle: {}\n"); }).what())
            .rfind("t.yaml:2:3: thing.parts.middle: unknown key", 0) == 0);
  CHECK(std::string(test::InputErrorOf([] { Read("count: 1.5\n"); }).what()) ==
        "t.yaml:1:1: thing.count: expected an integer, got '1.5'");
  CHECK(std::string(test::InputErrorOf([] { Read("shape: oval\n"); }).what()) ==
        "t.yaml:1:1: thing.shape: unknown value 'oval' (expected one of: round, square)");
}

TEST_CASE("the echo reads back as the same options and echoes as itself", "[options][yaml]") {
  Thing t;
  t.length_m = 1.0 / 3.0;
  t.gain = 0.1f;
  t.name = "line\nbreak \\ \"q\"";
  const std::string echo = OptionsYaml(ThingTable(), t);
  CHECK(echo.rfind("length_m: 0.3333333333333333\ngain: 0.1\ncount: 3\n", 0) == 0);
  CHECK(test::Contains(echo, "part:\n  size_m: 0.25\n  on: false\nparts:\n  left:\n    size_m: "));
  const Thing back = Read(echo);
  CHECK(back.length_m == t.length_m);
  CHECK(back.gain == t.gain);
  CHECK(back.name == t.name);
  CHECK(OptionsYaml(ThingTable(), back) == echo);
}

TEST_CASE("an empty map is written as {}", "[options][yaml]") {
  OptionsYamlWriter out;
  out.BeginMap("a");
  out.BeginMap("b");
  out.EndMap();
  out.Scalar("c", "1");
  out.EndMap();
  out.BeginMap("d");
  out.EndMap();
  CHECK(out.text() == "a:\n  b: {}\n  c: 1\nd: {}\n");
}

TEST_CASE("docs blocks: one per section, named sections with their defaults side by side",
          "[options][yaml]") {
  const Thing defaults;
  const std::vector<OptionsDocBlock> blocks = OptionsDocBlocks(ThingTable(), &defaults, "thing");
  REQUIRE(blocks.size() == 3);
  CHECK(blocks[0].name == "thing");
  CHECK(test::Contains(blocks[0].text, "| `length_m` | m | 2.5 | [0, 10] | a length |\n"));
  CHECK(test::Contains(blocks[0].text, "| `shape` |  | `round` | `round`, `square` | a shape |"));
  CHECK(test::Contains(blocks[0].text, "a \\| name"));
  CHECK(blocks[1].name == "part");
  CHECK(blocks[2].name == "parts");
  CHECK(
      test::Contains(blocks[2].text, "| `size_m` | m | left: 0.5, right: 0.75 | > 0 | its size |"));

  const std::string doc = "intro\n<!-- options:part -->\nold\n<!-- /options -->\nend\n";
  std::vector<std::string> problems;
  const std::string updated = ReplaceOptionsDocBlocks(doc, blocks, &problems);
  CHECK(updated == "intro\n<!-- options:part -->\n" + blocks[1].text + "<!-- /options -->\nend\n");
  // The old text differs, and two blocks have no markers.
  CHECK(problems.size() == 3);
  std::vector<std::string> again;
  ReplaceOptionsDocBlocks(updated, {blocks[1]}, &again);
  CHECK(again.empty());
}

}  // namespace
}  // namespace corridorsim

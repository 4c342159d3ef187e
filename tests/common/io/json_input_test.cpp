// Tests common/io/json_input: the bounds checked before a user's JSON is parsed (nesting and
// values, at the line and column where they are passed), and reading a top-level array entry by
// entry.
#include "common/io/json_input.h"

#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "common/error.h"
#include "tests/support/expect_input_error.h"

namespace corridorsim {
namespace {

using test::InputErrorOf;

TEST_CASE("JSON nesting is bounded at the line and column of the bracket past the bound",
          "[common][json_input]") {
  CHECK_NOTHROW(
      ParseJsonInput(std::string(kMaxJsonDepth, '[') + std::string(kMaxJsonDepth, ']'), "f.json"));
  const InputError e =
      InputErrorOf([] { ParseJsonInput("{\n \"a\": " + std::string(80, '['), "f.json"); });
  CHECK(e.location().file == "f.json");
  CHECK(e.location().line == 2);
  CHECK(e.location().column == 7 + kMaxJsonDepth - 1);
  CHECK(e.message() == "more than 64 nested arrays and objects");
  // Brackets in strings, escaped quotes included, are text; closing brackets free depth again.
  const std::string text = "[\"" + std::string(100, '[') + "\\\"[[\", " + std::string(60, '[') +
                           std::string(60, ']') + ", " + std::string(70, '{') + "]";
  CHECK(
      InputErrorOf([&] { ParseJsonInput(text, "f.json"); }).message().starts_with("more than 64"));
  CHECK_NOTHROW(CheckJsonInputBounds(
      "[\"" + std::string(100, '{') + "\", " + std::string(60, '[') + std::string(60, ']') + "]",
      "f.json", kMaxJsonValues));
}

TEST_CASE("JSON values are counted in the document or per top-level element",
          "[common][json_input]") {
  // [1, "a", {"k": [true, null]}] holds 8 values: the array, 1, "a", the object, "k", its
  // array, true, null.
  const std::string text = "[1, \"a\", {\"k\": [true, null]}]";
  CHECK_NOTHROW(CheckJsonInputBounds(text, "f.json", 8));
  const InputError e = InputErrorOf([&] { CheckJsonInputBounds(text, "f.json", 7); });
  CHECK(e.location().column == 23);
  CHECK(e.message() == "more than 7 values (numbers, strings, arrays and objects)");
  // Per element: the largest element ({"k": [true, null]}) holds 5.
  CHECK_NOTHROW(CheckJsonInputBounds(text, "f.json", 5, true));
  CHECK(InputErrorOf([&] { CheckJsonInputBounds(text, "f.json", 4, true); }).message() ==
        "more than 4 values in one element of the top-level array (numbers, strings, arrays and "
        "objects)");
}

TEST_CASE("a top-level array is read entry by entry", "[common][json_input]") {
  std::vector<std::string> seen;
  ParseJsonArrayInput("[1, {\"a\": [2]}, [3], \"x\"]", "f.json", "not an array",
                      [&](std::size_t i, const nlohmann::ordered_json& v) {
                        CHECK(i == seen.size());
                        seen.push_back(v.dump());
                      });
  CHECK(seen == std::vector<std::string>{"1", "{\"a\":[2]}", "[3]", "\"x\""});
  for (const char* text : {"{\"a\": 1}", "7", "\"s\""}) {
    INFO(text);
    const InputError e = InputErrorOf([&] {
      ParseJsonArrayInput(text, "f.json", "not an array", [](std::size_t, const auto&) {});
    });
    CHECK(std::string(e.what()) == "f.json: not an array");
  }
  // Entries before a syntax error have been handed over; the error names the byte.
  seen.clear();
  const InputError e = InputErrorOf([&] {
    ParseJsonArrayInput("[1, 2, }", "f.json", "not an array",
                        [&](std::size_t, const auto& v) { seen.push_back(v.dump()); });
  });
  CHECK(seen == std::vector<std::string>{"1", "2"});
  CHECK(e.message().starts_with("malformed JSON at byte 8"));
}

}  // namespace
}  // namespace corridorsim

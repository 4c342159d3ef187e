// Reading options structs in tests (STYLE.md 4: a free ParseXxxOptions next to each): what a
// parser reads from a YAML text over the defaults (ParsedOptions), and the InputError it throws
// on a bad text (ParseErrorOf).
#pragma once

#include <string>

#include "common/error.h"
#include "common/io/yaml_reader.h"
#include "tests/support/expect_input_error.h"

namespace corridorsim::test {

/// What `parse` reads from the YAML `text` over the default options: a document named `file`
/// whose keys are named under `path` (path "robot.odometry": "robot.odometry.rate_hz").
template <class Options>
Options ParsedOptions(void (*parse)(YamlMap&, Options&), const std::string& text,
                      const std::string& file, const std::string& path) {
  const YamlDocument doc = YamlDocument::FromString(text, file);
  YamlMap map(doc, doc.root, path, nullptr);
  Options options;
  parse(map, options);
  return options;
}

/// The InputError `parse` throws on the YAML `text` (named as in ParsedOptions); fails the test
/// when it throws none.
template <class Options>
InputError ParseErrorOf(void (*parse)(YamlMap&, Options&), const std::string& text,
                        const std::string& file, const std::string& path) {
  return InputErrorOf([&] { ParsedOptions(parse, text, file, path); });
}

}  // namespace corridorsim::test

// What the tests of DatasetExporter (tests/harness/run/export_test.cpp, export_sensor_test.cpp)
// share: the clocks they feed it, the tolerances of the layouts they read back, and the rows of
// an exported text file. Both live in namespace corridorsim::export_tests, where these are named
// once.
#pragma once

#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "common/time.h"
#include "tests/support/tolerances.h"

namespace corridorsim::export_tests {

namespace fs = std::filesystem;
using test::kEurocPoseTol;
using test::kTumRotationTol;
using test::kTumTranslationTolM;

inline constexpr double kDeg = std::numbers::pi / 180.0;
inline constexpr TimeNs kFramePeriodNs = 300'000'000;  // the rig's 10/3 Hz
inline constexpr TimeNs kTruthPeriodNs = 10'000'000;   // 100 Hz

inline std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  REQUIRE(in.good());
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Lines that are not comments, split at `separator` (' ' or ',').
inline std::vector<std::vector<std::string>> Rows(const fs::path& path, char separator) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream text(ReadText(path));
  std::string line;
  while (std::getline(text, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> fields;
    std::istringstream fields_text(line);
    std::string field;
    while (std::getline(fields_text, field, separator)) fields.push_back(field);
    rows.push_back(fields);
  }
  return rows;
}

}  // namespace corridorsim::export_tests

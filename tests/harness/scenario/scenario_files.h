// Scenario files for the scenario tests: a fresh fixture folder and the message a bad scenario
// gives (tests/harness/scenario/scenario_test.cpp, scenario_pipelines_test.cpp).
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include <catch2/catch.hpp>

#include "common/error.h"
#include "harness/scenario/scenario.h"
#include "tests/support/expect_input_error.h"

namespace corridorsim::test {

// A fresh folder for YAML fixtures under the system temp folder, removed at the end of the test.
class FixtureDir {
 public:
  FixtureDir()
      : path_(std::filesystem::temp_directory_path() /
              ("corridorsim_scenario_test_" + std::to_string(::getpid()) + "_" +
               std::to_string(counter_++))) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~FixtureDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  FixtureDir(const FixtureDir&) = delete;
  FixtureDir& operator=(const FixtureDir&) = delete;

  // Writes `text` to `name` in this folder and returns its path.
  std::string Write(const std::string& name, const std::string& text) const {
    const std::filesystem::path path = path_ / name;
    std::ofstream out(path, std::ios::binary);
    out << text;
    REQUIRE(out.good());
    return path.string();
  }
  std::string Path(const std::string& name) const { return (path_ / name).string(); }

 private:
  static inline int counter_ = 0;
  std::filesystem::path path_;
};

// The full message of the InputError that loading `text` as a scenario throws.
inline std::string LoadError(const std::string& text) {
  const FixtureDir dir;
  const std::string path = dir.Write("s.yaml", text);
  const InputError e = InputErrorOf([&] { LoadScenario(path); });
  const std::string what = e.what();
  // Every message starts with the file; tests below compare what follows it.
  REQUIRE(what.rfind(path + ":", 0) == 0);
  return what.substr(path.size());
}

}  // namespace corridorsim::test

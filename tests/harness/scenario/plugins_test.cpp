// harness/scenario/plugins.h: a plugin library registers its pipeline types, which a scenario then
// names like shipped ones; every way a library can fail to be a plugin is an InputError at the line
// that names it, with the reason (docs/plugins.md, "Failures").

#include "harness/scenario/plugins.h"

#include <filesystem>
#include <fstream>
#include <string>

#include <catch2/catch.hpp>

#include "common/io/sha256.h"
#include "harness/scenario/scenario.h"
#include "slam/registry.h"
#include "slam/sdk_version.h"
#include "tests/support/expect_input_error.h"
#include "tests/support/scratch_dir.h"

namespace corridorsim {
namespace {

namespace fs = std::filesystem;
using test::Contains;
using test::InputErrorOf;

const SourceLocation kWhere{"s.yaml", 7, 3};

// The test plugins tests/CMakeLists.txt builds (tests/plugins/echo_plugin.cpp).
fs::path Plugin(const std::string& name) {
  return fs::path(CORRIDORSIM_TEST_PLUGIN_DIR) / (name + ".so");
}

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

TEST_CASE("plugins: a plugin registers its types; loading it again gives the same record") {
  const LoadedPlugin plugin = LoadPlugin(Plugin("test_echo_plugin"), kWhere);
  CHECK(plugin.name == "test_echo_plugin");
  CHECK(plugin.version == "2.5.0");
  CHECK(plugin.sdk_version == CORRIDORSIM_VERSION);
  CHECK(plugin.path == fs::canonical(Plugin("test_echo_plugin")));
  CHECK(plugin.sha256 == Sha256Hex(test::FileBytes(Plugin("test_echo_plugin"))));
  REQUIRE(plugin.types == std::vector<std::string>{"test_echo"});
  const std::optional<slam::PipelineType> type = slam::FindPipelineType("test_echo");
  REQUIRE(type);
  CHECK(type->library == plugin.path.string());
  CHECK(slam::NewPipelineOptions("test_echo") != nullptr);
  // Not among the shipped types (the generated docs list those only).
  for (const slam::PipelineType& shipped : slam::ShippedPipelineTypes()) {
    CHECK(shipped.name != "test_echo");
  }
  const LoadedPlugin again = LoadPlugin(Plugin("test_echo_plugin"), kWhere);
  CHECK(again.types == plugin.types);
  CHECK(FindLoadedPlugin(plugin.path) != nullptr);
  CHECK(Contains(DescribePlugin(plugin), "| `scale` |  | 1 | [0.5, 2] |"));
}

TEST_CASE("plugins: a library that cannot be a plugin is an input error naming why") {
  test::ScratchDir dir("plugins_test");
  WriteText(dir.path() / "text.so", "not an ELF file\n");
  struct Case {
    fs::path path;
    std::string gist;
  };
  const Case cases[] = {
      {dir.path() / "missing.so", "does not exist"},
      {dir.path(), "is not a regular file"},
      {dir.path() / "text.so", "does not load: "},
      {Plugin("test_broken_plugin_1"), "has no entry point corridorsim_plugin_info"},
      {Plugin("test_broken_plugin_2"), "was built against the corridorsim SDK ABI version " +
                                           std::to_string(CORRIDORSIM_SDK_ABI_VERSION + 98) +
                                           "; this corridorsim " + CORRIDORSIM_VERSION +
                                           " has SDK ABI version " +
                                           std::to_string(CORRIDORSIM_SDK_ABI_VERSION)},
      {Plugin("test_broken_plugin_3"), "registers the type 'odometry', which corridorsim ships"},
      {Plugin("test_broken_plugin_4"), "'Echo-Pipeline', which is not a pipeline name"},
      {Plugin("test_broken_plugin_5"),
       "threw while registering its types: cannot find my configuration"},
      {Plugin("test_broken_plugin_6"), "std::string's ABI (_GLIBCXX_USE_CXX11_ABI)"},
  };
  for (const Case& c : cases) {
    INFO(c.path.string());
    const InputError e = InputErrorOf([&] { LoadPlugin(c.path, kWhere); });
    CHECK(e.location().file == "s.yaml");
    CHECK(e.location().line == 7);
    CHECK(e.key() == "plugins");
    CHECK(Contains(e.message(), "the plugin library '"));
    CHECK(Contains(e.message(), c.gist));
  }
  // None of them registered anything.
  CHECK_FALSE(slam::FindPipelineType("Echo-Pipeline"));
}

TEST_CASE("plugins: a plugin of the old std::string ABI is refused naming its symbol and the fix") {
  // dlopen() fails on the SDK function it calls (tests/plugins/old_string_abi_plugin.cpp) before
  // corridorsim_plugin_info can be read: the message demangles the symbol and says what to rebuild.
  const InputError e =
      InputErrorOf([&] { LoadPlugin(Plugin("test_old_string_abi_plugin"), kWhere); });
  CHECK(e.location().line == 7);
  CHECK(e.key() == "plugins");
  CHECK(Contains(e.message(), "does not load: "));
  CHECK(Contains(e.message(),
                 "undefined symbol: corridorsim::slam::IsPipelineName(std::string const&) "
                 "(_ZN11corridorsim4slam14IsPipelineNameERKSs)"));
  CHECK(Contains(e.message(), "old std::string ABI (_GLIBCXX_USE_CXX11_ABI=0)"));
  CHECK(Contains(e.message(), "rebuild it with _GLIBCXX_USE_CXX11_ABI=1"));
  CHECK(Contains(e.message(), "by the compiler corridorsim was built with ("));
  CHECK(e.message().find('\n') == std::string::npos);
  CHECK_FALSE(slam::FindPipelineType("old_abi"));
}

TEST_CASE("plugins: a type another plugin registered is taken") {
  const LoadedPlugin first = LoadPlugin(Plugin("test_echo_plugin"), kWhere);
  test::ScratchDir dir("plugins_taken_test");
  // The same code in another file: another library, whose type name is taken.
  fs::copy_file(Plugin("test_echo_plugin"), dir.path() / "other.so");
  const InputError e = InputErrorOf([&] { LoadPlugin(dir.path() / "other.so", kWhere); });
  CHECK(Contains(e.message(), "registers the type 'test_echo', which the plugin '" +
                                  first.path.string() + "' registered"));
}

TEST_CASE("plugins: a scenario names a library relative to itself and uses its types") {
  test::ScratchDir dir("plugins_scenario_test");
  fs::create_directories(dir.path() / "lib");
  // A link, so that the library is the one other test cases load (a copy would register its
  // type a second time, which a process that runs every case refuses).
  fs::create_symlink(fs::canonical(Plugin("test_echo_plugin")), dir.path() / "lib" / "echo.so");
  WriteText(dir.path() / "s.yaml",
            "plugins: [lib/echo.so]\n"
            "pipelines:\n"
            "  mine: {type: test_echo, scale: 1.5}\n"
            "  odometry: {}\n");
  const Scenario scenario = LoadScenario((dir.path() / "s.yaml").string());
  REQUIRE(scenario.plugins == std::vector<fs::path>{fs::canonical(dir.path() / "lib" / "echo.so")});
  REQUIRE(scenario.pipelines.size() == 2);
  CHECK(scenario.pipelines[0].type == "test_echo");
  // The echo names the library by its absolute path: it is read from the run folder.
  const std::string echo = ResolvedScenarioYaml(scenario, 1);
  CHECK(Contains(echo, "plugins: [\"" + scenario.plugins[0].string() + "\"]"));
  CHECK(Contains(echo, "scale: 1.5"));

  // The type's option table checks its keys like a shipped one's.
  WriteText(dir.path() / "bad.yaml",
            "plugins: [lib/echo.so]\n"
            "pipelines:\n"
            "  mine: {type: test_echo, scale: 9}\n");
  const InputError bound = InputErrorOf([&] { LoadScenario((dir.path() / "bad.yaml").string()); });
  CHECK(bound.location().line == 3);
  CHECK(bound.key() == "pipelines.mine.scale");
  WriteText(dir.path() / "unknown.yaml",
            "plugins: [lib/echo.so]\n"
            "pipelines:\n"
            "  mine: {type: test_echo, gain: 1}\n");
  const InputError unknown =
      InputErrorOf([&] { LoadScenario((dir.path() / "unknown.yaml").string()); });
  CHECK(unknown.key() == "pipelines.mine.gain");

  // A missing library: at its line in the list.
  WriteText(dir.path() / "missing.yaml",
            "pipelines:\n"
            "  odometry: {}\n"
            "plugins:\n"
            "  - lib/echo.so\n"
            "  - lib/nothing.so\n");
  const InputError missing =
      InputErrorOf([&] { LoadScenario((dir.path() / "missing.yaml").string()); });
  CHECK(missing.location().line == 5);
  CHECK(missing.key() == "plugins");
  CHECK(Contains(missing.message(), "does not exist"));
}

TEST_CASE("plugins: a program that disables loading refuses every library") {
  DisablePluginLoading();
  const InputError e = InputErrorOf([&] { LoadPlugin(Plugin("test_echo_plugin"), kWhere); });
  CHECK(Contains(e.message(), "this program loads no plugins"));
}

}  // namespace
}  // namespace corridorsim

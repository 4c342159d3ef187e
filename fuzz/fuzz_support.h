#pragma once
// What the fuzz targets that load YAML files share (docs/fuzzing.md): a private temporary folder
// of includable files (copies of the shipped scenarios and tests/data/includes/*.yaml, and the
// files a loader must refuse without reading or blocking: fifo.yaml, zero.yaml -> /dev/zero,
// link_loop.yaml, dangling.yaml, folder.yaml), the check that an input's `include:` stays inside
// it, the input taken in as a scenario file (plugin loading off), and the check that an error
// message quotes the input only briefly.

#include <sys/stat.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <system_error>
#include <utility>

#include "common/error.h"
#include "common/io/yaml_reader.h"
#include "fuzz/fuzz_checks.h"
#include "harness/scenario/plugins.h"

namespace corridorsim::fuzz {

inline void WriteFile(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) Bug("cannot write " + path.string());
}

/// The private folder of includable files, made once (removed at exit).
inline const std::filesystem::path& IncludeFolder() {
  namespace fs = std::filesystem;
  static const fs::path folder = [] {
    char pattern[] = "/tmp/corridorsim_fuzz_XXXXXX";
    const char* made = ::mkdtemp(pattern);
    if (!made) Bug("mkdtemp failed");
    static fs::path dir;
    dir = made;
    std::atexit([] {
      std::error_code ignored;
      fs::remove_all(dir, ignored);
    });
    const fs::path source(CORRIDORSIM_SOURCE_DIR);
    for (const fs::path& from : {source / "scenarios", source / "tests/data/includes"}) {
      for (const fs::directory_entry& entry : fs::directory_iterator(from)) {
        if (entry.path().extension() == ".yaml") {
          fs::copy_file(entry.path(), dir / entry.path().filename(),
                        fs::copy_options::overwrite_existing);
        }
      }
    }
    if (::mkfifo((dir / "fifo.yaml").c_str(), 0600) != 0) Bug("mkfifo failed");
    fs::create_symlink("/dev/zero", dir / "zero.yaml");
    fs::create_symlink(dir / "link_loop2.yaml", dir / "link_loop.yaml");
    fs::create_symlink(dir / "link_loop.yaml", dir / "link_loop2.yaml");
    fs::create_symlink(dir / "nowhere.yaml", dir / "dangling.yaml");
    fs::create_directory(dir / "folder.yaml");
    return dir;
  }();
  return folder;
}

/// True when the input's `include:` (if it parses and has one) stays inside IncludeFolder(): not
/// absolute and no `..`. The included copies include only each other by plain names.
inline bool IncludeStaysInside(const std::string& text) {
  try {
    const YamlDocument doc = YamlDocument::FromString(text, "input.yaml");
    const YAML::Node include = doc.root["include"];
    if (!include || !include.IsScalar()) return true;
    const std::filesystem::path target(include.Scalar());
    if (target.is_absolute() || target.has_root_name() || target.has_root_directory()) {
      return false;
    }
    for (const std::filesystem::path& part : target) {
      if (part == "..") return false;
    }
  } catch (const InputError&) {
    // The loader stops at the same error before it follows any include.
  }
  return true;
}

/// Writes the input to input.yaml in IncludeFolder() and returns its path; nothing when its
/// `include:` would leave that folder (the target then returns -1: not a useful input).
inline std::optional<std::filesystem::path> WriteInput(const std::string& text) {
  if (!IncludeStaysInside(text)) return std::nullopt;
  const std::filesystem::path input = IncludeFolder() / "input.yaml";
  WriteFile(input, text);
  return input;
}

/// An input as the text of a scenario file and the path it is written to (WriteInput).
struct ScenarioInput {
  std::string text;
  std::filesystem::path path;
};

/// What a target that loads the input as a scenario file does first: plugin loading disabled,
/// the input written by WriteInput. Nothing when its `include:` would leave IncludeFolder() (the
/// target then returns -1).
inline std::optional<ScenarioInput> TakeScenarioInput(const std::uint8_t* data, std::size_t size) {
  // A scenario's `plugins:` would dlopen() whatever library an input names: never here.
  static const bool no_plugins = (DisablePluginLoading(), true);
  (void)no_plugins;
  std::string text(reinterpret_cast<const char*>(data), size);
  std::optional<std::filesystem::path> written = WriteInput(text);
  if (!written) return std::nullopt;
  return ScenarioInput{std::move(text), std::move(*written)};
}

/// A message quotes at most a short excerpt of the input (InputExcerpt: a path at most 240
/// bytes, a key 120, a value 80): any 300 bytes of it in a row contain one of these aligned
/// 250-byte windows (a step of 50), and no quote of 240 bytes or less does.
inline void CheckShortQuotes(const InputError& error, const std::string& text) {
  const std::string message = error.what();
  for (std::size_t at = 0; at + 250 <= text.size(); at += 50) {
    if (message.find(text.substr(at, 250)) != std::string::npos) {
      Bug("an error message quotes the input at length: " + message);
    }
  }
}

/// Runs `load` (the target's loader on the input): true when it loaded, false when it refused
/// the input with an InputError (a short one: CheckShortQuotes); any other exception is a bug.
template <class Load>
bool LoadedOrRefused(const std::string& text, const std::string& loader, Load&& load) {
  try {
    load();
    return true;
  } catch (const InputError& e) {
    CheckShortQuotes(e, text);
    return false;  // bad input, reported as it should be
  } catch (const std::exception& e) {
    Bug(loader + " threw something other than InputError: " + e.what());
  }
}

}  // namespace corridorsim::fuzz

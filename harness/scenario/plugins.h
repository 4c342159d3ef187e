#pragma once
// Pipeline plugins: shared libraries a scenario names under `plugins:` (paths relative to the
// scenario file, like `include:`), each of which registers pipeline types through the entry
// points of slam/plugin.h. Loading checks, in order: the path is a regular file (followed through
// links) of at most kMaxPluginBytes; dlopen() succeeds (else its dlerror() text); the library has
// corridorsim_plugin_info; the SDK ABI version, std::string's ABI and Eigen's version it was
// built with are this program's; it has corridorsim_plugin_register, which
// returns normally; every type name it adds is a valid pipeline name, taken neither by a shipped
// type, another plugin nor itself. Any failure is an InputError (exit 2) at the scenario line
// that names the library. A library is loaded once per process (by its canonical path) and
// never unloaded: its types stay registered. docs/plugins.md.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "common/error.h"

namespace corridorsim {

/// The largest plugin library loaded (its bytes are hashed for provenance before it is loaded).
inline constexpr std::uintmax_t kMaxPluginBytes = std::uintmax_t{512} << 20;

/// A loaded plugin, as provenance.json records it.
struct LoadedPlugin {
  std::filesystem::path path;      // canonical
  std::string sha256;              // of the file's bytes when it was loaded (what sha256sum prints)
  std::string name;                // the plugin's name, as it reports it
  std::string version;             // the plugin's version, as it reports it
  std::string sdk_version;         // the corridorsim version of the SDK it was built against
  std::vector<std::string> types;  // the pipeline types it registered, in order
};

/// Loads the plugin library at `path` (relative paths are taken as they are: the caller resolves
/// them against the scenario's folder) and registers its types; returns its record. `where` is
/// the scenario line that names it and `key` the key there, for errors.
LoadedPlugin LoadPlugin(const std::filesystem::path& path, const SourceLocation& where,
                        const std::string& key = "plugins");

/// What `corridorsim plugin LIB` prints: the plugin's name, version, SDK version, file and
/// SHA-256, then each type it registers with its options as docs/scenarios.md shows the shipped
/// ones (Markdown tables: key, unit, default, bounds, meaning).
std::string DescribePlugin(const LoadedPlugin& plugin);

/// The record of the plugin loaded from canonical path `path`, or nullptr.
const LoadedPlugin* FindLoadedPlugin(const std::filesystem::path& path);

/// Refuses every later LoadPlugin (an InputError saying so): the fuzz targets parse scenarios
/// that name libraries, and must never load one.
void DisablePluginLoading();

}  // namespace corridorsim

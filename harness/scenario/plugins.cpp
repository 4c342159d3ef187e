#include "harness/scenario/plugins.h"

#include <dlfcn.h>

#include <algorithm>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <system_error>
#include <tuple>
#include <utility>

#include "common/io/atomic_file.h"
#include "common/io/input_text.h"
#include "common/io/options_yaml.h"
#include "common/io/sha256.h"
#include "harness/scenario/plugin_load_error.h"
#include "slam/plugin.h"

namespace corridorsim {
namespace {

constexpr std::size_t kMaxTextFromPlugin = 200;  // its name, version, an exception's text

struct Registry {
  std::mutex mutex;
  bool disabled = false;
  std::map<std::filesystem::path, LoadedPlugin> loaded;
};

Registry& Plugins() {
  static Registry registry;
  return registry;
}

// Text a library gave (dlerror(), what it reports, what it throws), made safe to print.
std::string FromLibrary(const char* text) {
  return text ? InputExcerpt(text, kMaxTextFromPlugin) : std::string("(none)");
}

std::string VersionText(int version) {
  return version < 0 ? std::string("none") : std::to_string(version);
}

// Collects the types a plugin adds; the loader checks them before any is registered.
class CollectingRegistrar : public slam::PluginRegistrar {
 public:
  void Add(slam::PipelineType type) override { types.push_back(std::move(type)); }
  std::vector<slam::PipelineType> types;
};

}  // namespace

void DisablePluginLoading() {
  const std::lock_guard<std::mutex> lock(Plugins().mutex);
  Plugins().disabled = true;
}

const LoadedPlugin* FindLoadedPlugin(const std::filesystem::path& path) {
  const std::lock_guard<std::mutex> lock(Plugins().mutex);
  const auto it = Plugins().loaded.find(path);
  return it == Plugins().loaded.end() ? nullptr : &it->second;
}

LoadedPlugin LoadPlugin(const std::filesystem::path& path, const SourceLocation& where,
                        const std::string& key) {
  Registry& registry = Plugins();
  const std::lock_guard<std::mutex> lock(registry.mutex);
  const std::string shown = "'" + PathExcerpt(path.string()) + "'";
  const auto fail = [&](const std::string& message) {
    throw InputError(where, key, "the plugin library " + shown + " " + message);
  };
  if (registry.disabled) fail("is not loaded: this program loads no plugins");
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (error || !std::filesystem::exists(status)) fail("does not exist");
  if (!std::filesystem::is_regular_file(status)) fail("is not a regular file");
  const std::filesystem::path canonical = std::filesystem::canonical(path, error);
  if (error) fail("cannot be resolved: " + error.message());
  if (const auto it = registry.loaded.find(canonical); it != registry.loaded.end()) {
    return it->second;  // loaded before (an include chain, a second scenario of one process)
  }
  std::string content;
  try {
    content = ReadRegularFile(canonical, kMaxPluginBytes);  // bounded, never blocks
  } catch (const InputError& e) {
    fail("cannot be read: " + e.message());
  }
  LoadedPlugin plugin;
  plugin.path = canonical;
  plugin.sha256 = Sha256Hex(content);
  content.clear();
  content.shrink_to_fit();

  // RTLD_NOW: an undefined symbol is an error here, not a crash in the middle of a run.
  // RTLD_LOCAL: two plugins' own symbols never resolve against each other.
  dlerror();
  void* handle = dlopen(canonical.c_str(), RTLD_NOW | RTLD_LOCAL);
  // Its symbols are resolved and its static initializers run here, before any check below: a
  // library of another std::string ABI or SDK fails here, with its symbol demangled and what to
  // rebuild.
  if (!handle) {
    const char* reason = dlerror();
    fail("does not load: " + (reason ? ExplainDlopenError(reason) : std::string("(no reason)")));
  }
  // Never dlclose()d: its types' code must stay, and unloading C++ code is not safe in general.
  using InfoFunction = const CorridorsimPluginInfo* (*)();
  using RegisterFunction = void (*)(slam::PluginRegistrar*);
  dlerror();
  auto info_function = reinterpret_cast<InfoFunction>(dlsym(handle, "corridorsim_plugin_info"));
  if (!info_function) {
    fail(
        "has no entry point corridorsim_plugin_info (is it a corridorsim plugin? it defines "
        "one with CORRIDORSIM_PLUGIN, slam/plugin.h)");
  }
  const CorridorsimPluginInfo* info = info_function();
  if (!info) fail("returned no plugin information (corridorsim_plugin_info)");
  const CorridorsimPluginInfo ours = slam::ThisBuildPluginInfo("corridorsim", CORRIDORSIM_VERSION);
  if (info->sdk_abi_version != ours.sdk_abi_version) {
    fail("was built against the corridorsim SDK ABI version " +
         std::to_string(info->sdk_abi_version) + "; this corridorsim " + CORRIDORSIM_VERSION +
         " has SDK ABI version " + std::to_string(ours.sdk_abi_version) +
         ": rebuild the plugin against this corridorsim's SDK");
  }
  // The compiler's own ABI version (__GXX_ABI_VERSION) is not compared: GCC and clang report
  // different numbers for the same Itanium C++ ABI and libstdc++, and either may build a plugin.
  for (const auto& [what, theirs, mine] :
       {std::tuple<const char*, int, int>{"std::string's ABI (_GLIBCXX_USE_CXX11_ABI)",
                                          info->cxx11_string_abi, ours.cxx11_string_abi},
        {"Eigen's version", info->eigen_version, ours.eigen_version}}) {
    if (theirs != mine) {
      fail(std::string("was built with ") + what + " " + VersionText(theirs) +
           "; this corridorsim uses " + VersionText(mine) +
           ": rebuild it with the compiler and Eigen corridorsim was built with");
    }
  }
  plugin.name = FromLibrary(info->plugin_name);
  plugin.version = FromLibrary(info->plugin_version);
  plugin.sdk_version = FromLibrary(info->sdk_version);
  auto register_function =
      reinterpret_cast<RegisterFunction>(dlsym(handle, "corridorsim_plugin_register"));
  if (!register_function) fail("has no entry point corridorsim_plugin_register");
  CollectingRegistrar registrar;
  try {
    register_function(&registrar);
  } catch (const std::exception& e) {
    fail("threw while registering its types: " + FromLibrary(e.what()));
  } catch (...) {
    fail("threw while registering its types (not a std::exception)");
  }
  if (registrar.types.empty()) fail("registers no pipeline type");
  std::set<std::string> names;
  for (const slam::PipelineType& type : registrar.types) {
    if (!slam::IsPipelineName(type.name)) {
      fail("registers the type '" + InputExcerpt(type.name) +
           "', which is not a pipeline name (1 to 64 lower-case letters, digits and '_', "
           "starting with a letter)");
    }
    if (!type.new_options) fail("registers the type '" + type.name + "' without a factory");
    // Its default options are made once here, so that a broken factory is an input error at
    // the `plugins:` line, not a crash at the first scenario that names the type.
    try {
      if (!type.new_options())
        fail("registers the type '" + type.name + "' whose factory returns none");
    } catch (const InputError&) {
      throw;
    } catch (const std::exception& e) {
      fail("registers the type '" + type.name + "' whose factory throws: " + FromLibrary(e.what()));
    }
    if (!names.insert(type.name).second) fail("registers the type '" + type.name + "' twice");
    if (const std::optional<slam::PipelineType> taken = slam::FindPipelineType(type.name)) {
      fail("registers the type '" + type.name + "', which " +
           (taken->library.empty()
                ? std::string("corridorsim ships")
                : "the plugin '" + PathExcerpt(taken->library) + "' registered"));
    }
  }
  for (slam::PipelineType& type : registrar.types) {
    type.library = canonical.string();
    plugin.types.push_back(type.name);
    slam::AddPipelineType(std::move(type));
  }
  registry.loaded.emplace(canonical, plugin);
  return plugin;
}

}  // namespace corridorsim

namespace corridorsim {

std::string DescribePlugin(const LoadedPlugin& plugin) {
  std::string text = "plugin " + plugin.name + " " + plugin.version +
                     " (built against corridorsim " + plugin.sdk_version + ", SDK ABI " +
                     std::to_string(CORRIDORSIM_SDK_ABI_VERSION) + ")\n";
  text += "file " + plugin.path.string() + "\nsha256 " + plugin.sha256 + "\n";
  for (const std::string& name : plugin.types) {
    const std::unique_ptr<slam::PipelineOptions> options = slam::NewPipelineOptions(name);
    text += "\n## pipeline type `" + name + "`\n";
    if (!options) continue;
    for (const OptionsDocBlock& block : OptionsDocBlocks(
             options->table(), options->options(), "pipelines." + name, "pipelines." + name)) {
      text += "\n### `" + block.name + "`\n\n" + block.text;
    }
  }
  return text;
}

}  // namespace corridorsim

#pragma once
// The entry point of a pipeline plugin: a shared library (a CMake MODULE, built with
// `corridorsim_add_pipeline_plugin`, docs/plugins.md) that registers pipeline types, which
// scenarios then name under `pipelines:` exactly like the shipped ones.
//
//   #include "slam/plugin.h"
//   CORRIDORSIM_PLUGIN("my_plugin", "1.2.0", registrar) {
//     registrar.Add<MyOptions, MyPipeline>("my_ekf", &MyOptionsTable);
//   }
//
// The macro defines two C functions the loader finds by name (harness/scenario/plugins.cpp):
//   const CorridorsimPluginInfo* corridorsim_plugin_info(void);
//       what the plugin was built with; read right after dlopen() (which has already resolved
//       the library's symbols and run its static initializers) and before any other call, so
//       that a plugin of another ABI is refused with both versions named instead of crashing in
//       a C++ call
//   void corridorsim_plugin_register(corridorsim::slam::PluginRegistrar*);
//       called once, after the ABI check, to add the plugin's types.
// The ABI is C++ (std::string, Eigen, virtual calls): a plugin must be built against the same
// SDK ABI version, with the same std::string ABI and Eigen version, as the corridorsim that
// loads it, by a compiler of the Itanium C++ ABI and libstdc++ (GCC or clang); the loader checks
// the three (the compiler's own ABI number is recorded, not compared: GCC and clang differ).

#include <string>
#include <utility>

#include <Eigen/Core>

#include "slam/registry.h"
#include "slam/sdk_version.h"

#ifndef _GLIBCXX_USE_CXX11_ABI
#define CORRIDORSIM_CXX11_STRING_ABI -1
#else
#define CORRIDORSIM_CXX11_STRING_ABI _GLIBCXX_USE_CXX11_ABI
#endif

#define CORRIDORSIM_EIGEN_VERSION \
  (EIGEN_WORLD_VERSION * 10000 + EIGEN_MAJOR_VERSION * 100 + EIGEN_MINOR_VERSION)

extern "C" {
/// What a plugin was built with. The first member stays first in every SDK version, so that any
/// corridorsim can read it; the rest is read only when it matches.
struct CorridorsimPluginInfo {
  int sdk_abi_version;         // CORRIDORSIM_SDK_ABI_VERSION of the SDK the plugin was built with
  int cxx_abi_version;         // __GXX_ABI_VERSION (recorded; GCC and clang report different ones)
  int cxx11_string_abi;        // _GLIBCXX_USE_CXX11_ABI (std::string's layout); -1: not libstdc++
  int eigen_version;           // CORRIDORSIM_EIGEN_VERSION, e.g. 30407
  const char* sdk_version;     // CORRIDORSIM_VERSION, e.g. "0.1.0"
  const char* plugin_name;     // the plugin's own name (free text, printed)
  const char* plugin_version;  // the plugin's own version (free text, recorded in provenance)
};
}

namespace corridorsim::slam {

/// What a plugin's registration function receives: it adds the plugin's pipeline types. A name
/// must be 1 to 64 lower-case letters, digits and '_' starting with a letter, and not taken by a
/// shipped type or another plugin's; the loader checks and refuses the library otherwise.
class PluginRegistrar {
 public:
  virtual ~PluginRegistrar() = default;
  virtual void Add(PipelineType type) = 0;

  /// The type `name` of pipeline class `P` with options struct `Options` and its table (see
  /// MakePipelineType, slam/registry.h).
  template <class Options, class P>
  void Add(std::string name, const OptionTable<Options>& (*table)(),
           Options (*defaults)() = nullptr) {
    Add(MakePipelineType<Options, P>(std::move(name), table, defaults));
  }
};

/// The info of the code that includes this header (the loader's side compares with it).
inline CorridorsimPluginInfo ThisBuildPluginInfo(const char* name, const char* version) {
  return {CORRIDORSIM_SDK_ABI_VERSION,
          __GXX_ABI_VERSION,
          CORRIDORSIM_CXX11_STRING_ABI,
          CORRIDORSIM_EIGEN_VERSION,
          CORRIDORSIM_VERSION,
          name,
          version};
}

}  // namespace corridorsim::slam

#define CORRIDORSIM_PLUGIN_EXPORT extern "C" __attribute__((visibility("default")))

/// Defines the plugin's entry points; the block that follows is the registration function's body
/// with `REGISTRAR` (a corridorsim::slam::PluginRegistrar&) in scope.
#define CORRIDORSIM_PLUGIN(NAME, VERSION, REGISTRAR)                                      \
  CORRIDORSIM_PLUGIN_EXPORT const CorridorsimPluginInfo* corridorsim_plugin_info() {      \
    static const CorridorsimPluginInfo info =                                             \
        ::corridorsim::slam::ThisBuildPluginInfo(NAME, VERSION);                          \
    return &info;                                                                         \
  }                                                                                       \
  static void CorridorsimPluginRegister(::corridorsim::slam::PluginRegistrar& REGISTRAR); \
  CORRIDORSIM_PLUGIN_EXPORT void corridorsim_plugin_register(                             \
      ::corridorsim::slam::PluginRegistrar* registrar) {                                  \
    CorridorsimPluginRegister(*registrar);                                                \
  }                                                                                       \
  static void CorridorsimPluginRegister(::corridorsim::slam::PluginRegistrar& REGISTRAR)

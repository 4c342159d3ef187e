// A plugin built with the old std::string ABI (-D_GLIBCXX_USE_CXX11_ABI=0, tests/CMakeLists.txt),
// as a team's older toolchain or a copied CMAKE_CXX_FLAGS builds one: it calls an SDK function
// that takes a std::string, which the SDK (built with the C++11 ABI) does not provide under that
// name, so dlopen() refuses it before corridorsim can read its info
// (tests/harness/scenario/plugins_test.cpp, tests/harness/cli_plugin_test.py).

#include <stdexcept>
#include <string>

#include "slam/plugin.h"
#include "slam/registry.h"

#if !defined(_GLIBCXX_USE_CXX11_ABI) || _GLIBCXX_USE_CXX11_ABI != 0
#error "this test plugin must be built with -D_GLIBCXX_USE_CXX11_ABI=0"
#endif

CORRIDORSIM_PLUGIN("test_old_string_abi_plugin", "1.0.0", registrar) {
  static_cast<void>(registrar);
  const std::string name = "old_abi";
  if (!corridorsim::slam::IsPipelineName(name)) throw std::invalid_argument("not a pipeline name");
}

// harness/scenario/plugin_load_error.h: dlerror()'s text with its C++ names demangled and what a
// plugin's author must rebuild (docs/plugins.md, "Failures").

#include "harness/scenario/plugin_load_error.h"

#include <string>

#include <catch2/catch.hpp>

#include "slam/sdk_version.h"
#include "tests/support/expect_input_error.h"

namespace corridorsim {
namespace {

using test::Contains;

TEST_CASE("plugin load error: an old-ABI std::string symbol is demangled and the ABI named") {
  const std::string text =
      ExplainDlopenError("/p/old.so: undefined symbol: _ZN11corridorsim4slam14IsPipelineNameERKSs");
  CHECK(Contains(text,
                 "/p/old.so: undefined symbol: corridorsim::slam::IsPipelineName(std::string "
                 "const&) (_ZN11corridorsim4slam14IsPipelineNameERKSs); the library was "
                 "built with the old std::string ABI (_GLIBCXX_USE_CXX11_ABI=0)"));
  CHECK(Contains(text, "rebuild it with _GLIBCXX_USE_CXX11_ABI=1"));
  // std::list of the old ABI too.
  CHECK(Contains(ExplainDlopenError("x.so: undefined symbol: _Z1fRKSt4listIiSaIiEE"),
                 "_GLIBCXX_USE_CXX11_ABI=1"));
}

TEST_CASE("plugin load error: a C++11-ABI corridorsim symbol asks for this corridorsim's SDK") {
  const std::string text = ExplainDlopenError(
      "/p/new.so: undefined symbol: "
      "_ZN11corridorsim4slam13GoneInThisSdkERKNSt7__cxx1112basic_stringIcSt11char_"
      "traitsIcESaIcEEE");
  CHECK(Contains(text, "corridorsim::slam::GoneInThisSdk(std::__cxx11::basic_string<char"));
  CHECK_FALSE(Contains(text, "_GLIBCXX_USE_CXX11_ABI=1"));
  CHECK(Contains(text, std::string("rebuild it against this corridorsim's (") +
                           CORRIDORSIM_VERSION + ", SDK ABI version " +
                           std::to_string(CORRIDORSIM_SDK_ABI_VERSION)));
}

TEST_CASE("plugin load error: other symbols, versions and texts without symbols") {
  // A C symbol nothing provides: link what defines it.
  CHECK(Contains(ExplainDlopenError("/p/a.so: undefined symbol: cblas_dgemm"),
                 "undefined symbol: cblas_dgemm; neither the library nor the libraries it link"));
  // A newer libstdc++ than this system's.
  CHECK(Contains(ExplainDlopenError("/lib/libstdc++.so.6: version `GLIBCXX_3.4.32' not found "
                                    "(required by /p/a.so)"),
                 "built by a newer compiler or C library than this system's"));
  // No symbol: the text as it is; a name that does not demangle stays as it was.
  CHECK(ExplainDlopenError("/p/a.so: invalid ELF header") == "/p/a.so: invalid ELF header");
  CHECK(Contains(ExplainDlopenError("x: undefined symbol: _Zgarbage"), "_Zgarbage"));
  CHECK(Demangle("_ZN11corridorsim4slam14IsPipelineNameERKSs") ==
        "corridorsim::slam::IsPipelineName(std::string const&)");
  CHECK(Demangle("IsPipelineName").empty());
}

TEST_CASE("plugin load error: the text is bounded and on one line") {
  std::string many;
  for (int i = 0; i < 2000; ++i) many += "_ZN11corridorsim4slam14IsPipelineNameERKSs\n";
  const std::string text = ExplainDlopenError("/p/a.so: undefined symbol: " + many);
  CHECK(text.size() < 2000);
  CHECK(text.find('\n') == std::string::npos);
  CHECK(Contains(text, "_GLIBCXX_USE_CXX11_ABI=1"));
}

}  // namespace
}  // namespace corridorsim

#include "harness/scenario/plugin_load_error.h"

#include <cxxabi.h>

#include <cstdlib>
#include <memory>

#include "common/io/yaml_reader.h"
#include "slam/sdk_version.h"

namespace corridorsim {
namespace {

constexpr std::size_t kMaxDemangledBytes = 512;
constexpr std::size_t kMaxTextInMessage = 900;  // dlerror()'s text after demangling
constexpr std::string_view kUndefined = "undefined symbol: ";

#if defined(__clang__)
constexpr const char* kCompiler = "clang " __clang_version__;
#elif defined(__GNUC__)
constexpr const char* kCompiler = "GCC " __VERSION__;
#else
constexpr const char* kCompiler = "an unknown compiler";
#endif

bool IsSymbolChar(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
         c == '.' || c == '$';
}

bool Has(const std::string& text, std::string_view part) {
  return text.find(part) != std::string::npos;
}

// A name of the old (pre-C++11, GCC 4) libstdc++ ABI: its strings and lists carry no `__cxx11`
// (`Ss` demangles as std::string; the C++11 ABI's is std::__cxx11::basic_string<...>).
bool OldStringAbi(const std::string& demangled) {
  if (Has(demangled, "__cxx11")) return false;
  for (const std::string_view type :
       {"std::string", "std::wstring", "std::basic_string<", "std::list<", "std::stringstream",
        "std::istringstream", "std::ostringstream", "std::basic_stringstream<",
        "std::basic_istringstream<", "std::basic_ostringstream<", "std::basic_stringbuf<"}) {
    if (Has(demangled, type)) return true;
  }
  return false;
}

// What to rebuild, for the undefined symbol `mangled` (demangled: `demangled`, "" if not C++).
std::string Advice(const std::string& mangled, const std::string& demangled) {
  const std::string shown = demangled.empty() ? mangled : demangled;
  if (!demangled.empty() && OldStringAbi(demangled)) {
    return "; the library was built with the old std::string ABI (_GLIBCXX_USE_CXX11_ABI=0), "
           "which this corridorsim's SDK does not provide: rebuild it with "
           "_GLIBCXX_USE_CXX11_ABI=1 (remove -D_GLIBCXX_USE_CXX11_ABI=0 from its flags) by the "
           "compiler corridorsim was built with (" +
           std::string(kCompiler) + "), against this corridorsim's SDK";
  }
  if (Has(shown, "corridorsim")) {
    return std::string(
               "; the library was built against another corridorsim SDK: rebuild it "
               "against this corridorsim's (") +
           CORRIDORSIM_VERSION + ", SDK ABI version " +
           std::to_string(CORRIDORSIM_SDK_ABI_VERSION) +
           ": find_package(corridorsim) from its prefix, corridorsim_add_pipeline_plugin)";
  }
  return "; neither the library nor the libraries it links provide it: link the library that "
         "defines it (target_link_libraries), or rebuild the plugin by the compiler corridorsim "
         "was built with (" +
         std::string(kCompiler) + ")";
}

}  // namespace

std::string Demangle(const std::string& mangled) {
  if (mangled.size() < 3 || mangled.compare(0, 2, "_Z") != 0) return "";
  int status = 0;
  const std::unique_ptr<char, void (*)(void*)> text(
      abi::__cxa_demangle(mangled.c_str(), nullptr, nullptr, &status), std::free);
  if (status != 0 || !text) return "";
  return InputExcerpt(text.get(), kMaxDemangledBytes);
}

std::string ExplainDlopenError(std::string_view dlerror_text, std::size_t max_bytes) {
  const std::string_view text = dlerror_text.substr(0, max_bytes);
  std::string out;
  std::string advice;
  for (std::size_t i = 0; i < text.size();) {
    const bool starts = text.compare(i, 2, "_Z") == 0 && (i == 0 || !IsSymbolChar(text[i - 1]));
    if (!starts) {
      out += text[i++];
      continue;
    }
    std::size_t end = i;
    while (end < text.size() && IsSymbolChar(text[end])) ++end;
    const std::string mangled(text.substr(i, end - i));
    const std::string demangled = Demangle(mangled);
    out += demangled.empty() ? mangled : demangled + " (" + mangled + ")";
    const bool undefined = i >= kUndefined.size() &&
                           text.substr(i - kUndefined.size(), kUndefined.size()) == kUndefined;
    if (undefined && advice.empty()) advice = Advice(mangled, demangled);
    i = end;
  }
  // A C symbol (no mangling) that nothing provides.
  if (advice.empty()) {
    const std::size_t at = text.find(kUndefined);
    if (at != std::string_view::npos) {
      std::size_t end = at + kUndefined.size();
      while (end < text.size() && IsSymbolChar(text[end])) ++end;
      advice = Advice(
          std::string(text.substr(at + kUndefined.size(), end - at - kUndefined.size())), "");
    }
  }
  // A library that needs a newer libstdc++ (or C library) than this system's.
  if (advice.empty() && Has(std::string(text), "' not found (required by")) {
    advice =
        "; the library was built by a newer compiler or C library than this system's: "
        "rebuild it by the compiler corridorsim was built with (" +
        std::string(kCompiler) + ")";
  }
  return InputExcerpt(out, kMaxTextInMessage) + advice;
}

}  // namespace corridorsim

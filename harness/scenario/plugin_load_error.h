#pragma once
// Why dlopen() refused a plugin library, in words a plugin's author can act on. dlopen() resolves
// every symbol (RTLD_NOW) and runs the library's static initializers before corridorsim can read
// corridorsim_plugin_info, so a library built with another std::string ABI or against another
// SDK fails there, with a mangled name in dlerror()'s text, before the ABI check can speak.
// docs/plugins.md ("Failures").

#include <string>
#include <string_view>

namespace corridorsim {

/// dlerror()'s text with every mangled C++ name (`_Z...`) replaced by its demangled form (the
/// mangled one kept in parentheses after it), followed by what to rebuild when the text names an
/// undefined symbol: for one of the old std::string ABI (std::string, std::list, ... without
/// `__cxx11`), rebuilding with _GLIBCXX_USE_CXX11_ABI=1 and the compiler corridorsim's SDK was
/// built with; for another of corridorsim's, rebuilding against this corridorsim's SDK; else
/// linking what provides it. At most `max_bytes` of dlerror()'s text are read; the result is
/// bounded too (each name's demangled form at most 512 bytes).
std::string ExplainDlopenError(std::string_view dlerror_text, std::size_t max_bytes = 4096);

/// The demangled form of one mangled C++ name, or "" when it is not one.
std::string Demangle(const std::string& mangled);

}  // namespace corridorsim

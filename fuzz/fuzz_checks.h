#pragma once
// What every fuzz target's checks share (docs/fuzzing.md): a bug found ends the target loudly
// (Bug), and a JSON result holds only finite numbers (CheckFinite).

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <nlohmann/json.hpp>

namespace corridorsim::fuzz {

/// A bug found: said on stderr, then abort() (libFuzzer saves the input).
[[noreturn]] inline void Bug(const std::string& what) {
  std::fprintf(stderr, "%s: BUG: %s\n", program_invocation_short_name, what.c_str());
  std::fflush(stderr);
  std::abort();
}

/// Every number of `j` is finite (a NaN would compare false everywhere); `path` names `j` in the
/// message of a Bug.
inline void CheckFinite(const nlohmann::ordered_json& j, const std::string& path) {
  if (j.is_number() && !std::isfinite(j.get<double>())) Bug("not finite: " + path);
  if (j.is_structured()) {
    for (const auto& [key, value] : j.items()) CheckFinite(value, path + "." + key);
  }
}

}  // namespace corridorsim::fuzz

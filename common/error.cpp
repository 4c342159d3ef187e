#include "common/error.h"

#include <cstdio>
#include <cstdlib>

#include <utility>

namespace corridorsim {
namespace {

std::string Format(const SourceLocation& loc, const std::string& key, const std::string& msg) {
  std::string out;
  out.reserve(loc.file.size() + key.size() + msg.size() + 32);
  out.append(loc.file.empty() ? "<input>" : loc.file);
  if (loc.line > 0) {
    out.append(":").append(std::to_string(loc.line));
    if (loc.column > 0) out.append(":").append(std::to_string(loc.column));
  }
  out.append(": ");
  if (!key.empty()) out.append(key).append(": ");
  out.append(msg);
  return out;
}

}  // namespace

InputError::InputError(SourceLocation location, std::string key, std::string message)
    : std::runtime_error(Format(location, key, message)),
      location_(std::move(location)),
      key_(std::move(key)),
      message_(std::move(message)) {}

OptionsError::OptionsError(OptionsProblem problem)
    : std::runtime_error(problem.key + ": " + problem.message), problem_(std::move(problem)) {}

void CheckOrDie(bool ok, const char* where, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "corridorsim: %s: %s\n", where, what);
  std::abort();
}

}  // namespace corridorsim

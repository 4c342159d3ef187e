#pragma once
// Errors for bad user input (STYLE item 10): they name the file, line, column and key, and
// become exit code 2 in the command. Broken invariants are bugs and abort instead.

#include <stdexcept>
#include <string>

namespace corridorsim {

/// Where in an input file something is. Lines and columns are 1-based; 0 means unknown.
struct SourceLocation {
  std::string file;
  int line = 0;
  int column = 0;
};

/// Bad input: `file:line:column: key: message`.
class InputError : public std::runtime_error {
 public:
  InputError(SourceLocation location, std::string key, std::string message);

  const SourceLocation& location() const { return location_; }
  const std::string& key() const { return key_; }
  const std::string& message() const { return message_; }

 private:
  SourceLocation location_;
  std::string key_;
  std::string message_;
};

/// A problem found by an options `Check()` or a generator, before it is given a location: the
/// dotted key relative to the options struct (e.g. "doors.width_m") and what is wrong.
struct OptionsProblem {
  std::string key;
  std::string message;
};

/// Thrown by code that has no file context (generators); loaders turn it into an InputError.
class OptionsError : public std::runtime_error {
 public:
  explicit OptionsError(OptionsProblem problem);
  const OptionsProblem& problem() const { return problem_; }

 private:
  OptionsProblem problem_;
};

/// A broken invariant is a bug (STYLE item 10): prints "corridorsim: <where>: <what>" to stderr
/// and aborts when `ok` is false. Never for bad input.
void CheckOrDie(bool ok, const char* where, const char* what);

}  // namespace corridorsim

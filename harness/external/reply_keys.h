#pragma once
// The keys a program's reply may carry, and what an unknown one means (docs/protocol.md,
// "Unknown keys"). An unknown key is reported naming the reply, the key, the key it most likely
// misspells and every valid key. A misspelling of a key that carries no result (`ready`'s `name`
// and `version`, `finished`'s `stage_seconds`) leaves the results complete: a warning. Any other
// unknown key may hold a result the program meant to give (a misspelt `landmarks`), so the
// reply's results are incomplete: an error that fails the pipeline, after what did arrive is
// kept.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace corridorsim::external {

/// What a reply's keys hold: `keys` every valid key, in the order docs/protocol.md lists them;
/// `no_result` those that carry no result (timing, the program's name).
struct ReplyKeys {
  std::vector<std::string> keys;
  std::vector<std::string> no_result;
};

/// What was wrong with a reply that still gave results: `errors` make them incomplete (the
/// pipeline fails with them once what arrived is kept), `warnings` do not.
struct ReplyProblems {
  std::vector<std::string> errors;
  std::vector<std::string> warnings;
};

/// The valid key that `key` most likely misspells: the nearest by edit distance (a swap of two
/// neighbours counts once), if at most max(2, its length / 3) edits away; case is ignored.
std::optional<std::string> NearestKey(std::string_view key, const std::vector<std::string>& known);

/// "<where>: unknown key '<key>' (did you mean '<nearest>'?); the valid keys are a, b, c".
std::string UnknownKeyText(const std::string& where, std::string_view key,
                           const std::vector<std::string>& known);

/// The unknown keys of `object` (an object) sorted into errors and warnings as above.
ReplyProblems UnknownKeys(const nlohmann::json& object, const std::string& where,
                          const ReplyKeys& keys);

/// "a; b; c".
std::string JoinProblems(const std::vector<std::string>& problems);

}  // namespace corridorsim::external

#include "harness/external/reply_keys.h"

#include <algorithm>
#include <cctype>

#include "common/io/yaml_reader.h"

namespace corridorsim::external {
namespace {

// Keys longer than this are not compared (a key is a name; the distance is quadratic).
constexpr std::size_t kMaxComparedKeyBytes = 64;

char Lower(char c) { return static_cast<char>(std::tolower(static_cast<unsigned char>(c))); }

// Optimal string alignment distance: insertions, deletions, substitutions and swaps of two
// neighbouring characters each cost 1.
std::size_t EditDistance(std::string_view a, std::string_view b) {
  const std::size_t n = a.size(), m = b.size();
  std::vector<std::vector<std::size_t>> d(n + 1, std::vector<std::size_t>(m + 1, 0));
  for (std::size_t i = 0; i <= n; ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= m; ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= n; ++i) {
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = Lower(a[i - 1]) == Lower(b[j - 1]) ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && Lower(a[i - 1]) == Lower(b[j - 2]) &&
          Lower(a[i - 2]) == Lower(b[j - 1])) {
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    }
  }
  return d[n][m];
}

}  // namespace

std::optional<std::string> NearestKey(std::string_view key, const std::vector<std::string>& known) {
  if (key.empty() || key.size() > kMaxComparedKeyBytes) return std::nullopt;
  std::optional<std::string> best;
  std::size_t best_distance = 0;
  for (const std::string& k : known) {
    const std::size_t distance = EditDistance(key, k);
    if (distance > std::max<std::size_t>(2, k.size() / 3)) continue;
    if (!best || distance < best_distance) {
      best = k;
      best_distance = distance;
    }
  }
  return best;
}

std::string UnknownKeyText(const std::string& where, std::string_view key,
                           const std::vector<std::string>& known) {
  std::string text = where + ": unknown key '" + InputExcerpt(std::string(key), 60) + "'";
  if (const std::optional<std::string> nearest = NearestKey(key, known)) {
    text += " (did you mean '" + *nearest + "'?)";
  }
  std::string list;
  for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
  return text + "; the valid keys are " + list;
}

ReplyProblems UnknownKeys(const nlohmann::json& object, const std::string& where,
                          const ReplyKeys& keys) {
  ReplyProblems problems;
  if (!object.is_object()) return problems;
  for (const auto& [key, value] : object.items()) {
    if (std::find(keys.keys.begin(), keys.keys.end(), key) != keys.keys.end()) continue;
    std::string text = UnknownKeyText(where, key, keys.keys);
    const std::optional<std::string> nearest = NearestKey(key, keys.keys);
    if (nearest &&
        std::find(keys.no_result.begin(), keys.no_result.end(), *nearest) != keys.no_result.end()) {
      problems.warnings.push_back(text + " (ignored: '" + *nearest + "' carries no result)");
    } else {
      problems.errors.push_back(std::move(text));
    }
  }
  return problems;
}

std::string JoinProblems(const std::vector<std::string>& problems) {
  std::string out;
  for (const std::string& p : problems) out += (out.empty() ? "" : "; ") + p;
  return out;
}

}  // namespace corridorsim::external

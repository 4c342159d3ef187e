// The strict parsers of single command-line values (harness/cli/cli.h): seeds, numbers, poses,
// room and pipeline names, `score --expect` checks.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <iterator>
#include <string>
#include <vector>

#include "common/error.h"
#include "harness/cli/cli.h"
#include "harness/cli/options.h"

namespace corridorsim {
namespace {

using cli::Fail;
using cli::Got;
using cli::Quoted;

// Longest number text accepted (a double needs at most ~25 characters).
constexpr std::size_t kMaxNumberChars = 64;

}  // namespace

std::uint64_t ParseSeedArgument(const std::string& text, const std::string& flag) {
  const std::string expected = "expected a decimal integer in [0, 18446744073709551615] ";
  if (text.empty()) Fail(flag, expected + "(got an empty value)");
  if (text.find_first_not_of("0123456789") != std::string::npos) {
    Fail(flag, expected + "of digits only: no sign, hex, spaces or other characters " + Got(text));
  }
  if (text.size() > 1 && text[0] == '0') {
    Fail(flag, expected + "without leading zeros " + Got(text));
  }
  std::uint64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error == std::errc::result_out_of_range) Fail(flag, expected + Got(text) + ": too large");
  if (error != std::errc() || end != text.data() + text.size()) Fail(flag, expected + Got(text));
  return value;
}

double ParseNumberArgument(const std::string& text, double max_abs, const std::string& flag) {
  const std::string expected = "expected a decimal number (e.g. -1.5, 12, 3e2) ";
  if (text.empty()) Fail(flag, expected + "(got an empty value)");
  if (text.size() > kMaxNumberChars) Fail(flag, expected + Got(text) + ": too long");
  // [+-]? (digits [. digits?] | . digits) ([eE] [+-]? digits)?
  std::size_t i = 0;
  const auto digits = [&] {
    const std::size_t start = i;
    while (i < text.size() && text[i] >= '0' && text[i] <= '9') ++i;
    return i - start;
  };
  if (text[i] == '+' || text[i] == '-') ++i;
  const std::size_t mantissa_start = i;
  std::size_t mantissa_digits = digits();
  if (i < text.size() && text[i] == '.') {
    ++i;
    mantissa_digits += digits();
  }
  bool ok = mantissa_digits > 0;
  if (ok && i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
    ++i;
    if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
    ok = digits() > 0;
  }
  if (!ok || i != text.size()) Fail(flag, expected + Got(text));
  double value = 0.0;
  // from_chars takes no '+'; the sign is applied here.
  const char* first = text.data() + mantissa_start;
  const auto [end, error] =
      std::from_chars(first, text.data() + text.size(), value, std::chars_format::general);
  const bool out_of_range = error == std::errc::result_out_of_range;
  if (!out_of_range && (error != std::errc() || end != text.data() + text.size())) {
    Fail(flag, expected + Got(text));
  }
  if (out_of_range) Fail(flag, "too large or too small for a double " + Got(text));
  if (text[0] == '-') value = -value;
  if (!std::isfinite(value) || std::abs(value) > max_abs) {
    Fail(flag, "must lie in [-" + std::to_string(static_cast<long long>(max_abs)) + ", " +
                   std::to_string(static_cast<long long>(max_abs)) + "] " + Got(text));
  }
  return value;
}

PoseArgument ParsePoseArgument(const std::string& text, const std::string& flag) {
  const std::string expected = "expected x,y,yaw (metres, metres, degrees; e.g. 10,0.5,90) ";
  std::vector<std::string> fields;
  std::size_t start = 0;
  while (fields.size() <= 3) {
    const std::size_t comma = text.find(',', start);
    fields.push_back(text.substr(start, comma == std::string::npos ? comma : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (fields.size() != 3) Fail(flag, expected + Got(text));
  static const char* const kNames[3] = {"x", "y", "yaw"};
  double values[3];
  for (int k = 0; k < 3; ++k) {
    const double bound = k < 2 ? kPoseMaxAbsMetres : kPoseMaxAbsYawDeg;
    try {
      values[k] = ParseNumberArgument(fields[k], bound, flag);
    } catch (const InputError& e) {
      Fail(flag, expected + Got(text) + ": " + kNames[k] + " " + e.message());
    }
  }
  return PoseArgument{values[0], values[1], values[2]};
}

std::string ParseRoomArgument(const std::string& text, const std::string& flag) {
  const bool printable = std::all_of(text.begin(), text.end(), [](char c) {
    return static_cast<unsigned char>(c) > 0x20 && static_cast<unsigned char>(c) < 0x7f;
  });
  if (text.empty() || text.size() > kMaxRoomChars || !printable) {
    Fail(flag, "expected a room number: 1 to " + std::to_string(kMaxRoomChars) +
                   " printable characters without spaces " + Got(text));
  }
  return text;
}

std::string ParsePipelineArgument(const std::string& text, const std::string& flag) {
  const bool name = std::all_of(text.begin(), text.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
  });
  if (text.empty() || text.size() > kMaxPipelineChars || !name) {
    Fail(flag, "expected a pipeline name: 1 to " + std::to_string(kMaxPipelineChars) +
                   " letters, digits, '_' or '-' " + Got(text));
  }
  return text;
}

ScoreExpectation ParseScoreExpectation(const std::string& text, const std::string& flag) {
  const std::string expected =
      "expected <class>.<metric><op><number>, e.g. lamp.ap50>=0.8 (op: >=, >, <=, <) ";
  ScoreExpectation e;
  e.text = text;
  const std::size_t op_at = text.find_first_of("<>");
  if (op_at == std::string::npos) Fail(flag, expected + Got(text));
  const bool with_equal = op_at + 1 < text.size() && text[op_at + 1] == '=';
  e.op = text[op_at] == '>'
             ? (with_equal ? ScoreExpectation::Op::kGreaterEqual : ScoreExpectation::Op::kGreater)
             : (with_equal ? ScoreExpectation::Op::kLessEqual : ScoreExpectation::Op::kLess);
  const std::string key = text.substr(0, op_at);
  const std::size_t dot = key.find('.');
  if (dot == std::string::npos) Fail(flag, expected + Got(text));
  e.class_name = key.substr(0, dot);
  e.metric = key.substr(dot + 1);
  const auto names = [](const auto& list) {
    std::string joined;
    for (const char* n : list) joined += (joined.empty() ? "" : ", ") + std::string(n);
    return joined;
  };
  if (std::find(std::begin(kScoreClassNames), std::end(kScoreClassNames), e.class_name) ==
      std::end(kScoreClassNames)) {
    Fail(flag, "unknown class " + Quoted(e.class_name) + " in " + Quoted(text) +
                   " (classes: " + names(kScoreClassNames) + ")");
  }
  if (std::find(std::begin(kScoreMetricNames), std::end(kScoreMetricNames), e.metric) ==
      std::end(kScoreMetricNames)) {
    Fail(flag, "unknown metric " + Quoted(e.metric) + " in " + Quoted(text) +
                   " (metrics: " + names(kScoreMetricNames) + ")");
  }
  const std::string number = text.substr(op_at + (with_equal ? 2 : 1));
  try {
    e.value = ParseNumberArgument(number, 1e12, flag);
  } catch (const InputError& error) {
    Fail(flag, Quoted(text) + ": " + error.message());
  }
  return e;
}

}  // namespace corridorsim

#include "harness/evaluate/trajectory_file.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <system_error>

#include "common/error.h"
#include "common/io/line_reader.h"
#include "common/io/yaml_reader.h"  // InputExcerpt

namespace corridorsim::evaluate {
namespace {

constexpr std::size_t kTumColumns = 8;
constexpr std::size_t kOvEvalColumns = 20;
constexpr double kMaxQuaternionNormError = 1e-2;

struct Token {
  std::string_view text;
  int column = 0;  // 1-based
};

[[noreturn]] void FailAt(const std::string& file, int line, int column, const std::string& what) {
  throw InputError(SourceLocation{file, line, column}, "", what);
}

bool Digits(std::string_view s) {
  for (const char c : s) {
    if (c < '0' || c > '9') return false;
  }
  return true;
}

// Seconds as integer nanoseconds: "[-]digits[.digits]" exactly (decimals past the ninth rounded
// half up), anything else a double rounded to the nanosecond.
bool ParseStamp(std::string_view text, TimeNs* out) {
  const bool negative = !text.empty() && text[0] == '-';
  const std::string_view body = negative ? text.substr(1) : text;
  const auto dot = body.find('.');
  const std::string_view whole = body.substr(0, dot);
  const std::string_view fraction = dot == std::string_view::npos ? "" : body.substr(dot + 1);
  if (!whole.empty() && whole.size() <= 10 && Digits(whole) && Digits(fraction) &&
      (!fraction.empty() || dot == std::string_view::npos)) {
    TimeNs seconds = 0;
    for (const char c : whole) seconds = seconds * 10 + (c - '0');
    if (static_cast<double>(seconds) > kMaxStampSeconds) return false;
    TimeNs nanos = 0;
    for (std::size_t i = 0; i < 9; ++i) {
      nanos = nanos * 10 + (i < fraction.size() ? fraction[i] - '0' : 0);
    }
    if (fraction.size() > 9 && fraction[9] >= '5') ++nanos;
    const TimeNs ns = seconds * kNanosecondsPerSecond + nanos;
    *out = negative ? -ns : ns;
    return true;
  }
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || ptr != text.data() + text.size() || !std::isfinite(value) ||
      std::abs(value) > kMaxStampSeconds) {
    return false;
  }
  *out = static_cast<TimeNs>(std::llround(value * 1e9));
  return true;
}

double Number(const std::string& file, int line, const Token& token) {
  double value = 0.0;
  const char* first = token.text.data();
  const char* last = first + token.text.size();
  if (first != last && *first == '+') ++first;
  const auto [ptr, ec] = std::from_chars(first, last, value);
  if (ec != std::errc() || ptr != last || !std::isfinite(value)) {
    FailAt(file, line, token.column,
           "expected a finite number, got '" + InputExcerpt(token.text, 40) + "'");
  }
  return value;
}

// The symmetric matrix of an upper triangle a11 a12 a13 a22 a23 a33.
Eigen::Matrix3d Symmetric(const double* v) {
  Eigen::Matrix3d m;
  m << v[0], v[1], v[2], v[1], v[3], v[4], v[2], v[4], v[5];
  return m;
}

}  // namespace

std::string FormatName(Trajectory::Format format) {
  return format == Trajectory::Format::kTum ? "tum" : "ov_eval";
}

namespace {

// The lines of one file, in order, onto one Trajectory (the checks of ParseTrajectory).
class TrajectoryParser {
 public:
  explicit TrajectoryParser(const std::string& file) : file_(file) {}

  void Line(std::string_view row, int line) {
    if (row.size() > kMaxTrajectoryLineBytes) {  // ReadRegularFileLines' own words
      FailAt(file_, line, 0,
             "a line longer than " + std::to_string(kMaxTrajectoryLineBytes) +
                 " bytes (is this a text file?)");
    }
    if (!row.empty() && row.back() == '\r') row.remove_suffix(1);
    const std::size_t first = row.find_first_not_of(" \t");
    if (first == std::string_view::npos || row[first] == '#') return;  // blank, comment
    for (std::size_t i = 0; i < row.size(); ++i) {
      const auto c = static_cast<unsigned char>(row[i]);
      if ((c < 0x20 && c != '\t') || c == 0x7f) {
        FailAt(file_, line, static_cast<int>(i + 1), "a control character");
      }
    }
    tokens_.clear();
    for (std::size_t i = first; i < row.size();) {
      if (row[i] == ' ' || row[i] == '\t') {
        ++i;
        continue;
      }
      if (tokens_.size() == kOvEvalColumns) {
        FailAt(file_, line, static_cast<int>(i + 1),
               "more than " + std::to_string(kOvEvalColumns) + " columns");
      }
      std::size_t j = i;
      while (j < row.size() && row[j] != ' ' && row[j] != '\t') ++j;
      tokens_.push_back({row.substr(i, j - i), static_cast<int>(i + 1)});
      i = j;
    }
    if (columns_ == 0) {
      columns_ = tokens_.size();
      first_data_line_ = line;
      if (columns_ != kTumColumns && columns_ != kOvEvalColumns) {
        FailAt(file_, line, 1,
               std::to_string(columns_) +
                   " columns: expected 8 (TUM: t tx ty tz qx qy qz qw) or 20 (ov_eval: the 8, "
                   "then Pr11 Pr12 Pr13 Pr22 Pr23 Pr33 Pt11 Pt12 Pt13 Pt22 Pt23 Pt33)");
      }
      out_.format =
          columns_ == kTumColumns ? Trajectory::Format::kTum : Trajectory::Format::kOvEval;
    } else if (tokens_.size() != columns_) {
      FailAt(file_, line, 1,
             std::to_string(tokens_.size()) + " columns where line " +
                 std::to_string(first_data_line_) + " has " + std::to_string(columns_));
    }
    if (out_.poses.size() == kMaxTrajectoryPoses) {
      FailAt(file_, line, 1,
             "more than " + std::to_string(kMaxTrajectoryPoses) + " poses (the maximum)");
    }
    TrajectoryPose pose;
    if (!ParseStamp(tokens_[0].text, &pose.stamp_ns)) {
      FailAt(file_, line, tokens_[0].column,
             "expected a stamp in seconds within +-4e9, got '" + InputExcerpt(tokens_[0].text, 40) +
                 "'");
    }
    if (!out_.poses.empty() && pose.stamp_ns <= out_.poses.back().stamp_ns) {
      FailAt(file_, line, tokens_[0].column,
             "stamp '" + InputExcerpt(tokens_[0].text, 40) +
                 "' is not after the previous pose's: stamps must increase");
    }
    double v[kOvEvalColumns] = {};
    for (std::size_t k = 1; k < columns_; ++k) {
      v[k] = Number(file_, line, tokens_[k]);
      const bool position = k <= 3, covariance = k >= 8;
      const double bound = position ? kMaxCoordinateMetres : kMaxCovarianceEntry;
      if ((position || covariance) && std::abs(v[k]) > bound) {
        FailAt(file_, line, tokens_[k].column,
               std::string(position ? "a position" : "a covariance entry") + " beyond +-" +
                   (position ? "1e9 m" : "1e12") + ", got '" + InputExcerpt(tokens_[k].text, 40) +
                   "'");
      }
    }
    pose.position = Eigen::Vector3d(v[1], v[2], v[3]);
    Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    const double norm = q.norm();
    if (!(std::abs(norm - 1.0) <= kMaxQuaternionNormError)) {
      FailAt(
          file_, line, tokens_[4].column,
          "the quaternion (qx qy qz qw) has norm " + std::to_string(norm) + ", not 1 within 1e-2");
    }
    q.coeffs() /= norm;
    if (q.w() < 0.0) q.coeffs() = -q.coeffs();
    pose.orientation = q;
    if (columns_ == kOvEvalColumns) {
      if (out_.covariances.empty()) out_.covariances.reserve(out_.poses.capacity());
      out_.covariances.push_back({Symmetric(v + 8), Symmetric(v + 14)});
    }
    out_.poses.push_back(pose);
  }

  // Room for `lines` poses (a count of the file's data lines made before: exact memory instead of
  // a vector's doubling; only a hint, a file that changed meanwhile is still read right).
  void Reserve(std::size_t lines) { out_.poses.reserve(std::min(lines, kMaxTrajectoryPoses + 1)); }

  Trajectory Finish() {
    if (out_.poses.empty()) FailAt(file_, 0, 0, "no poses (only comments or blank lines)");
    return std::move(out_);
  }

 private:
  const std::string& file_;
  Trajectory out_;
  std::size_t columns_ = 0;
  int first_data_line_ = 0;
  std::vector<Token> tokens_;
};

}  // namespace

Trajectory ParseTrajectory(std::string_view text, const std::string& file) {
  TrajectoryParser parser(file);
  std::size_t begin = 0;
  int line = 0;
  while (begin < text.size()) {
    ++line;
    std::size_t end = text.find('\n', begin);
    if (end == std::string_view::npos) end = text.size();
    parser.Line(text.substr(begin, end - begin), line);
    begin = end + 1;
  }
  return parser.Finish();
}

Trajectory ReadTrajectory(const std::string& file) {
  TrajectoryParser parser(file);
  // Two passes over the file: its data lines counted (a cheap scan), then parsed into vectors of
  // that size. The text itself is never held: one chunk and one line at a time.
  std::size_t data_lines = 0;
  ReadRegularFileLines(file, kMaxTrajectoryFileBytes, kMaxTrajectoryLineBytes,
                       [&](std::string_view row, std::int64_t) {
                         const std::size_t first = row.find_first_not_of(" \t\r");
                         data_lines += first != std::string_view::npos && row[first] != '#';
                       });
  parser.Reserve(data_lines);
  ReadRegularFileLines(
      file, kMaxTrajectoryFileBytes, kMaxTrajectoryLineBytes,
      [&](std::string_view row, std::int64_t line) { parser.Line(row, static_cast<int>(line)); });
  return parser.Finish();
}

}  // namespace corridorsim::evaluate

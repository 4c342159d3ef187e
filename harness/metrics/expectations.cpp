#include "harness/metrics/expectations.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <system_error>

#include "common/io/yaml_reader.h"  // InputExcerpt: user text in messages
#include "harness/metrics/registry.h"

namespace corridorsim {
namespace {

using Json = nlohmann::ordered_json;

std::string Trim(const std::string& s) {
  const auto begin = s.find_first_not_of(" \t");
  if (begin == std::string::npos) return "";
  const auto end = s.find_last_not_of(" \t");
  return s.substr(begin, end - begin + 1);
}

}  // namespace

std::optional<std::string> ParseExpectation(const std::string& text, Expectation* out) {
  return ParseExpectation(text, out, MetricNames());
}

std::optional<std::string> ParseExpectation(const std::string& text, Expectation* out,
                                            const std::vector<std::string>& names) {
  const std::string where = " in expectation '" + InputExcerpt(text) + "'";
  const auto op_begin = text.find_first_of("<>=!");
  if (op_begin == std::string::npos) {
    return "no comparison (use <, <=, > or >=)" + where;
  }
  const auto op_end = text.find_first_not_of("<>=!", op_begin);
  const std::string op = text.substr(op_begin, op_end - op_begin);
  Expectation e;
  if (op == "<") {
    e.op = Expectation::Op::kLess;
  } else if (op == "<=") {
    e.op = Expectation::Op::kLessEqual;
  } else if (op == ">") {
    e.op = Expectation::Op::kGreater;
  } else if (op == ">=") {
    e.op = Expectation::Op::kGreaterEqual;
  } else {
    return "bad operator '" + InputExcerpt(op) + "' (use <, <=, > or >=)" + where;
  }
  const std::string left = Trim(text.substr(0, op_begin));
  const auto dot = left.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == left.size()) {
    return "expected <pipeline>.<metric> before '" + InputExcerpt(op) + "'" + where;
  }
  e.pipeline = left.substr(0, dot);
  e.metric = left.substr(dot + 1);
  if (!metrics::IsKnownMetric(names, e.metric)) {
    std::string known;
    for (const std::string& n : names) {
      // timing.* are wall clock: scenarios may not bound them (ScenarioExpectations).
      if (n.rfind("timing.", 0) != 0) known += (known.empty() ? "" : ", ") + n;
    }
    return "unknown metric '" + InputExcerpt(e.metric) + "' (known: " + known + ")" + where;
  }
  const std::string number =
      op_end == std::string::npos ? std::string() : Trim(text.substr(op_end));
  const char* first = number.data();
  const char* last = number.data() + number.size();
  const auto [ptr, ec] = std::from_chars(first, last, e.value);
  if (number.empty() || ec != std::errc() || ptr != last || !std::isfinite(e.value)) {
    return "'" + InputExcerpt(number) + "' is not a number" + where;
  }
  e.text = text;
  *out = e;
  return std::nullopt;
}

std::vector<ExpectationResult> CheckExpectations(const nlohmann::ordered_json& metrics,
                                                 const std::vector<Expectation>& expectations,
                                                 const std::string& group) {
  static const Json kZero = 0;
  std::vector<ExpectationResult> results;
  for (const Expectation& e : expectations) {
    ExpectationResult r;
    r.expectation = e;
    const Json* node = nullptr;
    const bool known = metrics.contains(group) && metrics[group].contains(e.pipeline);
    if (known) {
      node = &metrics[group][e.pipeline];
      std::size_t begin = 0;
      while (node != nullptr) {
        const auto dot = e.metric.find('.', begin);
        const std::string key = e.metric.substr(begin, dot - begin);
        node = node->is_object() && node->contains(key) ? &(*node)[key] : nullptr;
        if (dot == std::string::npos) break;
        begin = dot + 1;
      }
    }
    if (node == nullptr && known) {
      // A counter written only when non-zero reads as 0 where it is absent.
      const metrics::MetricSpec* spec =
          metrics::FindMetric(metrics::MetricScope::kPipeline, e.metric);
      if (spec != nullptr && spec->absent_when_zero) node = &kZero;
    }
    if (node != nullptr && node->is_number()) {
      const double v = node->get<double>();
      r.measured = v;
      switch (e.op) {
        case Expectation::Op::kLess:
          r.passed = v < e.value;
          break;
        case Expectation::Op::kLessEqual:
          r.passed = v <= e.value;
          break;
        case Expectation::Op::kGreater:
          r.passed = v > e.value;
          break;
        case Expectation::Op::kGreaterEqual:
          r.passed = v >= e.value;
          break;
      }
    }
    results.push_back(std::move(r));
  }
  return results;
}

}  // namespace corridorsim

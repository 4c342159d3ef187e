#include "harness/record/topics.h"

#include <sstream>

#include "common/error.h"

namespace corridorsim::record {
namespace {

// Whether `text` matches `pattern`, where '*' matches any run of characters (iterative, with one
// backtrack point: linear in practice and never exponential).
bool Matches(const std::string& pattern, const std::string& text) {
  std::size_t p = 0, t = 0, star = std::string::npos, mark = 0;
  while (t < text.size()) {
    if (p < pattern.size() && pattern[p] == '*') {
      star = p++;
      mark = t;
    } else if (p < pattern.size() && pattern[p] == text[t]) {
      ++p;
      ++t;
    } else if (star != std::string::npos) {
      p = star + 1;
      t = ++mark;
    } else {
      return false;
    }
  }
  while (p < pattern.size() && pattern[p] == '*') ++p;
  return p == pattern.size();
}

}  // namespace

std::string OpticalFrame(const std::string& camera_id) { return camera_id + "_optical_frame"; }
std::string SensorFrame(const std::string& sensor_id) { return sensor_id + "_link"; }
std::string SensorTopic(const std::string& sensor_id, const std::string& leaf) {
  return "/" + sensor_id + "/" + leaf;
}
std::string SensorTruthTopic(const std::string& sensor_id, const std::string& leaf) {
  return "/corridorsim/" + sensor_id + "/" + leaf;
}
std::string PipelineTopic(const std::string& pipeline, const std::string& leaf) {
  return "/slam/" + pipeline + "/" + leaf;
}

TopicFilter::TopicFilter(const std::string& patterns, const std::string& flag) : text_(patterns) {
  std::istringstream in(patterns);
  std::string pattern;
  while (std::getline(in, pattern, ',')) {
    if (pattern.empty() || pattern.front() != '/' || pattern.size() > 256) {
      throw InputError(SourceLocation{"command line", 0, 0}, flag,
                       "'" + pattern +
                           "' is not a topic pattern (a topic starts with '/'; '*' matches any "
                           "characters; patterns are separated by commas)");
    }
    patterns_.push_back(pattern);
  }
  if (patterns_.empty() || patterns_.size() > 256) {
    throw InputError(SourceLocation{"command line", 0, 0}, flag,
                     "give 1 to 256 comma-separated topic patterns");
  }
}

bool TopicFilter::Keeps(const std::string& topic) const {
  if (patterns_.empty()) return true;
  for (const std::string& p : patterns_) {
    if (Matches(p, topic)) return true;
  }
  return false;
}

}  // namespace corridorsim::record

#pragma once
// `corridorsim test`: scenarios and studies run as a test suite, each expectation one test case,
// with a JUnit XML report (the format GitLab, Jenkins and GitHub read; docs/ci.md).

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace corridorsim {

inline constexpr int kMaxSuiteFiles = 1000;
inline constexpr int kMaxSuiteJobs = 256;  // --jobs

struct TestRequest {
  std::vector<std::string> files;  // scenario or study files; empty: scenarios/default.yaml
  // --set KEY=VALUE: applied to every file (harness/scenario/overrides.h), passed on to its job.
  std::vector<std::string> settings;
  // --record: every run (and every study's run) also writes recording.mcap in its folder.
  bool record = false;
  // --jobs: files whose jobs run at once (each a `corridorsim run` or `study` of its own; a
  // study's runs then get the cores divided by this). The report is the same for any count but
  // for its wall-clock `time` attributes.
  int jobs = 1;
  std::filesystem::path out_dir = "out/test";       // one folder per file under it
  std::optional<std::filesystem::path> junit_file;  // --junit
  std::string program;  // the corridorsim that runs each file; empty: this executable
};

/// One JUnit test case.
struct SuiteCase {
  std::string classname;  // corridorsim.<file stem>
  std::string name;       // the expectation (a study's prefixed by its point)
  double seconds = 0.0;
  enum class Result { kPassed, kFailed, kError } result = Result::kPassed;
  std::string message;     // failed: measured value and threshold; error: what went wrong
  std::string details;     // the failure's text (the log's tail for an error)
  std::string attachment;  // the run or study folder
};

struct SuiteFile {
  std::string file;
  std::string name;         // the suite's name: the file's stem
  std::string folder_name;  // its folder and log under --out: the stem made safe to attach
  bool study = false;
  double seconds = 0.0;
  std::vector<SuiteCase> cases;
};

/// The JUnit XML document of `files` (testsuites > testsuite per file > testcase per
/// expectation; failures carry the measured value and the threshold, system-out the folder as
/// `[[ATTACHMENT|path]]` when the path holds no `[`, `]`, `|` or control character). Every text
/// is escaped and made XML 1.0 characters (docs/ci.md): nothing in a name changes the structure.
std::string JunitXml(const std::vector<SuiteFile>& files);

/// Runs the suite; returns 0 when every case passed, 3 when an expectation failed, 1 when a run
/// or study could not finish. Throws InputError for a bad file, before anything runs.
int RunTestSuite(const TestRequest& request);

}  // namespace corridorsim

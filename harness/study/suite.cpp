#include "harness/study/suite.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "common/io/child_process.h"
#include "common/io/yaml_reader.h"
#include "harness/run/run.h"
#include "harness/run/run_folder.h"
#include "harness/study/study_file.h"
#include "harness/study/suite_runner.h"

namespace corridorsim {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;
constexpr std::uint64_t kMaxResultBytes = std::uint64_t{256} << 20;
constexpr std::size_t kMaxListedSeeds = 10;  // diverged seeds named in one failure message
constexpr std::uint64_t kLogTailBytes = 4000;

// `text` as XML 1.0 character data (or, with `attribute`, an attribute value in double quotes):
// markup characters escaped; every byte that is not part of a well-formed UTF-8 character, and
// every character XML 1.0 forbids (the control characters other than tab, newline and carriage
// return; U+FFFE, U+FFFF), replaced by U+FFFD. Tab, newline and carriage return are written as
// character references where a reader would otherwise normalise them (in attributes; CR in text).
std::string Xml(const std::string& text, bool attribute = false) {
  static const char* const kReplacement = "\xEF\xBF\xBD";  // U+FFFD
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const auto u = static_cast<unsigned char>(text[i]);
    if (u < 0x80) {
      ++i;
      switch (u) {
        case '&':
          out += "&amp;";
          break;
        case '<':
          out += "&lt;";
          break;
        case '>':
          out += "&gt;";
          break;
        case '"':
          out += "&quot;";
          break;
        case '\'':
          out += "&apos;";
          break;
        case '\t':
          out += attribute ? "&#9;" : "\t";
          break;
        case '\n':
          out += attribute ? "&#10;" : "\n";
          break;
        case '\r':
          out += "&#13;";
          break;
        default:
          if (u < 0x20) {
            out += kReplacement;
          } else {
            out += static_cast<char>(u);
          }
      }
      continue;
    }
    const std::size_t n = Utf8Length(text, i);
    // U+FFFE and U+FFFF (EF BF BE, EF BF BF) are well-formed UTF-8 but not XML characters.
    const bool non_character = n == 3 && u == 0xEF &&
                               static_cast<unsigned char>(text[i + 1]) == 0xBF &&
                               static_cast<unsigned char>(text[i + 2]) >= 0xBE;
    if (n == 0 || non_character) {
      out += kReplacement;
      i += n == 0 ? 1 : n;
    } else {
      out.append(text, i, n);
      i += n;
    }
  }
  return out;
}

// True when `path` can stand in `[[ATTACHMENT|path]]` as exactly one attachment: UTF-8 without
// control characters, and none of `[`, `]` and `|`, which the CI systems' pattern
// (`\[\[ATTACHMENT\|(.+?)\]\]`) would read as the end of this attachment or the start of another.
bool AttachmentPathIsSafe(const std::string& path) {
  if (path.empty()) return false;
  for (std::size_t i = 0; i < path.size();) {
    const auto u = static_cast<unsigned char>(path[i]);
    if (u < 0x20 || u == 0x7F || u == '[' || u == ']' || u == '|') return false;
    const std::size_t n = Utf8Length(path, i);
    if (n == 0) return false;
    i += n;
  }
  return true;
}

// A file's stem as the name of its folder and log under --out: a byte that is not part of a
// UTF-8 character, a control character and `[`, `]`, `|` each become `_`, so that the paths
// the report attaches are whatever the stem holds (AttachmentPathIsSafe).
std::string SuiteFolderName(const std::string& stem) {
  std::string out;
  for (std::size_t i = 0; i < stem.size();) {
    const auto u = static_cast<unsigned char>(stem[i]);
    const std::size_t n = Utf8Length(stem, i);
    if (n == 0 || u < 0x20 || u == 0x7F || u == '[' || u == ']' || u == '|') {
      out += '_';
      i += n == 0 ? 1 : n;
    } else {
      out.append(stem, i, n);
      i += n;
    }
  }
  return out;
}

// The failed pipelines of a run's events.json, each with its reason ("failed at t = 25.000 s:
// OnOdometry threw: ..." cut to a bounded excerpt), in the file's order; empty when it holds none
// or cannot be read (the log's tail still holds the reasons).
std::vector<std::pair<std::string, std::string>> PipelineFailures(const fs::path& events_file) {
  constexpr std::size_t kMaxReasonBytes = 600;
  constexpr std::size_t kMaxReasons = 8;
  std::vector<std::pair<std::string, std::string>> failures;
  try {
    const json events = json::parse(ReadRegularFile(events_file, kMaxResultBytes));
    for (const json& e : events.at("events")) {
      if (e.value("type", "") != "pipeline_failed") continue;
      if (failures.size() == kMaxReasons) break;
      char t[32];
      std::snprintf(t, sizeof t, "%.3f", e.value("t", 0.0));
      failures.emplace_back(e.value("pipeline", ""),
                            std::string("failed at t = ") + t + " s: " + e.value("call", "") +
                                " threw: " + InputExcerpt(e.value("reason", ""), kMaxReasonBytes));
    }
  } catch (const std::exception&) {
    return {};
  }
  return failures;
}

std::string Seconds3(double s) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", s);
  return text;
}

// The last kLogTailBytes of a log (only they are read), cut at a UTF-8 character boundary.
std::string LogTail(const fs::path& log) {
  std::ifstream in(log, std::ios::binary);
  if (!in) return "";
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size <= 0) return "";
  const auto tail = static_cast<std::streamoff>(kLogTailBytes);
  const std::streamoff start = size > tail ? size - tail : 0;
  in.seekg(start);
  std::string text(static_cast<std::size_t>(size - start), '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  if (start == 0) return text;
  // A cut inside a character drops its continuation bytes (at most 3: a longer run is not UTF-8,
  // and Xml() replaces it).
  std::size_t skip = 0;
  while (skip < 3 && skip < text.size() &&
         (static_cast<unsigned char>(text[skip]) & 0xC0) == 0x80) {
    ++skip;
  }
  return "..." + text.substr(skip);
}

// File i's folder and log under --out: numbered, so that two files of one name do not meet.
fs::path FileFolder(const TestRequest& request, std::size_t i, const SuiteFile& f) {
  char prefix[32];
  std::snprintf(prefix, sizeof prefix, "%03zu_", i);
  return request.out_dir / (prefix + f.folder_name);
}
fs::path FileLog(const TestRequest& request, std::size_t i, const SuiteFile& f) {
  return FileFolder(request, i, f).string() + ".log";
}

std::string Measured(const json& value) {
  return value.is_number() ? FormatFixed(value.get<double>(), 6) : std::string("nothing");
}

}  // namespace

std::string JunitXml(const std::vector<SuiteFile>& files) {
  int tests = 0, failures = 0, errors = 0;
  double seconds = 0.0;
  for (const SuiteFile& f : files) {
    seconds += f.seconds;
    for (const SuiteCase& c : f.cases) {
      ++tests;
      failures += c.result == SuiteCase::Result::kFailed;
      errors += c.result == SuiteCase::Result::kError;
    }
  }
  std::string xml = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  xml += "<testsuites name=\"corridorsim\" tests=\"" + std::to_string(tests) + "\" failures=\"" +
         std::to_string(failures) + "\" errors=\"" + std::to_string(errors) + "\" time=\"" +
         Seconds3(seconds) + "\">\n";
  for (const SuiteFile& f : files) {
    int f_failures = 0, f_errors = 0;
    for (const SuiteCase& c : f.cases) {
      f_failures += c.result == SuiteCase::Result::kFailed;
      f_errors += c.result == SuiteCase::Result::kError;
    }
    xml += "  <testsuite name=\"" + Xml(f.name, true) + "\" tests=\"" +
           std::to_string(f.cases.size()) + "\" failures=\"" + std::to_string(f_failures) +
           "\" errors=\"" + std::to_string(f_errors) + "\" skipped=\"0\" time=\"" +
           Seconds3(f.seconds) + "\">\n";
    xml += "    <properties>\n      <property name=\"file\" value=\"" + Xml(f.file, true) +
           "\"/>\n" + "      <property name=\"kind\" value=\"" + (f.study ? "study" : "scenario") +
           "\"/>\n    </properties>\n";
    for (const SuiteCase& c : f.cases) {
      xml += "    <testcase classname=\"" + Xml(c.classname, true) + "\" name=\"" +
             Xml(c.name, true) + "\" time=\"" + Seconds3(c.seconds) + "\">\n";
      if (c.result == SuiteCase::Result::kFailed) {
        xml += "      <failure message=\"" + Xml(c.message, true) + "\" type=\"expectation\">" +
               Xml(c.details) + "</failure>\n";
      } else if (c.result == SuiteCase::Result::kError) {
        xml += "      <error message=\"" + Xml(c.message, true) + "\" type=\"run\">" +
               Xml(c.details) + "</error>\n";
      }
      // A path that cannot stand alone between the markers is left out: the failure's text
      // still names it.
      if (AttachmentPathIsSafe(c.attachment)) {
        xml += "      <system-out>[[ATTACHMENT|" + Xml(c.attachment) + "]]</system-out>\n";
      }
      xml += "    </testcase>\n";
    }
    xml += "  </testsuite>\n";
  }
  xml += "</testsuites>\n";
  return xml;
}

int RunTestSuite(const TestRequest& request) {
  // Every file is checked before anything runs: a bad one is exit 2 with nothing run.
  std::vector<SuiteFile> files;
  std::vector<JobInput> inputs;  // every file's chain and plugins: no output may touch them
  for (const std::string& file : request.files) {
    const StudySpec spec = LoadStudy(file, std::nullopt, std::nullopt, request.settings);
    for (JobInput& input : StudyInputs(spec)) inputs.push_back(std::move(input));
    SuiteFile f;
    f.file = file;
    f.name = fs::path(file).stem().string();
    f.folder_name = SuiteFolderName(f.name);
    f.study = spec.has_section;
    files.push_back(std::move(f));
  }
  if (request.junit_file) {
    // Checked now, so that a suite never runs for an hour and then cannot write its report.
    const fs::path parent = fs::absolute(*request.junit_file).parent_path();
    std::error_code error;
    if (!fs::is_directory(parent, error) || ::access(parent.c_str(), W_OK) != 0) {
      throw InputError(SourceLocation{"command line", 0, 0}, "--junit",
                       "'" + InputExcerpt(parent.string()) + "' is not a writable folder");
    }
    if (fs::exists(fs::symlink_status(*request.junit_file, error)) &&
        !fs::is_regular_file(fs::symlink_status(*request.junit_file, error))) {
      throw InputError(SourceLocation{"command line", 0, 0}, "--junit",
                       "'" + InputExcerpt(request.junit_file->string()) +
                           "' exists and is not a regular file (the report replaces a file)");
    }
    RefuseOutputOverInputs(*request.junit_file, "--junit", inputs);
  }
  RefuseOutputOverInputs(request.out_dir, "--out", inputs);
  std::error_code error;
  fs::create_directories(request.out_dir, error);
  EnsureWritableDirectory(request.out_dir);
  const std::string program = request.program.empty() ? ThisProgram() : request.program;
  CatchStopSignals();

  // Each file's job in a folder and log of its own, --jobs at a time; a study's runs share the
  // cores with the other jobs.
  const int jobs = std::clamp(request.jobs, 1, kMaxSuiteJobs);
  const int cores = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  std::vector<SuiteCommand> commands;
  for (std::size_t i = 0; i < files.size(); ++i) {
    const SuiteFile& f = files[i];
    std::vector<std::string> argv = {program,     f.study ? "study" : "run",          f.file,
                                     "--out",     FileFolder(request, i, f).string(), "--force",
                                     "--no-plots"};
    if (f.study && jobs > 1) {
      argv.insert(argv.end(), {"--jobs", std::to_string(std::max(1, cores / jobs))});
    }
    for (const std::string& setting : request.settings) argv.insert(argv.end(), {"--set", setting});
    if (request.record) argv.push_back("--record");
    commands.push_back(
        {argv, FileLog(request, i, f), std::string(f.study ? "study " : "run ") + f.file});
  }
  const std::vector<SuiteCommandResult> ended = RunSuiteCommands(commands, jobs);

  int code = 0;
  for (std::size_t i = 0; i < files.size(); ++i) {
    SuiteFile& f = files[i];
    const fs::path folder = FileFolder(request, i, f);
    const fs::path log = FileLog(request, i, f);
    const ChildStatus& status = ended[i].status;
    f.seconds = ended[i].seconds;
    // A dot in the stem would add a level to the CI system's package tree: `_` instead.
    std::string stem = f.name;
    std::replace(stem.begin(), stem.end(), '.', '_');
    const std::string classname = "corridorsim." + stem;
    const auto error_case = [&](const std::string& name, const std::string& message) {
      SuiteCase c;
      c.classname = classname;
      c.name = name;
      c.seconds = f.seconds;  // shared with the file's other cases below, if it has any
      c.result = SuiteCase::Result::kError;
      c.message = message;
      c.details = LogTail(log);
      c.attachment = fs::absolute(log).string();
      f.cases.push_back(std::move(c));
    };
    const std::string results_file = f.study ? "summary.json" : "metrics.json";
    const bool written = fs::is_regular_file(folder / results_file, error);
    // `run`: 0, 3 (an expectation failed), 4 (an extra failed) and 5 (a pipeline failed: its
    // expectations fail on its missing metrics) leave the results written; `study`: 1 too (a
    // run failed; the others are summarised).
    const int code_of_job = status.exit_code;
    const bool usable =
        status.started && status.signal == 0 && written &&
        (f.study ? code_of_job == 0 || code_of_job == 1 || code_of_job == 3 || code_of_job == 4
                 : RunWroteResults(code_of_job));
    if (!usable) {
      error_case(f.study ? "study" : "run",
                 std::string(f.study ? "corridorsim study " : "corridorsim run ") +
                     DescribeChildStatus(status) + " (log: " + log.string() + ")");
      code = code == 0 || code == 3 ? 1 : code;
      std::printf("test: %s: ERROR, %s\n", f.file.c_str(), DescribeChildStatus(status).c_str());
      continue;
    }
    json results;
    try {
      results = json::parse(ReadRegularFile(folder / results_file, kMaxResultBytes));
    } catch (const std::exception& e) {
      error_case("results", std::string("unreadable ") + results_file + ": " + e.what());
      code = code == 0 || code == 3 ? 1 : code;
      continue;
    }
    const std::vector<std::pair<std::string, std::string>> failures =
        f.study ? std::vector<std::pair<std::string, std::string>>{}
                : PipelineFailures(folder / "events.json");
    if (!f.study && status.exit_code == kExitPipelineFailed) {
      // A pipeline failed (its reasons are in the log's tail): an error case of its own, beside
      // its expectations, which fail on its missing metrics.
      std::string reasons;
      for (const auto& [pipeline, reason] : failures) {
        reasons += (reasons.empty() ? "'" : "; '") + pipeline + "' " + reason;
      }
      error_case("pipeline failed", "corridorsim run " + DescribeChildStatus(status) +
                                        ": a pipeline failed" +
                                        (reasons.empty() ? "" : ": " + reasons) +
                                        " (events.json, log: " + log.string() + ")");
      code = code == 0 || code == 3 ? 1 : code;
    }
    // What a CI system shows beside the case ([[ATTACHMENT|...]]): the page that answers "what
    // happened": the run's viewer.html, the study's report.html (which links every run's
    // viewer), else the folder (--no-viewer, or the page failed).
    const fs::path page = folder / (f.study ? "report.html" : "viewer.html");
    std::error_code page_error;
    const std::string attachment =
        fs::absolute(fs::is_regular_file(page, page_error) ? page : folder).string();
    const auto add = [&](const std::string& name, bool passed, const std::string& measured) {
      SuiteCase c;
      c.classname = classname;
      c.name = name;
      c.result = passed ? SuiteCase::Result::kPassed : SuiteCase::Result::kFailed;
      if (!passed) {
        c.message = "measured " + measured + ", expected " + name;
        c.details = c.message + " (" + attachment + ")";
      }
      c.attachment = attachment;
      f.cases.push_back(std::move(c));
    };
    if (!f.study) {
      const json& expectations = results["expectations"];
      if (!expectations.is_array() || expectations.empty()) {
        add("run finishes", true, "");
      }
      for (const json& e : expectations) {
        // An expectation on a failed pipeline measured nothing: the message says why.
        const std::string text = e.value("text", "");
        std::string measured = Measured(e["measured"]);
        for (const auto& [pipeline, reason] : failures) {
          if (text.rfind(pipeline + ".", 0) == 0) measured += " (" + pipeline + " " + reason + ")";
        }
        add(text, e.value("passed", false), measured);
      }
    } else {
      std::size_t count = 0;
      for (const json& p : results["points"]) count += p["expectations"].size();
      for (const json& p : results["points"]) {
        const std::string point = p.value("id", "");
        std::string values;
        for (const auto& [key, value] : p["vary"].items()) {
          values += (values.empty() ? "" : ", ") + key + "=" + value.get<std::string>();
        }
        const std::string label = values.empty() ? "" : point + " (" + values + "): ";
        for (const json& e : p["expectations"]) {
          add(label + e.value("expectation", ""), e.value("passed", false),
              Measured(e["measured"]));
        }
        // A pipeline not allowed to diverge (study.may_diverge): one case, failed with the
        // seeds and reasons of its diverged runs.
        for (const auto& [name, pipeline] : p["pipelines"].items()) {
          const json r = pipeline.value("runs", json::object());
          if (r.value("may_diverge", false)) continue;
          const json diverged = r.value("diverged_seeds", json::array());
          const json why = r.value("diverged_why", json::array());
          std::string seeds;
          for (std::size_t k = 0; k < diverged.size() && k < kMaxListedSeeds; ++k) {
            seeds += (seeds.empty() ? "" : "; ") + std::string("seed ") + diverged[k].dump() +
                     (k < why.size() && why[k].is_string() ? ": " + why[k].get<std::string>()
                                                           : std::string());
          }
          if (diverged.size() > kMaxListedSeeds) seeds += "; ...";
          add(label + name + " does not diverge", diverged.empty(),
              std::to_string(diverged.size()) + " diverged run(s) (" + seeds + ")");
        }
        for (const char* outcome : {"failed_seeds", "timed_out_seeds"}) {
          for (const json& seed : p["runs"][outcome]) {
            error_case(point + " seed " + std::to_string(seed.get<std::uint64_t>()),
                       std::string("a run of the study ") +
                           (outcome[0] == 'f' ? "failed" : "timed out") + " (" +
                           (folder / "logs" / point /
                            ("seed_" + std::to_string(seed.get<std::uint64_t>()) + ".log"))
                               .string() +
                           ")");
          }
        }
      }
      if (count == 0 && f.cases.empty()) add("study finishes", true, "");
    }
    // The file's time shared by its cases, so that the suite's total is the files' total (the
    // cases of one file ran in one process and cannot be timed apart).
    for (SuiteCase& c : f.cases) {
      c.seconds = f.seconds / static_cast<double>(std::max<std::size_t>(f.cases.size(), 1));
    }
    int failed = 0, errors = 0;
    for (const SuiteCase& c : f.cases) {
      failed += c.result == SuiteCase::Result::kFailed;
      errors += c.result == SuiteCase::Result::kError;
    }
    if (errors > 0) {
      code = code == 0 || code == 3 ? 1 : code;
    } else if (failed > 0 && code == 0) {
      code = 3;
    }
    std::printf("test: %s: %zu case(s), %d failed, %d error(s) in %.1f s\n", f.file.c_str(),
                f.cases.size(), failed, errors, f.seconds);
  }
  const std::string xml = JunitXml(files);
  if (request.junit_file) {
    WriteFileAtomic(*request.junit_file, xml);
    std::printf("test: wrote %s\n", request.junit_file->string().c_str());
  }
  int tests = 0, failures = 0, errors = 0;
  for (const SuiteFile& f : files) {
    for (const SuiteCase& c : f.cases) {
      ++tests;
      failures += c.result == SuiteCase::Result::kFailed;
      errors += c.result == SuiteCase::Result::kError;
    }
  }
  std::printf("test: %d case(s), %d failed, %d error(s)\n", tests, failures, errors);
  return code;
}

}  // namespace corridorsim

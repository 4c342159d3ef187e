// The study's statistics against reference values (numpy's percentile, scipy.stats' binomtest
// and wilcoxon, computed once and written here), its expectations' grammar, and a study file's
// errors placed at the line that caused them.

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "common/io/yaml_reader.h"
#include "harness/study/study_file.h"
#include "harness/study/study_stats.h"
#include "harness/study/study_summary.h"
#include "harness/study/suite.h"
#include "tests/support/expect_input_error.h"
#include "tests/support/scratch_dir.h"

namespace corridorsim {
namespace {

using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

void Write(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

std::string Scenarios() { return std::string(CORRIDORSIM_SOURCE_DIR "/scenarios"); }

TEST_CASE("quantiles interpolate between order statistics (numpy's default)", "[study]") {
  const std::vector<double> v = {3, 1, 4, 1, 5, 9, 2, 6};
  // numpy.percentile(v, [50, 95, 25]) = [3.5, 7.95, 1.75]
  CHECK_THAT(study::Quantile(v, 0.5), WithinAbs(3.5, 1e-12));
  CHECK_THAT(study::Quantile(v, 0.95), WithinAbs(7.95, 1e-12));
  CHECK_THAT(study::Quantile(v, 0.25), WithinAbs(1.75, 1e-12));
  CHECK(study::Quantile(v, 0.0) == 1.0);
  CHECK(study::Quantile(v, 1.0) == 9.0);
  CHECK(study::Quantile({7.0}, 0.95) == 7.0);
}

TEST_CASE("the sign test is the exact binomial test", "[study]") {
  // scipy.stats.binomtest(9, 10).pvalue and binomtest(2, 12).pvalue
  std::vector<double> nine_of_ten(9, 1.0);
  nine_of_ten.push_back(-1.0);
  CHECK_THAT(study::SignTestP(nine_of_ten), WithinRel(0.021484375, 1e-9));
  std::vector<double> two_of_twelve = {0.1, 0.2};
  for (int i = 0; i < 10; ++i) two_of_twelve.push_back(-0.5);
  two_of_twelve.push_back(0.0);  // zeros are dropped
  CHECK_THAT(study::SignTestP(two_of_twelve), WithinRel(0.03857421875, 1e-9));
  CHECK(study::SignTestP({0.0, 0.0}) == 1.0);
  CHECK(study::SignTestP({}) == 1.0);
}

TEST_CASE("the Wilcoxon signed-rank test matches scipy, exact and approximate", "[study]") {
  // scipy.stats.wilcoxon(d, method='exact').pvalue
  CHECK_THAT(study::WilcoxonSignedRankP({0.5, -0.2, 0.3, 0.7, 0.1, 0.9, -0.4, 0.6}),
             WithinRel(0.109375, 1e-9));
  // All ten positive: W- = 0, p = 2 / 2^10.
  CHECK_THAT(study::WilcoxonSignedRankP({1, 2, 3, 4, 5, 6, 7, 8, 9, 10}),
             WithinRel(2.0 / 1024.0, 1e-9));
  // With ties: the normal approximation, tie and continuity corrected
  // (scipy.stats.wilcoxon(d, correction=True, method='approx').pvalue).
  CHECK_THAT(study::WilcoxonSignedRankP({1, 1, 2, -1, 3, 3, 3, -2, 4, 5, 1}),
             WithinRel(0.028189356302630857, 1e-6));
  CHECK(study::WilcoxonSignedRankP({0.0}) == 1.0);
  // Symmetric differences give a large p.
  CHECK(study::WilcoxonSignedRankP({1, -1.5, 2, -2.5, 3, -3.5}) > 0.5);
}

TEST_CASE("bootstrap intervals are seeded, hold the mean and shrink with more seeds", "[study]") {
  std::vector<double> v;
  for (int i = 0; i < 20; ++i) v.push_back(0.02 + 0.001 * ((i * 7) % 11));
  const study::Interval a = study::BootstrapMeanInterval(v, "x");
  const study::Interval b = study::BootstrapMeanInterval(v, "x");
  CHECK(a.low == b.low);
  CHECK(a.high == b.high);
  double mean = 0.0;
  for (double x : v) mean += x / 20.0;
  CHECK(a.low < mean);
  CHECK(a.high > mean);
  std::vector<double> more;
  for (int k = 0; k < 10; ++k) more.insert(more.end(), v.begin(), v.end());
  const study::Interval c = study::BootstrapMeanInterval(more, "x");
  CHECK(c.high - c.low < 0.5 * (a.high - a.low));
  CHECK(study::BootstrapMeanInterval({0.3}, "x").low == 0.3);

  // Paired: b = a + 0.01 exactly gives a difference interval of [-0.01, -0.01].
  std::vector<double> shifted = v;
  for (double& x : shifted) x += 0.01;
  const study::PairedIntervals p = study::BootstrapPairedIntervals(v, shifted, "y");
  CHECK_THAT(p.diff.low, WithinAbs(-0.01, 1e-12));
  CHECK_THAT(p.diff.high, WithinAbs(-0.01, 1e-12));
  CHECK(p.ratio.low < 1.0);
  CHECK(p.ratio.high < 1.0);
}

TEST_CASE("study expectations name a statistic of a pipeline, a pair, NEES or runs", "[study]") {
  StudyExpectation e;
  REQUIRE_FALSE(ParseStudyExpectation("p3_upward.ate_rmse_m.mean < 0.05", &e));
  CHECK(e.kind == StudyExpectation::Kind::kPipelineStat);
  CHECK(e.pipeline == "p3_upward");
  CHECK(e.metric == "ate_rmse_m");
  CHECK(e.stat == "mean");
  CHECK(e.op == StudyExpectation::Op::kLess);
  CHECK(e.value == 0.05);
  REQUIRE_FALSE(ParseStudyExpectation("paired(p3_upward, p3_corners).ate_rmse_m.ratio <= 0.5", &e));
  CHECK(e.kind == StudyExpectation::Kind::kPaired);
  CHECK(e.pipeline == "p3_upward");
  CHECK(e.other == "p3_corners");
  CHECK(e.stat == "ratio");
  CHECK(e.op == StudyExpectation::Op::kLessEqual);
  REQUIRE_FALSE(ParseStudyExpectation("p1_harris.map.corner.rmse_m.p95>=0", &e));
  CHECK(e.metric == "map.corner.rmse_m");
  CHECK(e.stat == "p95");
  CHECK(e.op == StudyExpectation::Op::kGreaterEqual);
  REQUIRE_FALSE(ParseStudyExpectation("odometry.nees.in_band_fraction > 0.5", &e));
  CHECK(e.kind == StudyExpectation::Kind::kNees);
  REQUIRE_FALSE(ParseStudyExpectation("odometry.runs.diverged < 1", &e));
  CHECK(e.kind == StudyExpectation::Kind::kRuns);
  REQUIRE_FALSE(ParseStudyExpectation("runs.failed < 1", &e));
  CHECK(e.kind == StudyExpectation::Kind::kFailedRuns);
  for (const char* bad : {"odometry.ate_rmse_m.mean", "odometry.ate_rmse_m.mean < x",
                          "odometry < 1", "paired(a).x.diff < 0", "paired(a, b)x.diff < 0",
                          "odometry.ate_rmse_m.mean < inf", "odometry.ate_rmse_m.mean < 0x10"}) {
    INFO(bad);
    CHECK(ParseStudyExpectation(bad, &e));
  }
}

TEST_CASE("a study file's errors name the file, line and key", "[study]") {
  test::ScratchDir dir("study_file_errors");
  const std::string base = Scenarios() + "/umbmark_cw.yaml";
  const auto write = [&](const std::string& body) {
    const std::filesystem::path file = dir.path() / "s.yaml";
    Write(file, "include: " + base + "\nduration_s: 5\n" + body);
    return file.string();
  };
  const auto error_of = [&](const std::string& body) {
    const std::string file = write(body);
    return test::InputErrorOf([&] { LoadStudy(file, std::nullopt, std::nullopt); });
  };

  // Each case: its study section, and what its error says: the line, the key (exactly or a part
  // of it) and a part of the message, where given.
  struct Case {
    const char* what;
    std::string body;
    int line = 0;
    const char* key = nullptr;
    const char* key_part = nullptr;
    const char* message_part = nullptr;
  };
  std::string values = "[";  // 40 sweep values
  for (int i = 0; i < 40; ++i) values += (i ? ", " : "") + std::to_string(1e-5 * (i + 1));
  values += "]";
  const Case cases[] = {
      {.what = "a sweep value the key does not take, at the value's line",
       .body = "study:\n  vary:\n    robot.odometry.random_k_m:\n      - 1.0e-5\n      - -3\n",
       .line = 7,
       .key = "study.vary.robot.odometry.random_k_m",
       .message_part = "-3"},
      {.what = "a sweep key the scenario does not have",
       .body = "study:\n  vary:\n    robot.odometry.no_such_key: [1, 2]\n",
       .line = 5,
       .key_part = "study.vary.robot.odometry.no_such_key"},
      {.what = "the seed is not swept", .body = "study:\n  vary:\n    seed: [1, 2]\n", .line = 5},
      {.what = "overlapping sweep keys",
       .body = "study:\n  vary:\n    robot.odometry: [{}]\n    robot.odometry.random_k_m: [1]\n",
       .line = 6,
       .message_part = "overlaps"},
      {.what = "an unknown study key",
       .body = "study:\n  runz: 4\n",
       .line = 4,
       .key_part = "runz"},
      {.what = "runs out of bounds", .body = "study:\n  runs: 0\n", .key = "study.runs"},
      {.what = "an expectation on a pipeline that does not run",
       .body = "study:\n  expectations:\n    - p3_upward.ate_rmse_m.mean < 0.1\n",
       .line = 5,
       .message_part = "does not run"},
      {.what = "an expectation on a metric the study does not summarise",
       .body = "study:\n  expectations:\n    - odometry.map.corner.rmse_m.mean < 0.1\n",
       .message_part = "study.metrics"},
      {.what = "an unknown extra metric",
       .body = "study:\n  metrics: [ate_rmse_m, no_such_metric]\n",
       .key = "study.metrics"},
      {.what = "may_diverge names a pipeline the scenario does not run, at its line",
       .body = "study:\n  may_diverge:\n    - odometry\n    - p1_harris\n",
       .line = 6,
       .key = "study.may_diverge",
       .message_part = "p1_harris"},
      {.what = "too many points",
       .body = "study:\n  vary:\n    robot.odometry.random_k_m: " + values +
               "\n    world.plates.count: " + values + "\n",
       .message_part = "points"},
  };
  for (const Case& c : cases) {
    DYNAMIC_SECTION(c.what) {
      const InputError e = error_of(c.body);
      if (c.line != 0) CHECK(e.location().line == c.line);
      if (c.key) CHECK(e.key() == c.key);
      if (c.key_part) CHECK(test::Contains(e.key(), c.key_part));
      if (c.message_part) CHECK(test::Contains(e.message(), c.message_part));
    }
  }
}

TEST_CASE("may_diverge keeps scenario order and takes the command line's names", "[study]") {
  test::ScratchDir dir("study_may_diverge");
  const std::filesystem::path file = dir.path() / "s.yaml";
  // umbmark_cw.yaml marks its odometry a baseline; here it is not, so that may_diverge is a.
  Write(file, "include: " + Scenarios() +
                  "/umbmark_cw.yaml\npipelines:\n  odometry: {baseline: false}\n  b:\n    type: "
                  "odometry\n  a:\n    type: odometry\nstudy:\n  may_diverge: [a]\n");
  StudySpec spec = LoadStudy(file.string(), std::nullopt, std::nullopt);
  CHECK(spec.pipelines == std::vector<std::string>{"odometry", "b", "a"});
  CHECK(spec.may_diverge == std::vector<std::string>{"a"});
  AddMayDiverge(&spec, {"odometry", "a"}, "--may-diverge");
  CHECK(spec.may_diverge == std::vector<std::string>{"odometry", "a"});
  const InputError e = test::InputErrorOf([&] { AddMayDiverge(&spec, {"nope"}, "--may-diverge"); });
  CHECK(e.key() == "--may-diverge");
  CHECK(e.location().file == "command line");
}

TEST_CASE("a run diverged by NEES, by health or without a NEES; may_diverge only reports it",
          "[study]") {
  test::ScratchDir dir("study_divergence");
  StudySpec spec;
  spec.pipelines = {"a", "b"};
  spec.may_diverge = {"b"};
  spec.metrics = {"ate_rmse_m"};
  spec.runs = 4;
  spec.points.push_back(StudyPoint{"p000", {}, Scenario{}});
  // seed 1: fine; 2: NEES above divergence_nees; 3: a non-positive covariance; 4: no NEES.
  const std::vector<std::string> a = {
      R"({"nees_mean": 2.5, "ate_rmse_m": 0.1})", R"({"nees_mean": 150, "ate_rmse_m": 0.1})",
      R"({"nees_mean": 2.5, "ate_rmse_m": 0.1, "health": {"non_positive_covariance": 3}})",
      R"({"ate_rmse_m": 0.1})"};
  std::vector<StudyRunRecord> records;
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    const std::filesystem::path folder = dir.path() / ("seed_" + std::to_string(seed));
    std::filesystem::create_directories(folder);
    const std::string b = seed == 2 ? R"({"nees_mean": 1e6, "ate_rmse_m": 9})" : a[0];
    Write(folder / "metrics.json",
          R"({"pipelines": {"a": )" + a[seed - 1] + R"(, "b": )" + b + "}}");
    for (const char* name : {"a", "b"}) {
      Write(folder / (std::string(name) + "_errors.csv"),
            "t,ex_m,ey_m,eyaw_rad,sigma_x_m,sigma_y_m,sigma_yaw_rad,nees\n0,0,0,0,1,1,1,1\n");
    }
    records.push_back({0, seed, StudyRunRecord::Outcome::kFinished, folder, ""});
  }
  const StudySummary summary = SummarizeStudy(spec, records);
  REQUIRE(summary.divergences.size() == 3);
  CHECK(summary.divergences[0].seed == 2);
  CHECK(test::Contains(summary.divergences[0].why, "average NEES 150 > divergence_nees 100"));
  CHECK(summary.divergences[1].seed == 3);
  CHECK(test::Contains(summary.divergences[1].why, "non-positive covariance (3)"));
  CHECK(summary.divergences[2].seed == 4);
  CHECK(summary.divergences[2].why == "no average NEES");
  for (const StudyDivergence& d : summary.divergences) CHECK(d.pipeline == "a");
  REQUIRE(summary.allowed_divergences.size() == 1);
  CHECK(summary.allowed_divergences[0].pipeline == "b");
  CHECK(summary.allowed_divergences[0].seed == 2);
  const auto& runs = summary.json["points"][0]["pipelines"];
  CHECK(runs["a"]["runs"]["diverged"] == 3);
  CHECK(runs["a"]["runs"]["may_diverge"] == false);
  CHECK(runs["b"]["runs"]["may_diverge"] == true);
  CHECK(summary.json["diverged_runs_failing"] == 3);
}

TEST_CASE("the shipped paper studies load and state their baselines", "[study]") {
  // Each file of scenarios/studies/ is a study with expectations; P1's Harris baseline and
  // dead reckoning diverge in some seeds by design and are listed in may_diverge, the pipelines
  // under test are not (a divergence of those fails the study).
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(Scenarios() + "/studies")) {
    if (entry.path().extension() != ".yaml") continue;
    ++files;
    INFO(entry.path().string());
    const StudySpec spec = LoadStudy(entry.path().string(), std::nullopt, std::nullopt);
    CHECK(spec.has_section);
    CHECK(spec.runs >= 20);
    CHECK_FALSE(spec.expectations.empty());
    CHECK(std::find(spec.may_diverge.begin(), spec.may_diverge.end(), "odometry") !=
          spec.may_diverge.end());
    for (const char* tested : {"p1_vp_doorplate", "p3_upward", "p3_corners"}) {
      CHECK(std::find(spec.may_diverge.begin(), spec.may_diverge.end(), tested) ==
            spec.may_diverge.end());
    }
  }
  CHECK(files == 3);
}

TEST_CASE("a sweep gives one scenario per point, the last key fastest", "[study]") {
  test::ScratchDir dir("study_points");
  const std::filesystem::path file = dir.path() / "s.yaml";
  Write(file, "include: " + Scenarios() +
                  "/umbmark_cw.yaml\nstudy:\n  runs: 3\n  first_seed: 5\n  vary:\n"
                  "    robot.odometry.random_k_m: [1.0e-5, 1.0e-3]\n"
                  "    world.plates.count: [2, 3]\n");
  const StudySpec spec = LoadStudy(file.string(), std::nullopt, std::nullopt);
  REQUIRE(spec.points.size() == 4);
  CHECK(spec.runs == 3);
  CHECK(spec.first_seed == 5);
  CHECK(spec.points[1].id == "p001");
  CHECK(spec.points[1].values[0].second == "1.0e-5");
  CHECK(spec.points[1].values[1].second == "3");
  CHECK(spec.points[1].scenario.world.plates.count == 3);
  CHECK(spec.points[2].scenario.robot.odometry.random_k_m == 1.0e-3);
  CHECK(spec.points[2].scenario.world.plates.count == 2);
  // The command line overrides the file.
  const StudySpec more = LoadStudy(file.string(), 7, 100);
  CHECK(more.runs == 7);
  CHECK(more.first_seed == 100);
  // A plain scenario is a study of one point at its seed.
  const StudySpec plain = LoadStudy(Scenarios() + "/umbmark_cw.yaml", std::nullopt, std::nullopt);
  CHECK_FALSE(plain.has_section);
  CHECK(plain.points.size() == 1);
  CHECK(plain.runs == 10);
}

TEST_CASE("the JUnit report escapes text and counts failures and errors", "[study]") {
  SuiteFile f;
  f.file = "a&b.yaml";
  f.name = "a&b";
  f.seconds = 2.5;
  SuiteCase passed;
  passed.classname = "corridorsim.a&b";
  passed.name = "odometry.ate_rmse_m < 1";
  f.cases.push_back(passed);
  SuiteCase failed = passed;
  failed.result = SuiteCase::Result::kFailed;
  failed.message = "measured 2.000000, expected odometry.ate_rmse_m < 1";
  f.cases.push_back(failed);
  SuiteCase error = passed;
  error.name = "run";
  error.result = SuiteCase::Result::kError;
  error.details = std::string("log \x01 tail");
  f.cases.push_back(error);
  const std::string xml = JunitXml({f});
  CHECK(test::Contains(xml, "tests=\"3\" failures=\"1\" errors=\"1\""));
  CHECK(test::Contains(xml, "name=\"a&amp;b\""));
  CHECK(test::Contains(xml, "name=\"odometry.ate_rmse_m &lt; 1\""));
  CHECK(test::Contains(xml, "<failure message=\"measured 2.000000, expected"));
  // No control character reaches the XML: U+FFFD stands for it.
  CHECK(test::Contains(xml, "log \xEF\xBF\xBD tail"));
}

// True when `text` is UTF-8 holding only characters XML 1.0 allows.
bool IsXmlText(const std::string& text) {
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x20 && c != '\t' && c != '\n' && c != '\r') return false;
    const std::size_t n = Utf8Length(text, i);
    if (n == 0) return false;
    if (n == 3 && text.compare(i, 2, "\xEF\xBF") == 0 &&
        static_cast<unsigned char>(text[i + 2]) >= 0xBE) {
      return false;  // U+FFFE, U+FFFF
    }
    i += n;
  }
  return true;
}

TEST_CASE("the JUnit report is XML 1.0 text whatever bytes its names and logs hold", "[study]") {
  // A study named in Japanese whose runs failed: its log's tail cut inside a character (the
  // continuation bytes of U+6587 first), bytes that are not UTF-8, control characters, U+FFFF.
  SuiteFile f;
  f.file = "/tmp/\xE5\xA4\xB1\xE6\x95\x97\x01\xE9.yaml";
  f.name = "\xE5\xA4\xB1\xE6\x95\x97\x01\xE9";
  SuiteCase error;
  error.classname = "corridorsim." + f.name;
  error.name = "p000 seed 1\nline two\ttab";
  error.result = SuiteCase::Result::kError;
  error.message = "a run of the study failed (\xE6\x96";
  error.details =
      "\x96\x87\xE5\xAD\x97 \x1B[31mred\x1B[0m \xC0\xAF \xED\xA0\x80 \xEF\xBF\xBF "
      "\xF4\x90\x80\x80 ok \xE6\x96\x87\r\n\xE6";
  error.attachment = "/tmp/\xE5\xA4\xB1\xE6\x95\x97\x7F\x02";
  f.cases.push_back(error);
  const std::string xml = JunitXml({f});
  CHECK(IsXmlText(xml));
  const std::string fffd = "\xEF\xBF\xBD";
  // Well-formed characters stay; each bad byte or forbidden character is one U+FFFD.
  CHECK(test::Contains(xml, "name=\"\xE5\xA4\xB1\xE6\x95\x97" + fffd + fffd + "\""));
  CHECK(test::Contains(xml, fffd + fffd + "\xE5\xAD\x97 " + fffd + "[31mred"));
  CHECK(test::Contains(xml, " ok \xE6\x96\x87&#13;\n" + fffd + "</error>"));
  // Newlines and tabs of attribute values survive a reader's normalisation.
  CHECK(test::Contains(xml, "name=\"p000 seed 1&#10;line two&#9;tab\""));
  CHECK(test::Contains(xml, "message=\"a run of the study failed (" + fffd + fffd + "\""));
}

TEST_CASE("no path adds or cuts an attachment of the JUnit report", "[study]") {
  // `[[ATTACHMENT|path]]` is read by pattern: a path holding `[`, `]`, `|` or a control
  // character is left out (its case still names it); every other path is attached once.
  SuiteFile f;
  f.file = "x.yaml";
  f.name = "x";
  SuiteCase c;
  c.classname = "corridorsim.x";
  c.name = "odometry.ate_rmse_m < 1";
  for (const std::string& path :
       {std::string("/out/000_x]] [[ATTACHMENT|secrets.txt]] [[y/viewer.html"),
        std::string("/out/a|b/viewer.html"), std::string("/out/a]/viewer.html"),
        std::string("/out/line\nbreak/viewer.html"), std::string("/out/caf\xE9/viewer.html"),
        std::string("/out/000_caf\xC3\xA9 (1)/viewer.html")}) {
    c.attachment = path;
    f.cases.push_back(c);
  }
  const std::string xml = JunitXml({f});
  std::size_t markers = 0;
  for (std::size_t at = xml.find("[[ATTACHMENT|"); at != std::string::npos;
       at = xml.find("[[ATTACHMENT|", at + 1)) {
    ++markers;
  }
  CHECK(markers == 1);
  CHECK(test::Contains(xml, "[[ATTACHMENT|/out/000_caf\xC3\xA9 (1)/viewer.html]]"));
  CHECK_FALSE(test::Contains(xml, "secrets.txt]]"));
}

TEST_CASE("a scenario's baselines may diverge in a study; the key is the harness's", "[study]") {
  test::ScratchDir dir("study_baselines");
  // default.yaml marks dead reckoning and P1's Harris EKF as baselines, not P1's system.
  const StudySpec p1 = LoadStudy(Scenarios() + "/default.yaml", std::nullopt, std::nullopt);
  CHECK(p1.may_diverge == std::vector<std::string>{"odometry", "p1_harris"});
  // Dead reckoning alone is a baseline too: its NEES diverges in some seeds by design.
  const StudySpec umbmark = LoadStudy(Scenarios() + "/umbmark_cw.yaml", std::nullopt, 7);
  CHECK(umbmark.may_diverge == std::vector<std::string>{"odometry"});
  // Marked in a child (and unmarked: odometry), echoed only where set and loaded again from the
  // echo; a disabled baseline is not a pipeline of the study.
  const std::filesystem::path file = dir.path() / "s.yaml";
  Write(file, "include: " + Scenarios() +
                  "/umbmark_cw.yaml\npipelines:\n  odometry: {baseline: false}\n  tight:\n    "
                  "type: odometry\n    baseline: true\n  off:\n    type: odometry\n    enabled: "
                  "false\n    baseline: true\n");
  const Scenario scenario = LoadScenario(file.string());
  const std::string echo = ResolvedScenarioYaml(scenario, 3);
  CHECK(test::Contains(echo,
                       "  tight:\n    type: odometry\n    enabled: true\n    baseline: true\n"));
  CHECK(test::Contains(echo, "  odometry:\n    type: odometry\n    enabled: true\n    k_m:"));
  const std::filesystem::path again = dir.path() / "again.yaml";
  Write(again, echo);
  const StudySpec spec = LoadStudy(again.string(), std::nullopt, std::nullopt);
  CHECK(spec.pipelines == std::vector<std::string>{"odometry", "tight"});
  CHECK(spec.may_diverge == std::vector<std::string>{"tight"});
  // Not a pipeline option: a value that is not a bool is an error at the key.
  Write(file,
        "include: " + Scenarios() + "/umbmark_cw.yaml\npipelines:\n  odometry:\n    baseline: 3\n");
  const InputError e = test::InputErrorOf([&] { LoadScenario(file.string()); });
  CHECK(e.location().line == 4);
  CHECK(test::Contains(e.key(), "baseline"));
  // A sweep cannot change which pipelines are baselines.
  Write(file,
        "include: " + Scenarios() +
            "/umbmark_cw.yaml\nstudy:\n  vary:\n    pipelines.odometry.baseline: [false, true]\n");
  const InputError sweep =
      test::InputErrorOf([&] { LoadStudy(file.string(), std::nullopt, std::nullopt); });
  CHECK(test::Contains(sweep.message(), "the same baselines"));
}

}  // namespace
}  // namespace corridorsim

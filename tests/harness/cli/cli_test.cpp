// Tests harness/cli/ (ParseCommandLine): the command line parsed strictly, touching no file.
#include "harness/cli/cli.h"

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "common/error.h"

namespace corridorsim {
namespace {

using Args = std::vector<std::string>;
using Job = CommandLine::Job;

// The message ParseCommandLine throws for `args` ("" when it throws none).
std::string ErrorOf(const Args& args) {
  try {
    ParseCommandLine(args);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST_CASE("ParseCommandLine fills each job's request", "[harness]") {
  const CommandLine run =
      ParseCommandLine({"run", "s.yaml", "--seed", "18446744073709551615", "--out", "o", "--export",
                        "e", "--no-plots", "--force"});
  CHECK(run.job == Job::kRun);
  CHECK(run.run.scenario_file == "s.yaml");
  CHECK(run.run.seed == std::numeric_limits<std::uint64_t>::max());
  CHECK(run.run.out_dir == "o");
  CHECK(run.run.export_dir == std::filesystem::path("e"));
  CHECK_FALSE(run.run.plots);
  CHECK(run.run.force);
  CHECK_FALSE(run.run.check_only);

  const CommandLine defaults = ParseCommandLine({"run"});
  CHECK(defaults.run.scenario_file.empty());  // none given: main picks and names the default
  CHECK_FALSE(defaults.run.seed);
  CHECK(defaults.run.out_dir == "out/run");
  CHECK_FALSE(defaults.run.export_dir);
  CHECK(defaults.run.plots);
  CHECK_FALSE(defaults.run.force);

  const CommandLine snapshot = ParseCommandLine({"snapshot", "--pose=-3.5,0.25,-90", "--seed=0"});
  CHECK(snapshot.job == Job::kSnapshot);
  CHECK(snapshot.snapshot.x_m == -3.5);
  CHECK(snapshot.snapshot.y_m == 0.25);
  CHECK(snapshot.snapshot.yaw_deg == -90.0);
  CHECK(snapshot.snapshot.seed == std::uint64_t{0});
  CHECK(snapshot.snapshot.out_dir == "out/snapshot");

  const CommandLine drive = ParseCommandLine({"drive", "--save-frames", "--out", "d"});
  CHECK(drive.job == Job::kDrive);
  CHECK(drive.drive.save_frames);
  CHECK(drive.drive.out_dir == "d");

  const CommandLine world = ParseCommandLine({"world", "w.yaml", "--seed", "7"});
  CHECK(world.job == Job::kWorld);
  CHECK(world.world.seed == std::uint64_t{7});
}

TEST_CASE("run --record and replay fill the run request; their flags are strict", "[harness]") {
  const CommandLine run = ParseCommandLine({"run", "s.yaml", "--record", "--record-topics",
                                            "/front/*,/tf*", "--record-compression", "lz4"});
  CHECK(run.run.record);
  CHECK(run.run.record_topics == "/front/*,/tf*");
  CHECK(run.run.record_compression == "lz4");
  CHECK_FALSE(run.run.replay);
  const CommandLine replay = ParseCommandLine({"replay", "r.mcap", "mine.yaml", "--out", "o"});
  CHECK(replay.job == Job::kReplay);
  CHECK(replay.run.replay == std::filesystem::path("r.mcap"));
  CHECK(replay.run.scenario_file == "mine.yaml");
  CHECK(replay.run.out_dir == "o");
  CHECK_FALSE(replay.run.record);
  // Without a scenario the recording's own runs: none is picked here.
  CHECK(ParseCommandLine({"replay", "r.mcap"}).run.scenario_file.empty());
  CHECK_THAT(ErrorOf({"replay"}), Catch::Contains("recording"));
  CHECK_THAT(ErrorOf({"replay", ""}), Catch::Contains("RECORDING: an empty file name"));
  CHECK_THAT(ErrorOf({"run", "--record-topics", "/tf"}), Catch::Contains("needs --record"));
  CHECK_THAT(ErrorOf({"run", "--record", "--record-compression", "gzip"}),
             Catch::Contains("--record-compression: must be zstd, lz4 or none"));
}

TEST_CASE("A setting (--set) is repeatable on every job that reads a scenario, one KEY=VALUE each",
          "[harness]") {
  const Args settings = {"--set", "duration_s=20", "--set=world.doors.count=4", "--set",
                         "expectations=[]"};
  const Args expected = {"duration_s=20", "world.doors.count=4", "expectations=[]"};
  const auto with = [&](Args args) {
    args.insert(args.end(), settings.begin(), settings.end());
    args.push_back("s.yaml");  // after a --set: still the scenario, never a second value
    return ParseCommandLine(args);
  };
  CHECK(with({"run"}).run.settings == expected);
  CHECK(with({"run"}).run.scenario_file == "s.yaml");
  CHECK(with({"world"}).world.settings == expected);
  CHECK(with({"snapshot", "--pose", "1,0,0"}).snapshot.settings == expected);
  CHECK(with({"drive"}).drive.settings == expected);
  CHECK(with({"dataset"}).dataset.settings == expected);
  CHECK(with({"study"}).study.settings == expected);
  CHECK(with({"study"}).study.scenario_file == "s.yaml");
  const CommandLine test = with({"test", "--jobs", "3"});
  CHECK(test.test.settings == expected);
  CHECK(test.test.files == Args{"s.yaml"});
  CHECK(test.test.jobs == 3);
  CHECK(ParseCommandLine({"test"}).test.jobs == 1);
  CHECK(ParseCommandLine({"run"}).run.settings.empty());

  // The syntax is checked here, the keys when the scenario is loaded.
  CHECK(ErrorOf({"run", "--set", "duration_s"}) ==
        "command line: --set: expected KEY=VALUE, e.g. --set duration_s=20 (got "
        "'duration_s')");
  CHECK(ErrorOf({"test", "--set", "a..b=1"}).rfind("command line: --set: a..b: ", 0) == 0);
  CHECK(ErrorOf({"run", "--set", "world.doors.cout=4"}).empty());
  CHECK_THAT(ErrorOf({"run", "x.yaml", "--set", "a=1", "b=2"}),
             Catch::Contains("b=2"));  // not a second value of --set
  CHECK(ErrorOf({"test", "--jobs", "0"}) ==
        "command line: --jobs: must be a whole number in [1, 256] (got '0')");
  CHECK(ErrorOf({"test", "--jobs", "257"}) ==
        "command line: --jobs: must be a whole number in [1, 256] (got '257')");
}

TEST_CASE("ParseCommandLine returns help text with the exit codes", "[harness]") {
  const CommandLine help = ParseCommandLine({"run", "--help"});
  CHECK(help.job == Job::kHelp);
  CHECK_THAT(help.help_text, Catch::Contains("--force"));
  CHECK_THAT(help.help_text, Catch::Contains("4 the results are written but an extra"));
  CHECK_THAT(help.help_text, Catch::Contains("5 a pipeline failed"));
  CHECK_THAT(help.help_text, Catch::Contains("5 takes precedence over 3, 3 over 4"));
  for (const char* job : {"world", "snapshot", "drive"}) {
    CHECK_THAT(ParseCommandLine({job, "--help"}).help_text, Catch::Contains("Exit codes: 0"));
  }
  CHECK_THAT(ParseCommandLine({"--help-all"}).help_text, Catch::Contains("--save-frames"));
}

TEST_CASE("a seed on the command line is a decimal uint64 and nothing else", "[harness]") {
  for (const char* bad : {"-1", "18446744073709551616", "99999999999999999999999", "12abc", "0x10",
                          "", " 1", "1 ", "+1", "1e3", "1.0", "inf", "nan", "007", "１"}) {
    INFO("--seed '" << bad << "'");
    const std::string error = ErrorOf({"run", "--seed", bad});
    CHECK_THAT(error, Catch::StartsWith("command line: --seed: expected a decimal integer"));
  }
  CHECK_THAT(ErrorOf({"drive", "--seed=18446744073709551616"}), Catch::Contains("too large"));
  CHECK_THAT(ErrorOf({"world", "--seed", "-1"}), Catch::Contains("(got '-1')"));
  CHECK(ParseSeedArgument("0", "--seed") == 0);
  CHECK(ParseSeedArgument("42", "--seed") == 42);
}

TEST_CASE("a pose on the command line is three bounded decimal numbers", "[harness]") {
  for (const char* bad :
       {"1,2,3,4",   "1,2",     "1,,3",      "1,2,",     ",1,2",      ",,",
        "0x10,0,0",  "inf,0,0", "0,nan,0",   "0,0,-inf", "1e400,0,0", "100001,0,0",
        "0,-1e6,0",  "0,0,361", "0,0,1e308", "1 ,2,3",   "1;2;3",     "10,zero,0",
        "1.2.3,0,0", "--1,0,0", "1e,0,0",    ".,0,0",    "+,0,0"}) {
    INFO("--pose '" << bad << "'");
    CHECK_THAT(ErrorOf({"snapshot", std::string("--pose=") + bad}),
               Catch::StartsWith("command line: --pose: expected x,y,yaw"));
  }
  CHECK_THAT(ErrorOf({"snapshot", "--pose", "0,0,400"}), Catch::Contains("yaw must lie in"));
  CHECK_THAT(ErrorOf({"snapshot", "--pose", "-1,-2,-3,-4"}),
             Catch::Contains("(got '-1,-2,-3,-4')"));
  CHECK_THAT(ErrorOf({"snapshot"}), Catch::Contains("--pose is required"));
  CHECK_THAT(ErrorOf({"snapshot", "--pose="}), Catch::StartsWith("command line: --pose: "));
  const PoseArgument pose = ParsePoseArgument("+1e2,.5,-360", "--pose");
  CHECK(pose.x_m == 100.0);
  CHECK(pose.y_m == 0.5);
  CHECK(pose.yaw_deg == -360.0);
  CHECK(ParsePoseArgument("100000,-100000,360", "--pose").x_m == kPoseMaxAbsMetres);
}

TEST_CASE("ParseCommandLine rejects what it does not know, naming it", "[harness]") {
  CHECK_THAT(ErrorOf({}), Catch::StartsWith("command line: "));
  CHECK_THAT(ErrorOf({"fly"}), Catch::StartsWith("command line: unknown subcommand 'fly'"));
  CHECK_THAT(ErrorOf({"world", "--bogus"}), Catch::Contains("--bogus"));
  CHECK_THAT(ErrorOf({"run", "a.yaml", "b.yaml"}), Catch::Contains("b.yaml"));
  CHECK_THAT(ErrorOf({"run", "--force=yes"}), Catch::Contains("force"));
  CHECK_THAT(ErrorOf({"run", ""}), Catch::StartsWith("command line: scenario: an empty"));
  CHECK_THAT(ErrorOf({"run", "--out", ""}), Catch::StartsWith("command line: --out: an empty"));
  CHECK_THAT(ErrorOf({"run", "--export="}), Catch::StartsWith("command line: --export: "));
  CHECK_THAT(ErrorOf({"drive", "--pose", "1,2,3"}), Catch::Contains("--pose"));
}

TEST_CASE("where takes a room number, a run folder and optionally one pipeline", "[harness]") {
  const CommandLine all = ParseCommandLine({"where", "101", "--run", "out/run"});
  CHECK(all.job == Job::kWhere);
  CHECK(all.where.room == "101");
  CHECK(all.where.run_dir == "out/run");
  CHECK(all.where.pipeline.empty());
  const CommandLine one = ParseCommandLine({"where", "--pipeline=p1_ekf", "A-12", "--run", "r"});
  CHECK(one.where.room == "A-12");
  CHECK(one.where.pipeline == "p1_ekf");

  CHECK_THAT(ErrorOf({"where", "101"}), Catch::Contains("--run"));
  CHECK_THAT(ErrorOf({"where", "--run", "r"}), Catch::Contains("room"));
  CHECK(ErrorOf({"where", "1 01", "--run", "r"}) ==
        "command line: ROOM: expected a room number: 1 to 32 printable characters without spaces "
        "(got '1 01')");
  CHECK_THAT(ErrorOf({"where", std::string(33, '1'), "--run", "r"}),
             Catch::StartsWith("command line: ROOM: "));
  CHECK_THAT(ErrorOf({"where", "101", "--run", ""}),
             Catch::StartsWith("command line: --run: an empty folder name"));
  for (const char* bad : {"", "../x", "a/b", "p q"}) {
    CHECK_THAT(ErrorOf({"where", "101", "--run", "r", "--pipeline", bad}),
               Catch::StartsWith("command line: --pipeline: expected a pipeline name"));
  }
  CHECK_THAT(ParseCommandLine({"where", "--help"}).help_text,
             Catch::Contains("Exit codes: 0 success, 2 bad input"));
  CHECK_THAT(ErrorOf({"wher"}), Catch::Contains("drive, where, detect, train-detectors, dataset, "
                                                "score, study, test, plugin or evaluate"));
}

TEST_CASE("ParseCommandLine fills the detect request", "[harness]") {
  const CommandLine plain = ParseCommandLine({"detect", "img.png"});
  CHECK(plain.job == Job::kDetect);
  CHECK(plain.detect.image_file == "img.png");
  CHECK(plain.detect.camera == DetectCamera::kFront);
  CHECK_FALSE(plain.detect.depth_file);
  CHECK_FALSE(plain.detect.overlay_file);

  const CommandLine full =
      ParseCommandLine({"detect", "a.png", "--camera", "front", "--depth", "d.png", "--out=o.png"});
  REQUIRE(full.detect.depth_file);
  CHECK(*full.detect.depth_file == "d.png");
  REQUIRE(full.detect.overlay_file);
  CHECK(*full.detect.overlay_file == "o.png");
  CHECK(ParseCommandLine({"detect", "a.png", "--camera=lateral"}).detect.camera ==
        DetectCamera::kLateral);
  const CommandLine upward =
      ParseCommandLine({"detect", "a.png", "--camera", "upward", "--intrinsics", "i.json"});
  CHECK(upward.detect.camera == DetectCamera::kUpward);
  REQUIRE(upward.detect.intrinsics_file);
  CHECK(*upward.detect.intrinsics_file == "i.json");
  CHECK_THAT(ParseCommandLine({"detect", "--help"}).help_text,
             Catch::Contains("Exit codes: 0 success"));
  CHECK_THAT(ParseCommandLine({"--help"}).help_text, Catch::Contains("detect"));
}

TEST_CASE("the detect command line is strict", "[harness]") {
  CHECK_THAT(ErrorOf({"detect"}), Catch::Contains("image is required"));
  CHECK_THAT(ErrorOf({"detect", ""}), Catch::StartsWith("command line: image: an empty"));
  CHECK_THAT(ErrorOf({"detect", "a.png", "b.png"}), Catch::Contains("b.png"));
  for (const char* bad : {"rear", "", "Front", "front ", "up"}) {
    INFO("--camera '" << bad << "'");
    CHECK_THAT(ErrorOf({"detect", "a.png", "--camera", bad}),
               Catch::StartsWith("command line: --camera: expected front, lateral or upward"));
  }
  CHECK_THAT(ErrorOf({"detect", "a.png", "--intrinsics", "i.json"}),
             Catch::StartsWith("command line: --intrinsics: only for --camera upward"));
  CHECK_THAT(ErrorOf({"detect", "a.png", "--camera", "upward", "--intrinsics", ""}),
             Catch::StartsWith("command line: --intrinsics: an empty file name"));
  CHECK_THAT(ErrorOf({"detect", "a.png", "--depth="}),
             Catch::StartsWith("command line: --depth: "));
  CHECK_THAT(ErrorOf({"detect", "a.png", "--depth", ""}),
             Catch::StartsWith("command line: --depth: an empty file name"));
  CHECK_THAT(ErrorOf({"detect", "a.png", "--out", ""}),
             Catch::StartsWith("command line: --out: an empty file name"));
  CHECK_THAT(ErrorOf({"detect", "a.png", "--camera", "lateral", "--depth", "d.png"}),
             Catch::StartsWith("command line: --depth: only the front camera"));
  CHECK_THAT(ErrorOf({"detect", "a.png", "--seed", "1"}), Catch::Contains("--seed"));
  CHECK_THAT(ErrorOf({"detect", "a.png", "--force"}), Catch::Contains("--force"));
  CHECK_THAT(ErrorOf({"detekt", "a.png"}),
             Catch::Contains("expected world, snapshot, run, replay, drive, where, detect, "
                             "train-detectors, dataset, score, study, test, plugin or evaluate"));
}

TEST_CASE("ParseCommandLine fills the study, study merge and test requests", "[harness]") {
  const CommandLine study = ParseCommandLine(
      {"study", "s.yaml", "--runs", "20", "--jobs", "2", "--shard", "3/8", "--seed", "5"});
  CHECK(study.job == Job::kStudy);
  CHECK(study.study.scenario_file == "s.yaml");
  CHECK(study.study.runs == 20);
  CHECK(study.study.jobs == 2);
  CHECK(study.study.shard_index == 2);
  CHECK(study.study.shard_count == 8);
  CHECK(study.study.seed == 5u);
  CHECK(study.study.out_dir == "out/study");
  CHECK(study.study.may_diverge.empty());
  const CommandLine baselines = ParseCommandLine(
      {"study", "s.yaml", "--may-diverge", "odometry,p1_harris", "--may-diverge", "x"});
  CHECK(baselines.study.may_diverge == std::vector<std::string>{"odometry", "p1_harris", "x"});
  const CommandLine slurm =
      ParseCommandLine({"study", "s.yaml", "--slurm", "--submit", "--slurm-tasks", "12"});
  CHECK(slurm.study.slurm);
  CHECK(slurm.study.submit);
  CHECK(slurm.study.slurm_tasks == 12);
  const CommandLine merge = ParseCommandLine({"study", "merge", "a", "b", "--out", "m"});
  CHECK(merge.job == Job::kStudyMerge);
  REQUIRE(merge.study.merge_dirs.size() == 2);
  CHECK(merge.study.merge_dirs[1] == "b");
  CHECK(merge.study.out_dir == "m");
  const CommandLine test = ParseCommandLine({"test", "a.yaml", "b.yaml", "--junit", "j.xml"});
  CHECK(test.job == Job::kTest);
  CHECK(test.test.files.size() == 2);
  CHECK(test.test.junit_file == std::filesystem::path("j.xml"));
  for (const auto& [args, flag] : std::vector<std::pair<std::vector<std::string>, std::string>>{
           {{"study", "s.yaml", "--runs", "0"}, "--runs"},
           {{"study", "s.yaml", "--runs", "10001"}, "--runs"},
           {{"study", "s.yaml", "--jobs", "1.5"}, "--jobs"},
           {{"study", "s.yaml", "--shard", "9/8"}, "--shard"},
           {{"study", "s.yaml", "--shard", "0/8"}, "--shard"},
           {{"study", "s.yaml", "--shard", "3"}, "--shard"},
           {{"study", "s.yaml", "--submit"}, "--submit"},
           {{"study", "s.yaml", "--slurm-tasks", "3"}, "--slurm-tasks"},
           {{"study", "s.yaml", "--slurm", "--slurm-tasks", "1001"}, "--slurm-tasks"},
           {{"study", "s.yaml", "--slurm", "--shard", "1/2"}, "--shard"},
           {{"test", "a.yaml", "--junit", ""}, "--junit"}}) {
    INFO(args[2]);
    CHECK_THAT(ErrorOf(args), Catch::Contains(flag));
  }
}

TEST_CASE("ParseCommandLine fills the dataset request", "[harness]") {
  const CommandLine plain = ParseCommandLine({"dataset", "s.yaml"});
  CHECK(plain.job == Job::kDataset);
  CHECK(plain.dataset.scenario_file == "s.yaml");
  CHECK(plain.dataset.worlds == 1);
  CHECK(plain.dataset.frames_per_world == 1);
  CHECK(plain.dataset.cameras.empty());
  CHECK(plain.dataset.poses == DatasetPoseMode::kRandom);
  CHECK(plain.dataset.out_dir == "out/dataset");

  const CommandLine full = ParseCommandLine(
      {"dataset", "s.yaml", "--worlds", "100000", "--frames-per-world=7", "--cameras",
       "upward,front", "--poses", "path", "--seed", "9", "--out", "d", "--force"});
  CHECK(full.dataset.worlds == 100000);
  CHECK(full.dataset.frames_per_world == 7);
  CHECK(full.dataset.cameras == std::vector<std::string>{"upward", "front"});
  CHECK(full.dataset.poses == DatasetPoseMode::kPath);
  CHECK(full.dataset.seed == 9u);
  CHECK(full.dataset.force);
}

TEST_CASE("the dataset command line is strict", "[harness]") {
  for (const char* bad : {"0", "100001", "-1", "1.5", "x", ""}) {
    INFO("count '" << bad << "'");
    CHECK_THAT(ErrorOf({"dataset", "--worlds", bad}),
               Catch::StartsWith("command line: --worlds: "));
    CHECK_THAT(ErrorOf({"dataset", "--frames-per-world", bad}),
               Catch::StartsWith("command line: --frames-per-world: "));
  }
  for (const char* bad : {"", ",", "front,", ",front", "front,,lateral"}) {
    INFO("--cameras '" << bad << "'");
    CHECK_THAT(ErrorOf({"dataset", "--cameras", bad}),
               Catch::StartsWith("command line: --cameras: an empty camera name"));
  }
  CHECK_THAT(ErrorOf({"dataset", "--poses", "grid"}),
             Catch::StartsWith("command line: --poses: expected path, random or plates"));
  CHECK_THAT(ErrorOf({"dataset", "--seed", "-1"}), Catch::StartsWith("command line: --seed: "));
}

TEST_CASE("ParseCommandLine fills the score request", "[harness]") {
  const CommandLine plain = ParseCommandLine({"score", "d.json", "--dataset", "ds"});
  CHECK(plain.job == Job::kScore);
  CHECK(plain.score.detections_file == "d.json");
  CHECK(plain.score.dataset_dir == "ds");
  CHECK_FALSE(plain.score.camera);
  CHECK_FALSE(plain.score.report_dir);
  CHECK(plain.score.expectations.empty());

  const CommandLine full =
      ParseCommandLine({"score", "d.json", "--dataset", "ds", "--camera", "upward", "--out", "r",
                        "--force", "--expect", "lamp.ap50>=0.8", "--expect", "door.recall<0.25"});
  REQUIRE(full.score.camera);
  CHECK(*full.score.camera == "upward");
  CHECK(*full.score.report_dir == "r");
  CHECK(full.score.force);
  REQUIRE(full.score.expectations.size() == 2);
  CHECK(full.score.expectations[0].class_name == "lamp");
  CHECK(full.score.expectations[0].metric == "ap50");
  CHECK(full.score.expectations[0].op == ScoreExpectation::Op::kGreaterEqual);
  CHECK(full.score.expectations[0].value == 0.8);
  CHECK(full.score.expectations[1].op == ScoreExpectation::Op::kLess);
  CHECK(full.score.expectations[1].value == 0.25);
}

TEST_CASE("the score command line is strict", "[harness]") {
  CHECK_THAT(ErrorOf({"score", "d.json"}), Catch::Contains("--dataset is required"));
  CHECK_THAT(ErrorOf({"score", "", "--dataset", "ds"}),
             Catch::StartsWith("command line: detections: an empty file name"));
  const auto expect_error = [](const char* text) {
    return ErrorOf({"score", "d.json", "--dataset", "ds", "--expect", text});
  };
  CHECK_THAT(expect_error("lamp.ap50"), Catch::StartsWith("command line: --expect: expected"));
  CHECK_THAT(expect_error("lamp>=1"), Catch::StartsWith("command line: --expect: expected"));
  CHECK_THAT(expect_error("lamps.ap50>=1"),
             Catch::StartsWith("command line: --expect: unknown class 'lamps'"));
  CHECK_THAT(expect_error("lamp.map>=1"),
             Catch::StartsWith("command line: --expect: unknown metric 'map'"));
  CHECK_THAT(expect_error("lamp.ap50>=high"), Catch::StartsWith("command line: --expect: "));
  CHECK_THAT(expect_error("lamp.ap50>=nan"), Catch::StartsWith("command line: --expect: "));
}

TEST_CASE("ParseCommandLine fills the evaluate request", "[harness]") {
  const CommandLine plain = ParseCommandLine({"evaluate", "run", "--estimate", "mine=est.tum"});
  CHECK(plain.job == Job::kEvaluate);
  CHECK(plain.evaluate.run_dir == "run");
  REQUIRE(plain.evaluate.estimates.size() == 1);
  CHECK(plain.evaluate.estimates[0].name == "mine");
  CHECK(plain.evaluate.estimates[0].file == "est.tum");
  CHECK(plain.evaluate.alignment == evaluate::Alignment::kNone);
  CHECK(plain.evaluate.max_dt_s == 0.01);
  CHECK(plain.evaluate.out_dir.empty());
  CHECK(plain.evaluate.plots);

  const CommandLine full =
      ParseCommandLine({"evaluate", "run", "--estimate", "a=x=y.txt", "--estimate", "b-2=b.tum",
                        "--landmarks", "a=map.json", "--align", "sim3", "--max-dt", "0.02", "--out",
                        "o", "--force", "--no-plots", "--expect", "a.ate_rmse_m<0.2"});
  REQUIRE(full.evaluate.estimates.size() == 2);
  CHECK(full.evaluate.estimates[0].file == "x=y.txt");  // the first '=' splits
  CHECK(full.evaluate.landmarks[0].name == "a");
  CHECK(full.evaluate.alignment == evaluate::Alignment::kSim3);
  CHECK(full.evaluate.max_dt_s == 0.02);
  CHECK(full.evaluate.out_dir == "o");
  CHECK(full.evaluate.force);
  CHECK_FALSE(full.evaluate.plots);
  CHECK(full.evaluate.expectations == std::vector<std::string>{"a.ate_rmse_m<0.2"});
}

TEST_CASE("the evaluate command line is strict", "[harness]") {
  const auto error = [](Args extra) {
    Args args = {"evaluate", "run"};
    args.insert(args.end(), extra.begin(), extra.end());
    return ErrorOf(args);
  };
  CHECK_THAT(error({}), Catch::StartsWith("command line: --estimate: nothing to evaluate"));
  CHECK_THAT(ErrorOf({"evaluate", "--estimate", "a=b"}), Catch::Contains("run is required"));
  CHECK_THAT(error({"--estimate", "ab"}),
             Catch::StartsWith("command line: --estimate: expected NAME=FILE"));
  CHECK_THAT(error({"--estimate", "a="}), Catch::Contains("an empty file name"));
  CHECK_THAT(error({"--estimate", "../a=f"}),
             Catch::StartsWith("command line: --estimate: expected a pipeline name"));
  CHECK_THAT(error({"--estimate", "a=f", "--estimate", "a=g"}),
             Catch::Contains("the name 'a' is given twice"));
  CHECK_THAT(error({"--estimate", "a=f", "--align", "sim2"}),
             Catch::StartsWith("command line: --align: expected none, se2, se3 or sim3"));
  CHECK_THAT(error({"--estimate", "a=f", "--max-dt", "-0.1"}),
             Catch::StartsWith("command line: --max-dt: must not be negative"));
  CHECK_THAT(error({"--estimate", "a=f", "--max-dt", "2"}),
             Catch::StartsWith("command line: --max-dt: "));
  CHECK_THAT(error({"--estimate", "a=f", "--max-dt", "nan"}),
             Catch::StartsWith("command line: --max-dt: "));
  CHECK_THAT(error({"--estimate", "a=f", "--out", ""}), Catch::Contains("an empty folder name"));
  CHECK_THAT(error({"--estimate", "a=f", "--frame", "b=front"}),
             Catch::StartsWith("command line: --frame: 'b' is no --estimate name"));
  CHECK_THAT(error({"--estimate", "a=f", "--frame", "a=../x"}),
             Catch::StartsWith("command line: --frame: expected a pipeline name"));
  const CommandLine framed =
      ParseCommandLine({"evaluate", "run", "--estimate", "a=f", "--frame", "a=front"});
  REQUIRE(framed.evaluate.frames.size() == 1);
  CHECK(framed.evaluate.frames[0].camera == "front");
  Args many;
  for (int i = 0; i <= 64; ++i) {
    many.push_back("--estimate");
    many.push_back("e" + std::to_string(i) + "=f");
  }
  CHECK_THAT(error(many), Catch::Contains("at most 64 files"));
}

}  // namespace
}  // namespace corridorsim

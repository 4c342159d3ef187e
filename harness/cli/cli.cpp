#include "harness/cli/cli.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iterator>
#include <limits>
#include <memory>
#include <utility>

#include <CLI/CLI.hpp>

#include "common/error.h"
#include "harness/scenario/overrides.h"
#include "harness/study/study_file.h"
#include "slam/registry.h"

namespace corridorsim {
namespace {

// `run --help`'s list of the shipped pipeline types (slam/registry.h).
std::string PipelineListFooter() {
  std::string names;
  for (const std::string& n : slam::PipelineNames()) names += (names.empty() ? "" : ", ") + n;
  return "Pipelines (under `pipelines:`, docs/scenarios.md; P1's: docs/p1.md): " + names + ".\n";
}

const SourceLocation kCommandLine{"command line", 0, 0};

// Longest number text accepted (a double needs at most ~25 characters).
constexpr std::size_t kMaxNumberChars = 64;

[[noreturn]] void Fail(const std::string& flag, const std::string& message) {
  throw InputError(kCommandLine, flag, message);
}

// The text as it was given, quoted and cut for a message (the input may be long or binary).
std::string Quoted(const std::string& text) {
  std::string shown;
  for (char c : text.substr(0, 80)) {
    const auto u = static_cast<unsigned char>(c);
    shown += (u < 0x20 || u == 0x7f) ? '?' : c;
  }
  return "'" + shown + (text.size() > 80 ? "...'" : "'");
}
std::string Got(const std::string& text) { return "(got " + Quoted(text) + ")"; }

// `--set KEY=VALUE`, one per option (repeatable): harness/scenario/overrides.h.
void AddSetOption(CLI::App* job, std::vector<std::string>* settings) {
  job->add_option("--set", *settings,
                  "Set a scenario (or study.*) key after the file's include chain: dotted key, "
                  "YAML value (duration_s=20, world.doors.count=4, expectations=[], "
                  "path.commands.1.0=2.5); checked like the file's keys and echoed in "
                  "scenario.yaml; repeatable, a later one wins (docs/scenarios.md)")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);  // one KEY=VALUE per --set: never the scenario file after it
}

// A count of a flag: a whole number in [1, max].
int WholeArgument(const std::string& text, int max, const std::string& flag) {
  // Parsed up to any int, so that the bound named is the count's, not the parser's.
  const double v = ParseNumberArgument(text, std::numeric_limits<int>::max(), flag);
  if (v != std::floor(v) || v < 1 || v > max)
    Fail(flag, "must be a whole number in [1, " + std::to_string(max) + "] " + Got(text));
  return static_cast<int>(v);
}

// The string options of every job: the scenario file, --seed, --out and --force (the folder's
// default shown in --help).
struct JobOptions {
  std::string scenario;
  std::string seed;
  std::string out;
  bool force = false;
  std::vector<std::string> settings;
  CLI::Option* scenario_option = nullptr;
  CLI::Option* seed_option = nullptr;

  JobOptions(CLI::App* job, std::string default_out, const char* scenario_help,
             const char* seed_help, const char* out_help)
      : out(std::move(default_out)) {
    scenario_option = job->add_option("scenario", scenario, scenario_help);
    seed_option = job->add_option("--seed", seed, seed_help)->type_name("UINT64");
    job->add_option("--out", out, out_help)->capture_default_str();
    job->add_flag("--force", force,
                  "Replace a non-empty output folder (it is replaced whole, never mixed)")
        ->disable_flag_override();
    AddSetOption(job, &settings);
  }

  // Checks the strings and moves them into the request.
  void Resolve(JobRequest* request) const {
    if (scenario_option->count() > 0 && scenario.empty()) Fail("scenario", "an empty file name");
    if (seed_option->count() > 0) request->seed = ParseSeedArgument(seed, "--seed");
    if (out.empty()) Fail("--out", "an empty folder name");
    ParseSettings(settings);  // the syntax now; the keys when the scenario is loaded
    request->settings = settings;
    request->scenario_file = scenario;
    request->out_dir = out;
    request->force = force;
  }
};

constexpr const char* kDefaultScenarioHelp =
    "(default: ./scenarios/default.yaml if it exists, else the shipped one; the file used is "
    "printed)";

constexpr const char* kFolderFooter =
    "Output folder: written whole. Files go to a staging folder beside it (.<name>.partial-<pid>) "
    "that replaces the folder when the job is done; a failed or killed job leaves the previous "
    "folder as it was. A folder that holds files is refused (exit 2) unless --force.\n";

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

CommandLine ParseCommandLine(const std::vector<std::string>& args) {
  CLI::App app{"corridorsim: a simulation harness for corridor SLAM", "corridorsim"};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Show the help of every subcommand");
  app.set_version_flag("--version", std::string("corridorsim"),
                       "Print the version, the git describe of the build and the SDK ABI version");
  app.footer(
      "Exit codes: 0 success, 2 bad input, 1 other failures; `run` also 3 (an expectation "
      "failed), 4 (results written, an extra failed) and 5 (a pipeline failed; the others' "
      "results are written); `score` also 3 (an --expect failed); "
      "`evaluate` also 3 (an --expect failed) and 4 (results written, plots/ failed). Run "
      "`corridorsim <subcommand> --help`.");

  CommandLine parsed;

  CLI::App* world = app.add_subcommand(
      "world", "Generate a corridor world and write its geometry, textures, ground truth and plan");
  JobOptions world_options(world, "out/world",
                           "Scenario YAML whose `world:` section and `seed` are used "
                           "(default: ./scenarios/default.yaml if it exists, else the shipped "
                           "one; the file used is printed)",
                           "Seed of the world's random streams (default: the scenario's `seed`)",
                           "Output folder for world.obj, world.mtl, textures/, ground_truth.json, "
                           "map.png");
  world->footer(
      std::string("Writes world.obj + world.mtl + textures/*.png (open in MeshLab or Blender), "
                  "ground_truth.json (door plates, lamps, doors, corridor segments, corner "
                  "points, distractors; metres, world frame) and map.png (top-down plan).\n") +
      kFolderFooter +
      "Exit codes: 0 success, 2 bad input (file:line:column: key: message, or command line: "
      "--flag: message; nothing is written), 1 other failures.");

  CLI::App* snapshot = app.add_subcommand(
      "snapshot", "Place the robot at one pose and render every camera of the rig");
  JobOptions snapshot_options(
      snapshot, "out/snapshot",
      (std::string("Scenario YAML (world, sensors, render) ") + kDefaultScenarioHelp).c_str(),
      "Seed of the world and the sensor noise", "Output folder");
  std::string pose_text;
  snapshot
      ->add_option("--pose", pose_text,
                   "Robot pose x,y,yaw: metres in the world frame (|x|, |y| <= 100000) and "
                   "degrees (0 = along +x, |yaw| <= 360)")
      ->required()
      ->type_name("X,Y,YAW");
  snapshot->footer(
      std::string(
          "Writes per camera <camera>_rgb.png, <camera>_labels.png (16-bit RGB: R = semantic "
          "class, G = instance id >> 16, B = instance id & 0xffff), <camera>_overlay.png (ground "
          "truth drawn on the image), front_depth.png (16-bit, 5000 per metre, 0 = invalid), "
          "plus frame_ground_truth.json and intrinsics.json.\n"
          "Environment: CORRIDORSIM_RENDER_BACKEND=osmesa|egl overrides the scenario's "
          "render.backend.\n") +
      kFolderFooter +
      "Exit codes: 0 success, 2 bad input (nothing is written), 1 other failures (e.g. no GL "
      "context).");

  CLI::App* run = app.add_subcommand(
      "run",
      "Run a scenario closed loop, score every pipeline against ground truth, write the run");
  JobOptions run_options(run, "out/run",
                         (std::string("Scenario YAML ") + kDefaultScenarioHelp).c_str(),
                         "Seed of every random stream of the run", "Run folder");
  std::string export_text;
  CLI::Option* export_option =
      run->add_option("--export", export_text,
                      "Also write a dataset into this folder (outside the run folder): TUM RGB-D "
                      "(front), EuRoC/ASL (upward, lateral), odometry CSV, labels and COCO plate "
                      "boxes (docs/export.md); staged and replaced like --out");
  bool no_plots = false, no_viewer = false;
  run->add_flag("--no-plots", no_plots, "Skip plots/ (matplotlib)")->disable_flag_override();
  run->add_flag("--no-viewer", no_viewer, "Skip viewer.html (docs/viewer.md)")
      ->disable_flag_override();
  run->add_flag("--keep-frames", parsed.run.keep_frames,
                "Keep downscaled JPEGs of the rendered frames in frames/ for viewer.html "
                "(within --keep-frames-mb)")
      ->disable_flag_override();
  std::string keep_frames_mb;
  CLI::Option* keep_frames_mb_option = run->add_option(
      "--keep-frames-mb", keep_frames_mb,
      "The most frames/ may hold, MB (1-40, default 20): past it every other kept frame is "
      "dropped and the stride doubles");
  run->add_flag("--check", parsed.run.check_only,
                "Only check the scenario: load it, build its world, path and pipelines, and exit")
      ->disable_flag_override();
  run->footer(
      std::string(
          "Writes the results first: scenario.yaml (resolved, with the seed), world.json, "
          "ground_truth.tum (the planar truth at 100 Hz and every odometry stamp, as drive "
          "writes it), <pipeline>.tum, <pipeline>_cov.txt (ov_eval), "
          "<pipeline>_errors.csv, <pipeline>_nis.csv, <pipeline>_landmarks.json, "
          "<pipeline>_detections.csv, "
          "metrics.json (docs/metrics.md), timing.json, events.json, "
          "provenance.json (what the bytes depend on: build, compiler, Mesa, backend); then "
          "the extras: maps/, the --export dataset, plots/ (python3 scripts/plot_run.py), "
          "viewer.html (scripts/make_viewer.py: one page, offline, docs/viewer.md).\n") +
      PipelineListFooter() + kFolderFooter +
      "Exit codes: 0 success; 5 a pipeline failed (it alone: the run went on and the other "
      "pipelines' results are written; the reason is on stderr and in events.json); 3 an "
      "expectation failed; 4 the results are written but an extra (maps/, plots/, viewer.html, "
      "the --export dataset) failed (its message is on stderr); 5 takes precedence over 3, 3 "
      "over 4; 2 bad input (nothing is written); 1 other failures (the previous folder is left "
      "as it was).");

  CLI::App* drive = app.add_subcommand(
      "drive", "Drive the scenario's path closed loop and write trajectories, odometry and events");
  JobOptions drive_options(
      drive, "out/drive",
      (std::string("Scenario YAML (world, robot, path, sensors) ") + kDefaultScenarioHelp).c_str(),
      "Seed of the world, the odometry errors and the sensor noise", "Output folder");
  drive
      ->add_flag("--save-frames", parsed.drive.save_frames,
                 "Render the cameras at their rates and write every frame")
      ->disable_flag_override();
  drive->footer(
      std::string(
          "Writes ground_truth.tum (the planar truth world_from_robot: x, y, yaw with z = 0, at "
          "100 Hz and every odometry stamp; the same file a run writes), ground_truth_3d.tum (the "
          "physics' full 3D pose at the same stamps) and odometry.tum (wheel odometry dead "
          "reckoning from the true start pose), all TUM format: t x y z qx qy qz qw, seconds; "
          "odometry.csv (the raw messages: per-wheel distances and ticks); events.json "
          "(collisions, slips, path done or timeout); provenance.json. With --save-frames: "
          "frames/<camera>/"
          "{rgb,labels,depth}/<t>.png, frames/<camera>/frames.json (pose and visible landmarks "
          "per frame) and frames/intrinsics.json.\n") +
      kFolderFooter + "Exit codes: 0 success, 2 bad input (nothing is written), 1 other failures.");

  CLI::App* where = app.add_subcommand(
      "where", "Say where a room is, as each pipeline of a finished run mapped it");
  std::string where_room, where_run, where_pipeline;
  where->add_option("room", where_room, "Room number, as on its door plate (e.g. 101)")
      ->required()
      ->type_name("ROOM");
  where->add_option("--run", where_run, "Run folder (corridorsim run --out)")
      ->required()
      ->type_name("DIR");
  CLI::Option* where_pipeline_option = where->add_option(
      "--pipeline", where_pipeline,
      "Only this pipeline's map (default: every DIR/maps/<pipeline>_semantic.json)");
  where->footer(
      "Reads DIR/maps/<pipeline>_semantic.json (the semantic map: room number -> door plate "
      "position with covariance) and prints per pipeline x and y in metres, world frame, with "
      "their 1-sigma.\n"
      "Exit codes: 0 success, 2 bad input (the folder or a map missing or malformed, or no map "
      "knows the room: the message lists the known rooms), 1 other failures.");

  CLI::App* detect = app.add_subcommand("detect",
                                        "Run the detectors (vanishing point, door plates, lamps, "
                                        "corners) on an image; JSON on stdout");
  std::string detect_image, detect_camera = "front", detect_depth, detect_out, detect_intrinsics;
  CLI::Option* detect_image_option =
      detect->add_option("image", detect_image, "PNG image (8-bit grey, RGB or RGBA, or 16-bit)")
          ->required()
          ->type_name("IMAGE.png");
  detect
      ->add_option("--camera", detect_camera,
                   "The camera the image comes from: front (vanishing point and corners; P1's "
                   "RGB-D sensor), lateral (door plates and corners) or upward (P3's circular "
                   "lamps and corners)")
      ->capture_default_str()
      ->type_name("front|lateral|upward");
  CLI::Option* detect_depth_option =
      detect
          ->add_option("--depth", detect_depth,
                       "Depth registered to the image (front only): 16-bit PNG at 5000 per metre, "
                       "0 = invalid (TUM RGB-D; snapshot's front_depth.png); gives each corner "
                       "its depth")
          ->type_name("D.png");
  CLI::Option* detect_intrinsics_option =
      detect
          ->add_option("--intrinsics", detect_intrinsics,
                       "The upward camera's model as intrinsics.json holds it (docs/frames.md; a "
                       "dataset's upward/intrinsics.json, or snapshot's intrinsics.json, whose "
                       "\"upward\" entry is used); default: the default rig's upward "
                       "camera (Kannala-Brandt, 640x480, 110 deg)")
          ->type_name("FILE.json");
  CLI::Option* detect_out_option =
      detect
          ->add_option("--out", detect_out, "Also write the image with what was found drawn on it")
          ->type_name("overlay.png");
  detect->footer(
      "Prints one JSON document on stdout (docs/detectors.md): the image, the camera, then one "
      "section per detector: vanishing_point (front: the point, its lines and quality, or the "
      "status saying why there is none), door_plates (lateral), lamps (upward: circular lamps "
      "and the rejected bright regions, P3 section II) and corners (pixel, depth_m, response). "
      "Images are at "
      "most 8192 px a side and 256 MiB.\n"
      "Exit codes: 0 success (also when nothing was found), 2 bad input (a missing, unreadable "
      "or non-PNG file, an image too large, a depth image of another size; one message naming "
      "the file, nothing is printed or written), 1 other failures.");

  CLI::App* train = app.add_subcommand(
      "train-detectors",
      "Render labelled lateral views of seeded worlds, train P1's door-plate SVM and "
      "room-number MLP, evaluate them on held-out worlds and fonts");
  std::string train_out = "models", train_report, train_seed, train_worlds, eval_worlds, views;
  train->add_option("--out", train_out, "Folder of the two model files (replaced atomically)")
      ->capture_default_str();
  CLI::Option* report_option =
      train->add_option("--report", train_report,
                        "Also write training_report.json and training_report.png into this "
                        "folder (staged and replaced like every output folder)");
  CLI::Option* train_seed_option =
      train->add_option("--seed", train_seed, "Seed of every random choice (default 1)")
          ->type_name("UINT64");
  CLI::Option* train_worlds_option =
      train->add_option("--train-worlds", train_worlds, "Training worlds, 1-200 (default 24)")
          ->type_name("N");
  CLI::Option* eval_worlds_option =
      train
          ->add_option("--eval-worlds", eval_worlds,
                       "Held-out evaluation worlds, 1-200 (default 8)")
          ->type_name("N");
  CLI::Option* views_option =
      train->add_option("--views", views, "Lateral views per world, 1-500 (default 48)")
          ->type_name("N");
  std::string train_dataset, eval_dataset;
  CLI::Option* train_dataset_option =
      train
          ->add_option("--dataset", train_dataset,
                       "Train on this folder of `corridorsim dataset` (its lateral camera; e.g. "
                       "--poses plates, appearance randomisation) instead of the built-in views")
          ->type_name("DIR");
  CLI::Option* eval_dataset_option =
      train
          ->add_option("--eval-dataset", eval_dataset,
                       "Evaluate on this dataset folder instead of the built-in held-out worlds")
          ->type_name("DIR");
  bool train_force = false;
  train->add_flag("--force", train_force, "Replace a non-empty --report folder")
      ->disable_flag_override();
  train->footer(
      "The built-in views are the frames of `corridorsim dataset "
      "scenarios/datasets/train_detectors.yaml "
      "--cameras lateral --poses plates`, rendered in memory (training worlds from a seed drawn "
      "from --seed, the held-out worlds after them).\n"
      "Writes <out>/door_plate_svm.yml and <out>/room_number_mlp.yml (cv::ml YAML, "
      "docs/detectors.md); with --report also training_report.json (detection precision and "
      "recall, reading accuracy by distance and viewing angle, the digit confusion matrix, the "
      "P1 targets) and training_report.png. The same arguments write byte-identical models.\n"
      "Exit codes: 0 success, 2 bad input (nothing is written), 1 other failures (e.g. no GL "
      "context).");

  CLI::App* dataset = app.add_subcommand(
      "dataset",
      "Render labelled images of seeded worlds (images, labels, depth, truth, COCO annotations) "
      "for developing detectors");
  JobOptions dataset_options(
      dataset, "out/dataset",
      (std::string("Scenario YAML (world, sensors, path) ") + kDefaultScenarioHelp).c_str(),
      "Seed of world 0 (world w uses seed + w; default: the scenario's `seed`)",
      "Dataset folder (filled in place and resumable; docs/datasets.md)");
  std::string dataset_worlds = "1", dataset_frames = "1", dataset_cameras, dataset_poses = "random";
  dataset->add_option("--worlds", dataset_worlds, "Number of worlds, 1-100000")
      ->capture_default_str()
      ->type_name("N");
  dataset->add_option("--frames-per-world", dataset_frames, "Poses rendered per world, 1-100000")
      ->capture_default_str()
      ->type_name("M");
  CLI::Option* dataset_cameras_option =
      dataset
          ->add_option("--cameras", dataset_cameras,
                       "Comma-separated cameras to render, each enabled in the scenario "
                       "(default: every enabled camera)")
          ->type_name("front,lateral,upward");
  dataset
      ->add_option("--poses", dataset_poses,
                   "random: uniform in the corridor, yaw uniform, collisions redrawn; path: evenly "
                   "spaced along the scenario's path; plates: the lateral camera aimed at door "
                   "plates (a quarter at posters and notice boards), 0.4-3.5 m, up to 50 deg off "
                   "their normal (what train-detectors learns from)")
      ->capture_default_str()
      ->type_name("path|random|plates");
  dataset->footer(
      "Writes DIR/dataset.json (the manifest), per camera DIR/<camera>/{images,labels,depth,truth}/"
      "w<WWW>_f<FFFF>.{png,json}, DIR/<camera>/intrinsics.json and DIR/<camera>/annotations.json "
      "(COCO: door_plate 1, door 2, lamp 3, ceiling_corner 4), and "
      "DIR/worlds/w<WWW>/ground_truth.json (docs/datasets.md).\n"
      "Output folder: filled in place, every file atomically. Rerunning the same command over a "
      "folder whose dataset.json matches resumes it (frames with a truth file are skipped); a "
      "folder with another dataset.json is refused (exit 2) unless --force, which clears it; a "
      "folder with files but no dataset.json is never touched.\n"
      "Exit codes: 0 success, 2 bad input, 1 other failures (e.g. no GL context).");

  CLI::App* score = app.add_subcommand(
      "score", "Score detections (COCO results JSON) against a dataset's annotations");
  std::string score_detections, score_dataset, score_camera, score_out;
  bool score_force = false;
  std::vector<std::string> score_expect;
  score
      ->add_option("detections", score_detections,
                   "COCO results: [{image_id, category_id, bbox | circle | point | keypoints, "
                   "score, room_number?}, ...]")
      ->required()
      ->type_name("DETECTIONS.json");
  score->add_option("--dataset", score_dataset, "Dataset folder (corridorsim dataset --out)")
      ->required()
      ->type_name("DIR");
  CLI::Option* score_camera_option =
      score->add_option("--camera", score_camera,
                        "The camera the detections are for (default: the dataset's only one)");
  CLI::Option* score_out_option =
      score
          ->add_option("--out", score_out,
                       "Also write score.json and score.png into this folder (staged and "
                       "replaced like every output folder)")
          ->type_name("REPORT_DIR");
  score->add_flag("--force", score_force, "Replace a non-empty --out folder")
      ->disable_flag_override();
  score
      ->add_option("--expect", score_expect,
                   "A check such as lamp.ap50>=0.8 or door_plate.recall>=0.5 (repeatable)")
      ->type_name("CLASS.METRIC>=VALUE");
  score->footer(
      "Matches detections to annotations per class (COCO's greedy matching by score; IoU of boxes, "
      "of circles for lamps, pixel distance for corners) and reports labels, detections, "
      "precision and recall at the best-F1 threshold, AP50, AP50:95 (101-point), localisation "
      "error, reading accuracy (plates) and recall by distance, viewing angle and appearance "
      "(docs/datasets.md).\n"
      "Exit codes: 0 success, 3 an --expect check failed, 2 bad input (the file and field are "
      "named), 1 other failures.");

  CLI::App* study = app.add_subcommand(
      "study", "Run a scenario over many seeds (and sweep points) and aggregate the statistics");
  JobOptions study_options(study, "out/study",
                           "Study YAML (a scenario with a `study:` section, docs/studies.md) or a "
                           "plain scenario file",
                           "First seed (run i uses seed + i; default: study.first_seed, else the "
                           "scenario's seed)",
                           "Study folder (resumed when it holds the same study)");
  std::string study_runs, study_jobs, study_shard;
  CLI::Option* study_runs_option =
      study->add_option("--runs", study_runs, "Seeds per sweep point (default: study.runs, 10)")
          ->type_name("N");
  CLI::Option* study_jobs_option =
      study->add_option("--jobs", study_jobs, "Worker processes (default: the number of cores)")
          ->type_name("J");
  CLI::Option* study_shard_option =
      study
          ->add_option("--shard", study_shard,
                       "Run only part K of N (run k of the plan belongs to part k mod N); "
                       "`study merge` combines the parts")
          ->type_name("K/N");
  std::vector<std::string> study_may_diverge;
  study
      ->add_option("--may-diverge", study_may_diverge,
                   "Pipelines whose diverged runs do not fail the study (added to the "
                   "scenario's baseline: true pipelines and study.may_diverge)")
      ->delimiter(',')
      ->type_name("PIPELINE[,PIPELINE]");
  bool study_no_plots = false, study_no_viewer = false;
  study->add_flag("--no-plots", study_no_plots, "Skip plots/ (matplotlib)")
      ->disable_flag_override();
  study
      ->add_flag("--no-viewer", study_no_viewer,
                 "Skip report.html and each run's viewer.html (docs/viewer.md)")
      ->disable_flag_override();
  bool study_slurm = false, study_submit = false;
  std::string study_slurm_tasks, study_task_minutes;
  study
      ->add_flag("--slurm", study_slurm,
                 "Write a Slurm job array (one task per shard) and a merge job into <out>/slurm/ "
                 "instead of running here (one run is run here first to measure the cost)")
      ->disable_flag_override();
  study->add_flag("--submit", study_submit, "With --slurm: submit both jobs with sbatch")
      ->disable_flag_override();
  CLI::Option* study_slurm_tasks_option =
      study
          ->add_option("--slurm-tasks", study_slurm_tasks,
                       "With --slurm: the number of array tasks (default: from the measured cost)")
          ->type_name("N");
  CLI::Option* study_task_minutes_option =
      study
          ->add_option("--slurm-task-minutes", study_task_minutes,
                       "With --slurm: the run time a task packs (default 60)")
          ->type_name("MIN");
  CLI::App* merge = study->add_subcommand(
      "merge", "Combine study folders of one plan (shards) into one study folder and summary");
  std::vector<std::string> merge_dirs;
  merge->add_option("dirs", merge_dirs, "Study folders to combine")->required();
  std::string merge_out = "out/study_merged";
  merge->add_option("--out", merge_out, "The combined study folder")->capture_default_str();
  bool merge_force = false, merge_no_plots = false, merge_no_viewer = false;
  merge->add_flag("--force", merge_force, "Replace a non-empty --out folder written by corridorsim")
      ->disable_flag_override();
  merge->add_flag("--no-plots", merge_no_plots, "Skip plots/ (matplotlib)")
      ->disable_flag_override();
  merge->add_flag("--no-viewer", merge_no_viewer, "Skip report.html (docs/viewer.md)")
      ->disable_flag_override();
  study->footer(
      std::string(
          "Each run is `corridorsim run <point scenario> --seed S --no-plots` in a process of its "
          "own; finished runs are kept (runs/<point>/seed_<S>/, each with its viewer.html) and "
          "skipped when the same study is run again. Writes study.json (the plan), points/, "
          "runs/, status/, logs/, summary.json, summary.csv, paired.csv, report.md, timing.json, "
          "plots/ (docs/studies.md) and report.html (docs/viewer.md).\n") +
      "Exit codes: 0 success; 1 a run failed or timed out, or a pipeline that is neither a "
      "baseline nor in may_diverge diverged (the others are summarised, each one named); 3 a "
      "study expectation failed; 4 only plots/ or report.html failed; 2 bad input (nothing runs), "
      "or `study "
      "merge` folders that lack runs of the plan (nothing is written). Ctrl-C or SIGTERM stops "
      "the runs in flight too; the same command resumes the study.");

  CLI::App* test = app.add_subcommand(
      "test", "Run scenarios and studies as a test suite and write a JUnit XML report");
  std::vector<std::string> test_files;
  test->add_option("files", test_files,
                   "Scenario or study files (default: ./scenarios/default.yaml if it exists, "
                   "else the shipped one)");
  std::string test_out = "out/test", test_junit;
  test->add_option("--out", test_out, "Folder of the runs and studies (one folder per file)")
      ->capture_default_str();
  CLI::Option* test_junit_option =
      test->add_option("--junit", test_junit, "Write the JUnit XML report to this file")
          ->type_name("FILE");
  std::string test_jobs;
  CLI::Option* test_jobs_option =
      test->add_option("--jobs", test_jobs,
                       "Files run at once, each its own `corridorsim run` or `study` (default 1, "
                       "at most 256; a study's runs then share the cores); the report is the "
                       "same for any count but for its `time` attributes")
          ->type_name("J");
  std::vector<std::string> test_settings;
  AddSetOption(test, &test_settings);
  test->footer(
      "Each expectation of a scenario (or each study expectation at each sweep point) is one "
      "test case; a failure gives the measured value and the threshold, system-out the run's "
      "viewer.html (a study's report.html; the folder with --no-viewer) as "
      "[[ATTACHMENT|path]]; a run that cannot finish is an error case with its log's "
      "tail (docs/ci.md).\n"
      "Exit codes: 0 every case passed; 3 an expectation failed; 1 a run or study could not "
      "finish; 2 bad input (nothing runs).");

  CLI::App* evaluate = app.add_subcommand(
      "evaluate", "Score trajectories and landmark maps of any system against a run's truth");
  std::string evaluate_run, evaluate_align = "none", evaluate_max_dt, evaluate_out;
  std::vector<std::string> evaluate_estimates, evaluate_landmarks, evaluate_expect, evaluate_frames;
  bool evaluate_force = false, evaluate_no_plots = false;
  evaluate
      ->add_option("run", evaluate_run,
                   "The run folder (corridorsim run --out): its ground_truth.tum and world.json")
      ->required()
      ->type_name("RUN_DIR");
  evaluate
      ->add_option("--estimate", evaluate_estimates,
                   "A trajectory: TUM (t tx ty tz qx qy qz qw) or OpenVINS ov_eval with "
                   "covariances (20 columns) of world_from_robot (repeatable)")
      ->type_name("NAME=FILE");
  evaluate
      ->add_option("--landmarks", evaluate_landmarks,
                   "A landmark map in <pipeline>_landmarks.json's format, in the frame of the "
                   "estimate of the same NAME (aligned with it) (repeatable)")
      ->type_name("NAME=FILE");
  evaluate
      ->add_option("--frame", evaluate_frames,
                   "The estimate NAME's poses are of this camera's optical frame (world_from_"
                   "camera, as the TUM RGB-D export's groundtruth.txt): scored as world_from_robot "
                   "through the run's mount (default: the robot frame)")
      ->type_name("NAME=CAMERA");
  evaluate
      ->add_option("--align", evaluate_align,
                   "Fit before scoring: none, se2 (yaw + x-y), se3, sim3 (with scale: monocular)")
      ->capture_default_str()
      ->type_name("none|se2|se3|sim3");
  CLI::Option* evaluate_max_dt_option =
      evaluate
          ->add_option("--max-dt", evaluate_max_dt,
                       "Largest stamp difference to a truth pose for a pose to be scored, s "
                       "(default 0.01, as evo's; at most 1)")
          ->type_name("S");
  CLI::Option* evaluate_out_option =
      evaluate->add_option("--out", evaluate_out, "Output folder (default: RUN_DIR/evaluation)")
          ->type_name("DIR");
  evaluate->add_flag("--force", evaluate_force, "Replace a non-empty output folder")
      ->disable_flag_override();
  evaluate
      ->add_option("--expect", evaluate_expect,
                   "A check such as mine.ate_rmse_m<0.2 or mine.map.lamp.rmse_m<=0.1 (repeatable)")
      ->type_name("NAME.METRIC<VALUE");
  evaluate->add_flag("--no-plots", evaluate_no_plots, "Skip plots/ (matplotlib)")
      ->disable_flag_override();
  evaluate->footer(
      "Writes evaluation.json (per NAME: the trajectory metrics of metrics.json after the "
      "alignment, NEES where the file has covariances, map.<type> for --landmarks, align.* and "
      "the evaluation's own metrics), <NAME>_aligned.tum, <NAME>_errors.csv and plots/ "
      "(docs/evaluation.md).\n"
      "Exit codes: 0 success, 3 an --expect check failed, 4 the results are written but plots/ "
      "failed, 2 bad input (the file, line and column, or the flag, are named), 1 other "
      "failures.");

  CLI::App* plugin = app.add_subcommand(
      "plugin", "Load a pipeline plugin library and print what it registers (docs/plugins.md)");
  std::string plugin_file;
  plugin->add_option("library", plugin_file, "The plugin library (a .so file)")
      ->required()
      ->type_name("LIB");
  plugin->footer(
      "Prints the plugin's name, version, the corridorsim version it was built against, its file "
      "and SHA-256, then each pipeline type it registers with its options (key, unit, default, "
      "bounds, meaning) as docs/scenarios.md shows the shipped ones.\n"
      "Exit codes: 0 success; 2 the library cannot be loaded as a plugin (missing, not a regular "
      "file, dlopen's error, no entry point, another SDK ABI, a taken type name).");

  static const char* const kJobs[] = {"world",  "snapshot",        "run",     "drive", "where",
                                      "detect", "train-detectors", "dataset", "score", "study",
                                      "test",   "plugin",          "evaluate"};
  if (!args.empty() && !args[0].empty() && args[0][0] != '-' &&
      std::find(std::begin(kJobs), std::end(kJobs), args[0]) == std::end(kJobs)) {
    Fail("", "unknown subcommand " + Quoted(args[0]) +
                 ": expected world, snapshot, run, drive, where, detect, train-detectors, "
                 "dataset, score, study, test, plugin or evaluate (see corridorsim --help)");
  }
  // CLI11 takes the arguments last first.
  std::vector<std::string> reversed(args.rbegin(), args.rend());
  try {
    app.parse(reversed);
  } catch (const CLI::CallForHelp&) {
    parsed.job = CommandLine::Job::kHelp;
    parsed.help_text = app.help();
    return parsed;
  } catch (const CLI::CallForVersion&) {
    parsed.job = CommandLine::Job::kVersion;
    return parsed;
  } catch (const CLI::CallForAllHelp&) {
    parsed.job = CommandLine::Job::kHelp;
    parsed.help_text = app.help("", CLI::AppFormatMode::All);
    return parsed;
  } catch (const CLI::ParseError& e) {
    Fail("", std::string(e.what()) + " (see corridorsim --help)");
  }

  if (world->parsed()) {
    parsed.job = CommandLine::Job::kWorld;
    world_options.Resolve(&parsed.world);
  } else if (snapshot->parsed()) {
    parsed.job = CommandLine::Job::kSnapshot;
    snapshot_options.Resolve(&parsed.snapshot);
    const PoseArgument pose = ParsePoseArgument(pose_text, "--pose");
    parsed.snapshot.x_m = pose.x_m;
    parsed.snapshot.y_m = pose.y_m;
    parsed.snapshot.yaw_deg = pose.yaw_deg;
  } else if (run->parsed()) {
    parsed.job = CommandLine::Job::kRun;
    run_options.Resolve(&parsed.run);
    if (export_option->count() > 0) {
      if (export_text.empty()) Fail("--export", "an empty folder name");
      parsed.run.export_dir = export_text;
    }
    parsed.run.plots = !no_plots;
    parsed.run.viewer = !no_viewer;
    if (keep_frames_mb_option->count() > 0) {
      const double mb = ParseNumberArgument(keep_frames_mb, 1e6, "--keep-frames-mb");
      if (!(mb >= 1.0 && mb <= 40.0))
        Fail("--keep-frames-mb", "must be in [1, 40] " + Got(keep_frames_mb));
      if (!parsed.run.keep_frames) Fail("--keep-frames-mb", "needs --keep-frames");
      parsed.run.keep_frames_budget_mb = mb;
    }
  } else if (drive->parsed()) {
    parsed.job = CommandLine::Job::kDrive;
    drive_options.Resolve(&parsed.drive);
  } else if (where->parsed()) {
    parsed.job = CommandLine::Job::kWhere;
    parsed.where.room = ParseRoomArgument(where_room, "ROOM");
    if (where_run.empty()) Fail("--run", "an empty folder name");
    parsed.where.run_dir = where_run;
    if (where_pipeline_option->count() > 0) {
      parsed.where.pipeline = ParsePipelineArgument(where_pipeline, "--pipeline");
    }
  } else if (detect->parsed()) {
    parsed.job = CommandLine::Job::kDetect;
    if (detect_image_option->count() > 0 && detect_image.empty()) {
      Fail("image", "an empty file name");
    }
    parsed.detect.image_file = detect_image;
    if (detect_camera == "front") {
      parsed.detect.camera = DetectCamera::kFront;
    } else if (detect_camera == "lateral") {
      parsed.detect.camera = DetectCamera::kLateral;
    } else if (detect_camera == "upward") {
      parsed.detect.camera = DetectCamera::kUpward;
    } else {
      Fail("--camera", "expected front, lateral or upward " + Got(detect_camera));
    }
    if (detect_intrinsics_option->count() > 0) {
      if (detect_intrinsics.empty()) Fail("--intrinsics", "an empty file name");
      if (parsed.detect.camera != DetectCamera::kUpward) {
        Fail("--intrinsics", "only for --camera upward (got --camera " + detect_camera + ")");
      }
      parsed.detect.intrinsics_file = detect_intrinsics;
    }
    if (detect_depth_option->count() > 0) {
      if (detect_depth.empty()) Fail("--depth", "an empty file name");
      if (parsed.detect.camera != DetectCamera::kFront) {
        Fail("--depth",
             "only the front camera has a depth sensor (got --camera " + detect_camera + ")");
      }
      parsed.detect.depth_file = detect_depth;
    }
    if (detect_out_option->count() > 0) {
      if (detect_out.empty()) Fail("--out", "an empty file name");
      parsed.detect.overlay_file = detect_out;
    }
  } else if (train->parsed()) {
    parsed.job = CommandLine::Job::kTrainDetectors;
    TrainDetectorsRequest& r = parsed.train_detectors;
    if (train_out.empty()) Fail("--out", "an empty folder name");
    r.out_dir = train_out;
    if (report_option->count() > 0) {
      if (train_report.empty()) Fail("--report", "an empty folder name");
      r.report_dir = train_report;
    }
    r.force = train_force;
    if (train_seed_option->count() > 0) r.seed = ParseSeedArgument(train_seed, "--seed");
    const auto count = [](const std::string& text, int max, const std::string& flag) {
      // Parsed up to any int, so that the bound named is the count's, not the parser's.
      const double v = ParseNumberArgument(text, std::numeric_limits<int>::max(), flag);
      if (v != std::floor(v) || v < 1 || v > max)
        Fail(flag, "must be a whole number in [1, " + std::to_string(max) + "] " + Got(text));
      return static_cast<int>(v);
    };
    if (train_worlds_option->count() > 0)
      r.train_worlds = count(train_worlds, kMaxTrainWorlds, "--train-worlds");
    if (eval_worlds_option->count() > 0)
      r.eval_worlds = count(eval_worlds, kMaxTrainWorlds, "--eval-worlds");
    if (views_option->count() > 0) r.views_per_world = count(views, kMaxViewsPerWorld, "--views");
    const auto folder = [](const std::string& text, const char* flag) {
      if (text.empty()) Fail(flag, "an empty folder name");
      return std::filesystem::path(text);
    };
    if (train_dataset_option->count() > 0) {
      r.train_dataset = folder(train_dataset, "--dataset");
      if (train_worlds_option->count() > 0)
        Fail("--train-worlds", "the --dataset folder decides the training worlds");
    }
    if (eval_dataset_option->count() > 0) {
      r.eval_dataset = folder(eval_dataset, "--eval-dataset");
      if (eval_worlds_option->count() > 0)
        Fail("--eval-worlds", "the --eval-dataset folder decides the evaluation worlds");
    }
    if (r.train_dataset && r.eval_dataset && views_option->count() > 0)
      Fail("--views", "both sets are dataset folders, whose frames decide the views");
  } else if (dataset->parsed()) {
    parsed.job = CommandLine::Job::kDataset;
    DatasetRequest& r = parsed.dataset;
    dataset_options.Resolve(&r);
    const auto count = [](const std::string& text, int max, const std::string& flag) {
      // Parsed up to any int, so that the bound named is the count's, not the parser's.
      const double v = ParseNumberArgument(text, std::numeric_limits<int>::max(), flag);
      if (v != std::floor(v) || v < 1 || v > max)
        Fail(flag, "must be a whole number in [1, " + std::to_string(max) + "] " + Got(text));
      return static_cast<int>(v);
    };
    r.worlds = count(dataset_worlds, kMaxDatasetWorlds, "--worlds");
    r.frames_per_world = count(dataset_frames, kMaxDatasetFramesPerWorld, "--frames-per-world");
    if (dataset_cameras_option->count() > 0) {
      std::size_t start = 0;
      for (;;) {
        const std::size_t comma = dataset_cameras.find(',', start);
        const std::string id = dataset_cameras.substr(
            start, comma == std::string::npos ? std::string::npos : comma - start);
        if (id.empty()) Fail("--cameras", "an empty camera name " + Got(dataset_cameras));
        r.cameras.push_back(id);
        if (comma == std::string::npos) break;
        start = comma + 1;
      }
    }
    if (dataset_poses == "random") {
      r.poses = DatasetPoseMode::kRandom;
    } else if (dataset_poses == "path") {
      r.poses = DatasetPoseMode::kPath;
    } else if (dataset_poses == "plates") {
      r.poses = DatasetPoseMode::kPlates;
    } else {
      Fail("--poses", "expected path, random or plates " + Got(dataset_poses));
    }
  } else if (score->parsed()) {
    parsed.job = CommandLine::Job::kScore;
    ScoreRequest& r = parsed.score;
    if (score_detections.empty()) Fail("detections", "an empty file name");
    if (score_dataset.empty()) Fail("--dataset", "an empty folder name");
    r.detections_file = score_detections;
    r.dataset_dir = score_dataset;
    if (score_camera_option->count() > 0) {
      if (score_camera.empty()) Fail("--camera", "an empty camera name");
      r.camera = score_camera;
    }
    if (score_out_option->count() > 0) {
      if (score_out.empty()) Fail("--out", "an empty folder name");
      r.report_dir = score_out;
    }
    r.force = score_force;
    for (const std::string& e : score_expect) {
      r.expectations.push_back(ParseScoreExpectation(e, "--expect"));
    }
  } else if (test->parsed()) {
    parsed.job = CommandLine::Job::kTest;
    TestRequest& r = parsed.test;
    if (test_files.size() > static_cast<std::size_t>(kMaxSuiteFiles)) {
      Fail("files", "at most " + std::to_string(kMaxSuiteFiles) + " files");
    }
    for (const std::string& f : test_files) {
      if (f.empty()) Fail("files", "an empty file name");
    }
    r.files = test_files;
    if (test_out.empty()) Fail("--out", "an empty folder name");
    r.out_dir = test_out;
    if (test_junit_option->count() > 0) {
      if (test_junit.empty()) Fail("--junit", "an empty file name");
      r.junit_file = test_junit;
    }
    if (test_jobs_option->count() > 0) r.jobs = WholeArgument(test_jobs, kMaxSuiteJobs, "--jobs");
    ParseSettings(test_settings);
    r.settings = test_settings;
  } else if (merge->parsed()) {
    parsed.job = CommandLine::Job::kStudyMerge;
    StudyRequest& r = parsed.study;
    if (merge_out.empty()) Fail("--out", "an empty folder name");
    if (merge_dirs.size() > static_cast<std::size_t>(kMaxShards)) {
      Fail("dirs", "at most " + std::to_string(kMaxShards) + " folders");
    }
    for (const std::string& d : merge_dirs) {
      if (d.empty()) Fail("dirs", "an empty folder name");
      r.merge_dirs.emplace_back(d);
    }
    r.out_dir = merge_out;
    r.force = merge_force;
    r.plots = !merge_no_plots;
    r.viewer = !merge_no_viewer;
  } else if (study->parsed()) {
    parsed.job = CommandLine::Job::kStudy;
    StudyRequest& r = parsed.study;
    study_options.Resolve(&r);
    const auto whole = WholeArgument;
    if (study_runs_option->count() > 0) r.runs = whole(study_runs, kMaxStudyRuns, "--runs");
    if (study_jobs_option->count() > 0) r.jobs = whole(study_jobs, kMaxStudyJobs, "--jobs");
    if (study_shard_option->count() > 0) {
      const std::size_t slash = study_shard.find('/');
      if (slash == std::string::npos) Fail("--shard", "expected K/N, e.g. 2/8 " + Got(study_shard));
      const int k = whole(study_shard.substr(0, slash), kMaxShards, "--shard");
      const int n = whole(study_shard.substr(slash + 1), kMaxShards, "--shard");
      if (k > n) Fail("--shard", "K must lie in [1, N] " + Got(study_shard));
      r.shard_index = k - 1;
      r.shard_count = n;
    }
    r.plots = !study_no_plots;
    r.viewer = !study_no_viewer;
    if (study_may_diverge.size() > 64) Fail("--may-diverge", "at most 64 pipelines");
    r.may_diverge = study_may_diverge;
    r.slurm = study_slurm;
    r.submit = study_submit;
    if (study_submit && !study_slurm) Fail("--submit", "only with --slurm");
    if (study_slurm_tasks_option->count() > 0) {
      if (!study_slurm) Fail("--slurm-tasks", "only with --slurm");
      r.slurm_tasks = whole(study_slurm_tasks, kMaxSlurmTasks, "--slurm-tasks");
    }
    if (study_task_minutes_option->count() > 0) {
      if (!study_slurm) Fail("--slurm-task-minutes", "only with --slurm");
      r.slurm_task_minutes = whole(study_task_minutes, 100000, "--slurm-task-minutes");
    }
    if (study_slurm && study_shard_option->count() > 0) {
      Fail("--shard", "--slurm writes the shards itself");
    }
  } else if (evaluate->parsed()) {
    parsed.job = CommandLine::Job::kEvaluate;
    EvaluateRequest& r = parsed.evaluate;
    if (evaluate_run.empty()) Fail("RUN_DIR", "an empty folder name");
    r.run_dir = evaluate_run;
    if (evaluate_estimates.empty() && evaluate_landmarks.empty()) {
      Fail("--estimate", "nothing to evaluate: give --estimate NAME=FILE or --landmarks NAME=FILE");
    }
    const auto named = [](const std::vector<std::string>& texts, const std::string& flag) {
      if (texts.size() > kMaxEvaluatedFiles) {
        Fail(flag, "at most " + std::to_string(kMaxEvaluatedFiles) + " files");
      }
      std::vector<EvaluateRequest::NamedFile> files;
      for (const std::string& text : texts) {
        const std::size_t eq = text.find('=');
        if (eq == std::string::npos) Fail(flag, "expected NAME=FILE " + Got(text));
        EvaluateRequest::NamedFile f{ParsePipelineArgument(text.substr(0, eq), flag),
                                     text.substr(eq + 1)};
        if (f.file.empty()) Fail(flag, "an empty file name " + Got(text));
        for (const auto& other : files) {
          if (other.name == f.name) Fail(flag, "the name '" + f.name + "' is given twice");
        }
        files.push_back(std::move(f));
      }
      return files;
    };
    r.estimates = named(evaluate_estimates, "--estimate");
    r.landmarks = named(evaluate_landmarks, "--landmarks");
    for (const EvaluateRequest::NamedFile& f : named(evaluate_frames, "--frame")) {
      const bool estimated = std::any_of(r.estimates.begin(), r.estimates.end(),
                                         [&](const auto& e) { return e.name == f.name; });
      if (!estimated) Fail("--frame", "'" + f.name + "' is no --estimate name");
      r.frames.push_back({f.name, ParsePipelineArgument(f.file.string(), "--frame")});
    }
    const std::optional<evaluate::Alignment> alignment =
        evaluate::AlignmentFromName(evaluate_align);
    if (!alignment) Fail("--align", "expected none, se2, se3 or sim3 " + Got(evaluate_align));
    r.alignment = *alignment;
    if (evaluate_max_dt_option->count() > 0) {
      r.max_dt_s = ParseNumberArgument(evaluate_max_dt, kMaxAssociationSeconds, "--max-dt");
      if (r.max_dt_s < 0.0) Fail("--max-dt", "must not be negative " + Got(evaluate_max_dt));
    }
    if (evaluate_out_option->count() > 0) {
      if (evaluate_out.empty()) Fail("--out", "an empty folder name");
      r.out_dir = evaluate_out;
    }
    r.force = evaluate_force;
    r.plots = !evaluate_no_plots;
    if (evaluate_expect.size() > 256) Fail("--expect", "at most 256 checks");
    r.expectations = evaluate_expect;
  } else if (plugin->parsed()) {
    parsed.job = CommandLine::Job::kPlugin;
    if (plugin_file.empty()) Fail("library", "an empty file name");
    parsed.plugin_file = plugin_file;
  } else {
    Fail("",
         "a subcommand is required: world, snapshot, run, drive, where, detect, train-detectors, "
         "dataset, score, study, test, plugin or evaluate (see corridorsim --help)");
  }
  return parsed;
}

}  // namespace corridorsim

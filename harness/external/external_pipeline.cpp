#include "harness/external/external_pipeline.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <utility>

#include "common/installation.h"
#include "common/io/atomic_file.h"
#include "common/io/child_process.h"
#include "common/io/options_yaml.h"
#include "common/io/sha256.h"
#include "common/io/stable_json.h"
#include "common/io/yaml_reader.h"
#include "harness/external/protocol.h"

namespace corridorsim::external {
namespace {

namespace fs = std::filesystem;

// Lines and bytes of the program's output a failure's reason quotes.
constexpr std::size_t kReasonLogLines = 12;
constexpr std::size_t kReasonLogBytes = 1200;
// How long a program has to exit once its connection closed after `finished`.
constexpr double kExitGraceSeconds = 10.0;

std::string FlowList(const std::vector<std::string>& items) {
  std::string list;
  for (const std::string& item : items) list += (list.empty() ? "" : ", ") + YamlString(item);
  return "[" + list + "]";
}

// `path` without "." and ".." parts or a trailing '/'.
fs::path Normal(const fs::path& path) {
  fs::path normal = path.lexically_normal();
  if (normal.filename().empty() && normal.has_parent_path()) normal = normal.parent_path();
  return normal;
}

// The folder of the file that set `key` of `map`.
fs::path FolderOf(YamlMap& map, const std::string& key) {
  fs::path file = map.LocationOfKey(key).file;
  fs::path folder = file.parent_path();
  if (folder.empty()) folder = ".";
  return Normal(fs::absolute(folder));
}

void ParseCommand(YamlMap& map, ExternalPipelineOptions& o) {
  std::vector<std::string> command;
  std::vector<SourceLocation> locations;
  if (map.Read("command", command, &locations)) {
    if (command.empty()) map.Fail("command", "needs the program, e.g. [python3, my_slam.py]");
    if (command.size() > kMaxCommandArgs) {
      map.Fail("command", "at most " + std::to_string(kMaxCommandArgs) + " arguments");
    }
    for (std::size_t i = 0; i < command.size(); ++i) {
      if (command[i].size() > kMaxArgumentBytes || command[i].find('\0') != std::string::npos) {
        throw InputError(
            locations[i], map.FullKey("command"),
            "an argument is at most " + std::to_string(kMaxArgumentBytes) + " bytes, without NUL");
      }
    }
    if (command[0].empty()) map.Fail("command", "the program's name is empty");
    // A program path is relative to the file that names it, like `include:` and `plugins:`.
    if (command[0].find('/') != std::string::npos && fs::path(command[0]).is_relative()) {
      command[0] = Normal(FolderOf(map, "command") / command[0]).string();
    }
    o.command = std::move(command);
    if (o.working_dir.empty()) o.working_dir = FolderOf(map, "command").string();
  }
  std::string working_dir;
  if (map.Read("working_dir", working_dir)) {
    if (working_dir.empty()) map.Fail("working_dir", "must not be empty");
    fs::path dir = working_dir;
    if (dir.is_relative()) dir = FolderOf(map, "working_dir") / dir;
    o.working_dir = Normal(dir).string();
  }
}

void EchoCommand(const ExternalPipelineOptions& o, OptionsYamlWriter& out) {
  out.Scalar("command", FlowList(o.command));
  if (!o.working_dir.empty()) out.Scalar("working_dir", YamlString(o.working_dir));
}

std::vector<OptionDocRow> CommandDocRows(const ExternalPipelineOptions&) {
  return {{"command", "", "(required)", "1 to 256 arguments",
           "the program and its arguments, never through a shell; a program path with a '/' is "
           "relative to the file that names it, one without is searched on PATH"},
          {"working_dir", "", "the file's folder", "",
           "the folder the program runs in, relative to the file that names it"}};
}

void ParsePassThrough(YamlMap& map, ExternalPipelineOptions& o) {
  nlohmann::ordered_json options;
  if (!map.ReadJson("options", options)) return;
  if (!options.is_object()) map.Fail("options", "expected a map of the program's options");
  o.options = std::move(options);
}

void EchoPassThrough(const ExternalPipelineOptions& o, OptionsYamlWriter& out) {
  out.Scalar("options", JsonText(o.options));  // JSON is YAML's flow style: typed as it was read
}

std::vector<OptionDocRow> PassThroughDocRows(const ExternalPipelineOptions&) {
  return {{"options", "", "`{}`", "",
           "the program's own options, any map: passed in the start message as given, typed"}};
}

}  // namespace

const OptionTable<ExternalPipelineOptions>& ExternalPipelineOptionsTable() {
  return StaticOptionTable<ExternalPipelineOptions>([](OptionTable<ExternalPipelineOptions>& t) {
    using O = ExternalPipelineOptions;
    t.AddCustom("command", "the program (docs/protocol.md)", &ParseCommand, &EchoCommand,
                &CommandDocRows);
    t.AddCustom(
        "cameras", "the cameras it reads",
        [](YamlMap& map, O& o) {
          std::vector<std::string> cameras;
          if (!map.Read("cameras", cameras)) return;
          if (cameras.size() > 16) map.Fail("cameras", "at most 16 cameras");
          for (std::size_t i = 0; i < cameras.size(); ++i) {
            for (std::size_t k = 0; k < i; ++k) {
              if (cameras[k] == cameras[i]) map.Fail("cameras", "'" + cameras[i] + "' twice");
            }
          }
          o.cameras = std::move(cameras);
        },
        [](const O& o, OptionsYamlWriter& out) { out.Scalar("cameras", FlowList(o.cameras)); },
        [](const O&) {
          return std::vector<OptionDocRow>{
              {"cameras", "", "`[]`", "front, lateral, upward",
               "the cameras it reads: their frames come in camera sets, and only cameras somebody "
               "reads are rendered"}};
        });
    t.Add("timeout_s", &O::timeout_s, "s",
          "the longest wait for one reply (or for the program to read a message); past it the "
          "pipeline fails")
        .RangeOpenLow(0, kMaxTimeoutSeconds);
    t.AddEnum(
        "transport", &O::transport,
        {{"shared_memory", ImageTransport::kSharedMemory}, {"inline", ImageTransport::kInline}},
        "how images travel: a shared memory passed once at start, or in each message");
    t.AddCustom("options", "the program's options", &ParsePassThrough, &EchoPassThrough,
                &PassThroughDocRows);
  });
}

std::optional<OptionsProblem> ExternalPipelineOptions::Check() const {
  if (auto problem = CheckOptionBounds(ExternalPipelineOptionsTable(), *this)) return problem;
  if (command.empty()) {
    return OptionsProblem{"command",
                          "an external pipeline needs its program, e.g. command: "
                          "[python3, my_slam.py]"};
  }
  return std::nullopt;
}

slam::PipelineType ExternalPipelineType() {
  slam::PipelineType type = slam::MakePipelineType<ExternalPipelineOptions, ExternalPipeline>(
      "external", &ExternalPipelineOptionsTable);
  return type;
}

nlohmann::ordered_json ProgramFingerprint(const ExternalPipelineOptions& options) {
  nlohmann::ordered_json files = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < options.command.size(); ++i) {
    const std::string& argument = options.command[i];
    if (argument.empty()) continue;
    fs::path path;
    if (i == 0) {
      std::string error;
      path = ResolveProgram(argument, &error);
      if (path.empty()) continue;
    } else {
      path = argument;
    }
    if (path.is_relative()) path = fs::path(options.working_dir) / path;
    std::error_code error;
    if (!fs::is_regular_file(path, error)) continue;
    nlohmann::ordered_json file = {{"argument", i}, {"path", Normal(path).string()}};
    try {
      file["sha256"] = Sha256Hex(ReadRegularFile(path, kMaxFingerprintBytes));
    } catch (const std::exception&) {
      file["sha256"] = nullptr;  // too large, or unreadable
    }
    files.push_back(std::move(file));
  }
  return {{"command", options.command},
          {"working_dir", options.working_dir},
          {"files", std::move(files)}};
}

void RegisterExternalPipelineType() {
  static std::once_flag once;
  std::call_once(once, [] {
    if (!slam::FindPipelineType("external")) slam::AddPipelineType(ExternalPipelineType());
  });
}

// ---- The pipeline --------------------------------------------------------------------------

ExternalPipeline::ExternalPipeline(const ExternalPipelineOptions& options,
                                   const slam::Calibration& calibration, std::uint64_t seed)
    : options_(options), calibration_(calibration), seed_(seed) {
  if (options_.command.empty()) throw StartError("no command");
  // The environment it gets (docs/protocol.md): this process's, the descriptor of the
  // connection, and the installed Python client on PYTHONPATH.
  std::vector<std::pair<std::string, std::string>> env = {
      {"CORRIDORSIM_PROTOCOL_FD", "3"},
      {"CORRIDORSIM_PROTOCOL_VERSION", std::to_string(kProtocolVersion)}};
  if (const std::string python_path = PythonPathWithPackage(); !python_path.empty()) {
    env.emplace_back("PYTHONPATH", python_path);
  }
  connection_ = std::make_unique<ProgramConnection>(options_.command, options_.working_dir, env);
}

ExternalPipeline::~ExternalPipeline() {
  if (memory_) ::munmap(memory_, memory_bytes_);
  if (memory_fd_ >= 0) ::close(memory_fd_);
}

std::chrono::duration<double> ExternalPipeline::timeout() const {
  return std::chrono::duration<double>(options_.timeout_s);
}

void ExternalPipeline::FailWith(const std::string& what) {
  ended_ = true;
  connection_->Kill();
  usage_ = {connection_->program_cpu_seconds(), connection_->program_peak_rss_mib()};
  std::string reason = what;
  const std::string tail = connection_->LogTail(kReasonLogLines, kReasonLogBytes);
  if (!tail.empty()) reason += "; its last output: " + tail;
  log_ = connection_->Log();
  throw std::runtime_error(reason);
}

Received ExternalPipeline::Exchange(const nlohmann::ordered_json& message, std::string_view blob,
                                    int fd) {
  if (ended_) throw std::logic_error("the program has ended");
  try {
    const auto t0 = std::chrono::steady_clock::now();
    connection_->Send(message, blob, fd, timeout());
    Received reply = connection_->Receive(timeout());
    times_.Add(MessageType(message),
               std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    return reply;
  } catch (const ConnectionError& e) {
    FailWith("'" + MessageType(message) + "' message: " + e.what());
  }
}

void ExternalPipeline::Initialize(TimeNs stamp_ns, const SE2& world_from_robot) {
  estimate_.stamp_ns = stamp_ns;
  estimate_.world_from_robot = world_from_robot;
  estimate_.covariance.setZero();
  // The images of one camera set: each camera's colour, then its depth, in `cameras` order.
  for (const std::string& id : options_.cameras) {
    const slam::CameraCalibration* camera = calibration_.Find(id);
    if (!camera) continue;  // the runner refuses this before the run
    image_offsets_[id] = set_bytes_;
    const std::size_t pixels = static_cast<std::size_t>(camera->model.width()) *
                               static_cast<std::size_t>(camera->model.height());
    set_bytes_ += pixels * 3 + (camera->depth ? pixels * sizeof(float) : 0);
  }
  const std::size_t bytes = set_bytes_;
  int pass_fd = -1;
  if (options_.transport == ImageTransport::kSharedMemory && bytes > 0) {
    memory_fd_ = ::memfd_create("corridorsim-frames", MFD_CLOEXEC | MFD_ALLOW_SEALING);
    if (memory_fd_ < 0 || ::ftruncate(memory_fd_, static_cast<off_t>(bytes)) != 0 ||
        // Its size is sealed: a program cannot shrink it under this side's writes (SIGBUS).
        ::fcntl(memory_fd_, F_ADD_SEALS, F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_SEAL) != 0) {
      throw std::runtime_error(std::string("shared memory: ") + std::strerror(errno));
    }
    void* mapped = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, memory_fd_, 0);
    if (mapped == MAP_FAILED) {
      throw std::runtime_error(std::string("shared memory: mmap: ") + std::strerror(errno));
    }
    memory_ = static_cast<std::uint8_t*>(mapped);
    memory_bytes_ = bytes;
    // The program gets a read-only descriptor of it: it reads the frames, never writes them.
    pass_fd = ::open(("/proc/self/fd/" + std::to_string(memory_fd_)).c_str(), O_RDONLY | O_CLOEXEC);
    if (pass_fd < 0) {
      throw std::runtime_error(std::string("shared memory: a read-only descriptor: ") +
                               std::strerror(errno));
    }
  }
  const nlohmann::ordered_json start =
      StartMessage(name_, calibration_, options_.cameras, stamp_ns, world_from_robot,
                   options_.options, seed_, memory_bytes_);
  Received reply;
  try {
    reply = Exchange(start, {}, pass_fd);
  } catch (...) {
    if (pass_fd >= 0) ::close(pass_fd);
    throw;
  }
  if (pass_fd >= 0) ::close(pass_fd);
  ReplyProblems problems;
  try {
    ready_ = ParseReady(reply.json, &problems, Offered(calibration_));
  } catch (const ProtocolError& e) {
    FailWith(std::string("'start' message: ") + e.what());
  }
  Keep("start", problems);
}

void ExternalPipeline::Keep(const char* message, const ReplyProblems& problems) {
  for (const std::string& w : problems.warnings) {
    warnings_.push_back("'" + std::string(message) + "' message: " + w);
  }
  if (!problems.errors.empty()) {
    FailWith("'" + std::string(message) + "' message: " + JoinProblems(problems.errors));
  }
}

void ExternalPipeline::OnOdometry(const WheelOdometry& odometry) {
  FlushImu();  // the samples before this message, in bus order
  const Received reply = Exchange(OdometryMessage(odometry), {});
  ReplyProblems problems;
  try {
    ReplyExtras extras;
    // What arrived is kept before an unknown key fails the pipeline (the runner records the
    // estimate of a failed call when its stamp is the message's).
    estimate_ =
        ParseEstimate(reply.json, odometry.stamp_ns, &extras, &problems, ready_.measurement_types);
    for (slam::Innovation& n : extras.innovations) innovations_.push_back(n);
  } catch (const ProtocolError& e) {
    FailWith(std::string("'odometry' message: ") + e.what());
  }
  Keep("odometry", problems);
}

void ExternalPipeline::OnCamera(const slam::CameraInput& input) {
  OnCameraSet(input.image.stamp_ns, {SetFrame{input.image.camera_id, &input}});
}

void ExternalPipeline::OnCameraSet(TimeNs stamp_ns, const std::vector<SetFrame>& frames) {
  FlushImu();
  std::vector<CameraSlice> slices;
  std::string blob;
  if (!memory_) blob.reserve(set_bytes_);
  std::vector<std::string> delivered;
  for (const SetFrame& frame : frames) {
    CameraSlice slice;
    slice.camera = frame.camera_id;
    if (!frame.input) {
      slice.dropped = true;
      slices.push_back(std::move(slice));
      continue;
    }
    const slam::CameraInput& input = *frame.input;
    slice.stamp_ns = input.image.stamp_ns;
    delivered.push_back(frame.camera_id);
    const auto it = image_offsets_.find(frame.camera_id);
    const slam::CameraCalibration* c = calibration_.Find(frame.camera_id);
    const Image8& rgb = input.image.image;
    if (it == image_offsets_.end() || !c || rgb.channels != 3 || rgb.width != c->model.width() ||
        rgb.height != c->model.height()) {
      throw std::logic_error("camera set: a frame of '" + frame.camera_id +
                             "' that its calibration does not describe");
    }
    std::size_t at = it->second;
    const auto place = [&](const std::string& encoding, int width, int height, const void* data,
                           std::size_t bytes) {
      ImageSlice image{encoding, width, height, 0, bytes};
      if (memory_) {
        std::memcpy(memory_ + at, data, bytes);
        image.offset = at;
      } else {
        image.offset = blob.size();
        blob.append(static_cast<const char*>(data), bytes);
      }
      at += bytes;
      return image;
    };
    slice.rgb = place("rgb8", rgb.width, rgb.height, rgb.data.data(), rgb.data.size());
    if (c->depth && input.depth) {
      const ImageF& depth = input.depth->depth_m;
      if (depth.width != rgb.width || depth.height != rgb.height) {
        throw std::logic_error("camera set: a depth image of '" + frame.camera_id +
                               "' not of its colour image's size");
      }
      slice.depth = place("depth_f32", depth.width, depth.height, depth.data.data(),
                          depth.data.size() * sizeof(float));
    }
    slices.push_back(std::move(slice));
  }
  const nlohmann::ordered_json message =
      CamerasMessage(stamp_ns, slices, memory_ ? "shared_memory" : "inline");
  KeepProcessed("cameras", Exchange(message, blob), stamp_ns, delivered);
}

void ExternalPipeline::KeepProcessed(const char* message, const Received& reply, TimeNs stamp_ns,
                                     const std::vector<std::string>& cameras) {
  ReplyProblems problems;
  try {
    ReplyExtras extras;
    ParseProcessed(reply.json, stamp_ns, cameras, &extras, &problems, ready_.measurement_types);
    for (slam::Detection& d : extras.detections) detections_.push_back(std::move(d));
    for (slam::Innovation& n : extras.innovations) innovations_.push_back(n);
  } catch (const ProtocolError& e) {
    FailWith("'" + std::string(message) + "' message: " + e.what());
  }
  Keep(message, problems);
}

void ExternalPipeline::OnImu(const ImuSample& sample) {
  const std::vector<std::string>& wanted = ready_.imus;
  if (std::find(wanted.begin(), wanted.end(), sample.sensor_id) == wanted.end()) return;
  imu_batch_.push_back(sample);
  if (imu_batch_.size() >= kMaxImuBatch) FlushImu();
}

void ExternalPipeline::FlushImu() {
  if (imu_batch_.empty()) return;
  const std::vector<ImuSample> batch = std::move(imu_batch_);
  imu_batch_.clear();
  KeepProcessed("imu", Exchange(ImuMessage(batch), {}), batch.back().stamp_ns, {});
}

void ExternalPipeline::OnScan(const LaserScan& scan) {
  const std::vector<std::string>& wanted = ready_.lasers;
  if (std::find(wanted.begin(), wanted.end(), scan.sensor_id) == wanted.end()) return;
  FlushImu();
  // The ranges ride in the blob (float32: REP 117's +-inf and NaN, which JSON lacks).
  KeepProcessed("scan", Exchange(ScanMessage(scan, 0), ScanBlob(scan)), scan.stamp_ns, {});
}

std::vector<slam::Detection> ExternalPipeline::TakeDetections() {
  std::vector<slam::Detection> out = std::move(detections_);
  detections_.clear();
  return out;
}

std::vector<slam::Innovation> ExternalPipeline::TakeInnovations() {
  std::vector<slam::Innovation> out = std::move(innovations_);
  innovations_.clear();
  return out;
}

void ExternalPipeline::Finish() {
  FlushImu();
  const Received reply = Exchange(FinishMessage(estimate_.stamp_ns), {});
  ReplyProblems problems;
  try {
    // Each part of the reply on its own: a bad or misspelt one costs only itself, and what the
    // others hold is kept (the runner records it for a failed pipeline too).
    Finished finished = ParseFinished(reply.json, reply.blob, estimate_.stamp_ns, options_.cameras,
                                      &problems, ready_.measurement_types);
    landmarks_ = std::move(finished.landmarks);
    for (slam::Detection& d : finished.extras.detections) detections_.push_back(std::move(d));
    for (slam::Innovation& n : finished.extras.innovations) innovations_.push_back(n);
    maps_ = std::move(finished.maps);
    health_ = finished.health;
    stage_seconds_ = std::move(finished.stage_seconds);
  } catch (const ProtocolError& e) {
    FailWith(std::string("'finish' message: ") + e.what());
  }
  Keep("finish", problems);
  // The connection closes; the program ends on its own, successfully.
  ended_ = true;
  const std::optional<ChildStatus> status =
      connection_->Close(std::chrono::duration<double>(kExitGraceSeconds));
  usage_ = {connection_->program_cpu_seconds(), connection_->program_peak_rss_mib()};
  log_ = connection_->Log();
  if (!status) {
    throw std::runtime_error("the program did not exit within " +
                             std::to_string(static_cast<int>(kExitGraceSeconds)) +
                             " s of its connection closing (killed)");
  }
  if (!status->succeeded()) {
    std::string reason = "after 'finished', the program " + DescribeChildStatus(*status);
    const std::string tail = connection_->LogTail(kReasonLogLines, kReasonLogBytes);
    if (!tail.empty()) reason += "; its last output: " + tail;
    throw std::runtime_error(reason);
  }
}

std::string ExternalPipeline::TakeLog() {
  if (!ended_) {
    ended_ = true;
    connection_->Kill();
    usage_ = {connection_->program_cpu_seconds(), connection_->program_peak_rss_mib()};
    log_ = connection_->Log();
  }
  return std::move(log_);
}

std::vector<std::string> ExternalPipeline::TakeWarnings() {
  std::vector<std::string> out = std::move(warnings_);
  warnings_.clear();
  return out;
}

nlohmann::ordered_json ExternalPipeline::ProtocolTiming(double corridorsim_cpu_seconds) const {
  double reported = 0.0;
  for (const auto& [stage, seconds] : stage_seconds_) reported += seconds;
  return ProtocolTimingJson(times_, usage_, reported, !stage_seconds_.empty(),
                            corridorsim_cpu_seconds);
}

}  // namespace corridorsim::external

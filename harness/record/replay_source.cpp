#include "harness/record/replay_source.h"

#include <algorithm>
#include <optional>
#include <sstream>

#include "common/error.h"
#include "harness/record/ros_convert.h"
#include "harness/record/topics.h"
#include "render/frame_truth.h"

namespace corridorsim::record {
namespace {

InputError RecordingInputError(const std::filesystem::path& file, const std::string& key,
                               const std::string& what) {
  return InputError(SourceLocation{file.string(), 0, 0}, key, what);
}

// "<file>: <record> at byte <offset>: <what>" as one InputError: the record and offset as its key.
InputError RecordingInputError(const std::filesystem::path& file, const mcap::RecordingError& e) {
  const std::string key = e.record() + " at byte " + std::to_string(e.offset());
  std::string what = e.what();
  const std::string prefix = file.string() + ": " + key + ": ";
  if (what.rfind(prefix, 0) == 0) what = what.substr(prefix.size());
  return RecordingInputError(file, key, what);
}

std::vector<std::string> SplitCommas(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

// What a topic is to replay.
enum class Kind {
  kTruth,
  kWheel,
  kEvent,
  kCameraSet,
  kImage,
  kDepth,
  kDepthTruth,
  kInstance,
  kSemantic,
  kFrame,
  kImu,
  kImuTruth,
  kScan,
  kScanTruth
};
struct Route {
  Kind kind;
  std::size_t sensor = 0;  // camera, IMU or scanner index
};

// One camera's frame being put together from its topics until the camera set arrives.
struct PendingFrame {
  std::optional<sim::CameraMessage> message;
  bool has_image = false, has_frame = false;
};

}  // namespace

ReplaySource::ReplaySource(const std::filesystem::path& file) : file_(file) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(file, error)) {
    throw RecordingInputError(file, "RECORDING", "no such recording (a file)");
  }
  try {
    reader_ = std::make_unique<mcap::Reader>(file);
  } catch (const mcap::RecordingError& e) {
    throw RecordingInputError(file, e);
  } catch (const std::runtime_error& e) {
    throw RecordingInputError(file, "RECORDING", e.what());
  }
  const std::map<std::string, std::string>* meta = nullptr;
  const std::map<std::string, std::string>* provenance = nullptr;
  for (const auto& [name, values] : reader_->metadata()) {
    if (name == "corridorsim" && !meta) meta = &values;
    if (name == "provenance" && !provenance) provenance = &values;
  }
  if (!meta || !reader_->FindChannel(kTruthTopic)) {
    throw RecordingInputError(
        file, "RECORDING",
        "not a corridorsim recording (no 'corridorsim' metadata or no " + std::string(kTruthTopic) +
            " topic): replay scores against the truth corridorsim records; score another "
            "system's run with `corridorsim evaluate` (docs/evaluation.md)");
  }
  const auto get = [&](const std::string& key) {
    const auto it = meta->find(key);
    return it == meta->end() ? std::string() : it->second;
  };
  if (get("format") != "1") {
    throw RecordingInputError(file, "corridorsim.format",
                              "recording format '" + get("format") + "', this build reads 1");
  }
  info_.scenario_file = get("scenario_file");
  info_.topics = get("topics");
  info_.cameras = SplitCommas(get("cameras"));
  try {
    info_.seed = std::stoull(get("seed"));
  } catch (const std::exception&) {
    throw RecordingInputError(file, "corridorsim.seed", "not a seed: '" + get("seed") + "'");
  }
  if (provenance && provenance->count("json")) info_.provenance_json = provenance->at("json");
  const std::optional<mcap::Attachment> yaml = reader_->ReadAttachment("scenario.yaml");
  if (!yaml) throw RecordingInputError(file, "scenario.yaml", "the recording has no scenario");
  info_.scenario_yaml.assign(yaml->data.begin(), yaml->data.end());
}

ReplaySource::~ReplaySource() = default;

bool ReplaySource::truncated() const { return reader_->truncated(); }

void ReplaySource::Require(const std::set<std::string>& cameras,
                           const std::vector<std::string>& imus,
                           const std::vector<std::string>& lasers) const {
  const auto need = [&](const std::string& what, const std::string& topic) {
    if (!reader_->FindChannel(topic)) {
      throw RecordingInputError(
          file_, topic,
          "the pipelines read " + what + " and the recording lacks its topic " + topic +
              (info_.topics.empty() ? ""
                                    : " (recorded with --record-topics " + info_.topics + ")"));
    }
  };
  for (const std::string& camera : cameras) {
    if (std::find(info_.cameras.begin(), info_.cameras.end(), camera) == info_.cameras.end()) {
      std::string recorded;
      for (const std::string& c : info_.cameras) recorded += (recorded.empty() ? "" : ", ") + c;
      throw RecordingInputError(file_, "sensors." + camera,
                                "the pipelines read camera '" + camera +
                                    "' and the recording has no frames of it (it recorded: " +
                                    (recorded.empty() ? "no camera" : recorded) + ")");
    }
    need("camera '" + camera + "'", SensorTopic(camera, "image_raw"));
    need("camera '" + camera + "'", SensorTruthTopic(camera, "frame"));
  }
  for (const std::string& imu : imus) {
    need("IMU '" + imu + "'", SensorTopic(imu, "imu"));
    need("IMU '" + imu + "'", SensorTruthTopic(imu, "truth"));
  }
  for (const std::string& laser : lasers) {
    need("scanner '" + laser + "'", SensorTopic(laser, "scan"));
    need("scanner '" + laser + "'", SensorTruthTopic(laser, "truth"));
  }
  need("the wheel odometry", kWheelTopic);
  if (!cameras.empty()) need("camera sets", kCameraSetTopic);
}

void ReplaySource::Replay(const std::vector<BusConsumer*>& consumers, const worlds::World& world,
                          const render::RigOptions& rig, const std::vector<std::string>& imus,
                          const std::vector<std::string>& lasers, BusConsumer* progress) {
  if (reader_->truncated()) {
    throw RecordingInputError(file_, "RECORDING",
                              "the recording was cut short (no summary: a killed run); its "
                              "messages read up to the last complete chunk, but replay needs the "
                              "whole run");
  }
  std::map<std::uint16_t, Route> routes;
  std::vector<std::uint16_t> wanted;
  const auto route = [&](const std::string& topic, Kind kind, std::size_t sensor = 0) {
    if (const mcap::Channel* c = reader_->FindChannel(topic)) {
      routes[c->id] = {kind, sensor};
      wanted.push_back(c->id);
    }
  };
  route(kTruthTopic, Kind::kTruth);
  route(kWheelTopic, Kind::kWheel);
  route(kEventsTopic, Kind::kEvent);
  route(kCameraSetTopic, Kind::kCameraSet);
  std::vector<const render::CameraOptions*> camera_options;
  for (std::size_t k = 0; k < info_.cameras.size(); ++k) {
    const std::string& id = info_.cameras[k];
    const render::CameraOptions* options = rig.Find(id);
    if (!options) {
      throw RecordingInputError(file_, "sensors." + id,
                                "the recording has camera '" + id + "' and the scenario does not");
    }
    camera_options.push_back(options);
    route(SensorTopic(id, "image_raw"), Kind::kImage, k);
    route(SensorTopic(id, "depth/image_raw"), Kind::kDepth, k);
    route(SensorTruthTopic(id, "depth_truth"), Kind::kDepthTruth, k);
    route(SensorTruthTopic(id, "instance"), Kind::kInstance, k);
    route(SensorTruthTopic(id, "semantic"), Kind::kSemantic, k);
    route(SensorTruthTopic(id, "frame"), Kind::kFrame, k);
  }
  for (std::size_t i = 0; i < imus.size(); ++i) {
    route(SensorTopic(imus[i], "imu"), Kind::kImu, i);
    route(SensorTruthTopic(imus[i], "truth"), Kind::kImuTruth, i);
  }
  for (std::size_t i = 0; i < lasers.size(); ++i) {
    route(SensorTopic(lasers[i], "scan"), Kind::kScan, i);
    route(SensorTruthTopic(lasers[i], "truth"), Kind::kScanTruth, i);
  }

  std::vector<PendingFrame> frames(info_.cameras.size());
  std::vector<std::optional<ros::Imu>> imu_pending(imus.size());
  std::vector<std::optional<ros::LaserScan>> scan_pending(lasers.size());
  std::optional<sim::TruthSample> last_truth;
  bool started = false, ended = false;
  std::uint64_t count = 0, total = 0;
  const std::map<std::uint16_t, std::uint64_t> counts = reader_->MessageCounts();
  for (const std::uint16_t id : wanted) total += counts.count(id) ? counts.at(id) : 0;
  const auto each = [&](auto&& call) {
    for (BusConsumer* c : consumers) call(c);
  };
  const auto handle = [&](const mcap::Message& m) {
    const Route& r = routes.at(m.channel_id);
    const std::string what =
        reader_->channels().at(m.channel_id).topic + " message " + std::to_string(m.sequence);
    if (ended) throw CdrError(what + ": a message after the run's end");
    if (!started && r.kind != Kind::kTruth) throw CdrError(what + ": a message before the start");
    switch (r.kind) {
      case Kind::kTruth: {
        const ros::Truth t = ros::FromCdr<ros::Truth>(m.data, what);
        const sim::TruthSample truth = ros::FromTruth(t);
        if (t.kind == 0) {
          if (started) throw CdrError(what + ": a second start");
          started = true;
          each([&](BusConsumer* c) { c->OnStart(truth); });
        } else if (t.kind == 1) {
          if (!started) throw CdrError(what + ": a truth sample before the start");
          each([&](BusConsumer* c) { c->OnTruth(truth); });
          if (progress) progress->OnStepEnd(truth, false);
        } else if (t.kind == 2) {
          ended = true;
          end_ns_ = truth.stamp_ns;
          last_truth = truth;
        } else {
          throw CdrError(what + ": truth of kind " + std::to_string(t.kind));
        }
        break;
      }
      case Kind::kWheel: {
        const auto o = ros::FromWheelOdometry(ros::FromCdr<ros::WheelOdometry>(m.data, what));
        each([&](BusConsumer* c) { c->OnOdometry(o); });
        break;
      }
      case Kind::kEvent: {
        const sim::Event e = ros::FromEvent(ros::FromCdr<ros::Event>(m.data, what), what);
        if (e.kind == sim::EventKind::kPathDone) path_done_ = true;
        each([&](BusConsumer* c) { c->OnEvent(e); });
        break;
      }
      case Kind::kImu:
        imu_pending[r.sensor] = ros::FromCdr<ros::Imu>(m.data, what);
        break;
      case Kind::kImuTruth: {
        if (!imu_pending[r.sensor]) throw CdrError(what + ": IMU truth without its sample");
        const sim::ImuMessage imu =
            ros::FromImu(*imu_pending[r.sensor], ros::FromCdr<ros::ImuTruth>(m.data, what),
                         r.sensor, imus[r.sensor], what);
        imu_pending[r.sensor].reset();
        each([&](BusConsumer* c) { c->OnImu(imu); });
        break;
      }
      case Kind::kScan:
        scan_pending[r.sensor] = ros::FromCdr<ros::LaserScan>(m.data, what);
        break;
      case Kind::kScanTruth: {
        if (!scan_pending[r.sensor]) throw CdrError(what + ": scan truth without its sweep");
        const sim::ScanMessage scan =
            ros::FromScan(*scan_pending[r.sensor], ros::FromCdr<ros::ScanTruth>(m.data, what),
                          r.sensor, lasers[r.sensor], what);
        scan_pending[r.sensor].reset();
        each([&](BusConsumer* c) { c->OnScan(scan); });
        break;
      }
      case Kind::kCameraSet: {
        const ros::CameraSet set_record = ros::FromCdr<ros::CameraSet>(m.data, what);
        if (set_record.cameras.size() != set_record.dropped.size()) {
          throw CdrError(what + ": cameras and dropped differ in length");
        }
        CameraSet set;
        set.stamp_ns = set_record.header.stamp.ns;
        for (std::size_t i = 0; i < set_record.cameras.size(); ++i) {
          const auto it =
              std::find(info_.cameras.begin(), info_.cameras.end(), set_record.cameras[i]);
          if (it == info_.cameras.end()) {
            throw CdrError(what + ": camera '" + set_record.cameras[i] + "' was not recorded");
          }
          const std::size_t k = static_cast<std::size_t>(it - info_.cameras.begin());
          PendingFrame& pending = frames[k];
          if (!set_record.dropped[i]) {
            if (!pending.message || !pending.has_image || !pending.has_frame ||
                pending.message->stamp_ns != set.stamp_ns) {
              throw CdrError(what + ": camera '" + info_.cameras[k] +
                             "' has no complete frame at the set's stamp");
            }
            sim::CameraMessage& message = *pending.message;
            render::FrameTruthInput input;
            input.world = &world;
            input.camera_id = info_.cameras[k];
            input.model = camera_options[k]->model;
            input.world_from_camera = message.frame.world_from_camera;
            input.world_from_robot = message.world_from_robot;
            const std::size_t pixels = static_cast<std::size_t>(message.frame.rgb.width) *
                                       static_cast<std::size_t>(message.frame.rgb.height);
            if ((!message.frame.instance.empty() && message.frame.instance.size() != pixels) ||
                (!message.frame.semantic.empty() && message.frame.semantic.size() != pixels)) {
              throw CdrError(what + ": camera '" + info_.cameras[k] +
                             "' has label images of another size than its image");
            }
            input.instance = message.frame.instance.empty() ? nullptr : &message.frame.instance;
            input.semantic = message.frame.semantic.empty() ? nullptr : &message.frame.semantic;
            message.truth = render::ComputeFrameTruth(input);
          }
          set.cameras.push_back(
              {info_.cameras[k], k, set_record.dropped[i] ? nullptr : &*pending.message});
        }
        each([&](BusConsumer* c) { c->OnCameraSet(set); });
        for (PendingFrame& f : frames) f = PendingFrame{};
        break;
      }
      default: {
        PendingFrame& pending = frames[r.sensor];
        if (!pending.message) {
          pending.message.emplace();
          pending.message->camera = r.sensor;
          pending.message->frame.camera_id = info_.cameras[r.sensor];
          pending.message->stamp_ns = static_cast<TimeNs>(m.log_time_ns);
        }
        sim::CameraMessage& message = *pending.message;
        if (message.stamp_ns != static_cast<TimeNs>(m.log_time_ns)) {
          throw CdrError(what + ": a frame's topics at two stamps (no camera set between)");
        }
        const ros::ImageView image =
            r.kind == Kind::kFrame ? ros::ImageView{} : ros::FromCdr<ros::ImageView>(m.data, what);
        if (r.kind == Kind::kImage) {
          message.frame.rgb = ros::FromRgbImage(image, what);
          pending.has_image = true;
        } else if (r.kind == Kind::kDepth) {
          message.frame.noisy_depth_m = ros::FromFloatImage(image, what);
        } else if (r.kind == Kind::kDepthTruth) {
          message.frame.depth_m = ros::FromFloatImage(image, what);
        } else if (r.kind == Kind::kInstance) {
          message.frame.instance = ros::FromLabelImage(image, what);
        } else if (r.kind == Kind::kSemantic) {
          message.frame.semantic = ros::FromMono8Image(image, what);
        } else {
          const ros::CameraFrame f = ros::FromCdr<ros::CameraFrame>(m.data, what);
          message.frame_index = f.frame_index;
          message.frame.world_from_camera = ros::FromPose(f.world_from_camera);
          message.world_from_robot = ros::FromPose(f.world_from_robot);
          pending.has_frame = true;
        }
        break;
      }
    }
    ++count;
    fraction_ =
        total > 0 ? std::min(1.0, static_cast<double>(count) / static_cast<double>(total)) : 0.0;
  };
  try {
    reader_->ForEachMessage(
        [&](const mcap::Message& m) {
          handle(m);
          return true;
        },
        wanted);
  } catch (const mcap::RecordingError& e) {
    throw RecordingInputError(file_, e);
  } catch (const CdrError& e) {
    throw RecordingInputError(file_, "message", e.what());
  }
  if (!started || !last_truth) {
    throw RecordingInputError(file_, kTruthTopic,
                              started ? "the recording has no end of the run (truth of kind 2)"
                                      : "the recording has no start of the run");
  }
  each([&](BusConsumer* c) { c->OnStepEnd(*last_truth, true); });
  if (progress) progress->OnStepEnd(*last_truth, true);
}

}  // namespace corridorsim::record

#include "harness/record/recorder.h"

#include <chrono>
#include <cmath>

#include "harness/record/ros_convert.h"
#include "harness/run/stopwatch.h"

namespace corridorsim::record {
namespace {

ros::ColorRGBA ClassColor(worlds::SemanticClass c) {
  switch (c) {
    case worlds::SemanticClass::kWall:
      return {0.75f, 0.75f, 0.72f, 0.35f};
    case worlds::SemanticClass::kDoorFrame:
      return {0.45f, 0.3f, 0.2f, 0.9f};
    case worlds::SemanticClass::kDoorLeaf:
      return {0.6f, 0.4f, 0.25f, 0.9f};
    case worlds::SemanticClass::kFloor:
      return {0.4f, 0.4f, 0.4f, 0.2f};
    case worlds::SemanticClass::kCeiling:
      return {0.9f, 0.9f, 0.9f, 0.05f};
    default:
      return {0.5f, 0.6f, 0.7f, 0.6f};
  }
}

ros::Marker MapMarker(const std::string& ns, int id, std::int32_t type) {
  ros::Marker m;
  m.header.frame_id = kMapFrame;
  m.ns = ns;
  m.id = id;
  m.type = type;
  return m;
}

// The world as markers: its collision boxes by semantic class, the plates with their numbers,
// the lamps as discs.
ros::MarkerArray WorldMarkers(const worlds::World& world) {
  ros::MarkerArray array;
  int id = 0;
  for (const worlds::CollisionBox& box : world.collision_boxes) {
    if (box.semantic_class == worlds::SemanticClass::kFloor) continue;
    ros::Marker m =
        MapMarker(worlds::SemanticClassName(box.semantic_class), id++, ros::Marker::kCube);
    m.pose.position = {box.center.x(), box.center.y(), box.center.z()};
    m.scale = ros::ToVector3(2.0 * box.half_extents);
    m.color = ClassColor(box.semantic_class);
    array.markers.push_back(std::move(m));
  }
  for (const worlds::DoorPlate& plate : world.plates) {
    ros::Marker m = MapMarker("door_plate", plate.id, ros::Marker::kCube);
    m.pose.position = {plate.center.x(), plate.center.y(), plate.center.z()};
    const double yaw = std::atan2(plate.normal.y(), plate.normal.x());
    m.pose.orientation = {0, 0, std::sin(yaw / 2), std::cos(yaw / 2)};
    m.scale = {0.01, plate.size_m.x(), plate.size_m.y()};
    m.color = {0.1f, 0.3f, 0.8f, 1.0f};
    array.markers.push_back(m);
    ros::Marker text = MapMarker("door_plate_number", plate.id, ros::Marker::kText);
    text.pose.position = {plate.center.x(), plate.center.y(), plate.center.z() + 0.2};
    text.scale.z = 0.15;
    text.color = {1, 1, 1, 1};
    text.text = plate.room_number;
    array.markers.push_back(std::move(text));
  }
  for (const worlds::Lamp& lamp : world.lamps) {
    const bool disc = lamp.shape == worlds::LampShape::kCircular;
    ros::Marker m = MapMarker("lamp", lamp.id, disc ? ros::Marker::kCylinder : ros::Marker::kCube);
    m.pose.position = {lamp.center.x(), lamp.center.y(), lamp.center.z()};
    m.scale = disc ? ros::Vector3{2 * lamp.radius_m, 2 * lamp.radius_m, 0.01}
                   : ros::Vector3{lamp.size_m.x(), lamp.size_m.y(), 0.01};
    m.color =
        lamp.on ? ros::ColorRGBA{1.0f, 0.95f, 0.6f, 1.0f} : ros::ColorRGBA{0.3f, 0.3f, 0.3f, 1.0f};
    array.markers.push_back(std::move(m));
  }
  return array;
}

// (x, y, yaw) covariance as the 6x6 of geometry_msgs (x, y, z, rotation about x, y, z).
std::array<double, 36> Covariance6(const Eigen::Matrix3d& c) {
  std::array<double, 36> out{};
  const int index[3] = {0, 1, 5};
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 3; ++k) out[6 * index[r] + index[k]] = c(r, k);
  }
  return out;
}

}  // namespace

Recorder::Recorder(const std::filesystem::path& file, const RecordOptions& options,
                   const RecordingInfo& info, const render::RigOptions& rig,
                   const std::vector<sim::ImuOptions>& imus,
                   const std::vector<sim::LaserOptions>& lasers, const worlds::World& world,
                   double wheelbase_m)
    : filter_(options.topics), camera_ids_(info.cameras), wheelbase_m_(wheelbase_m) {
  for (const std::string& id : camera_ids_) {
    const render::CameraOptions* camera = rig.Find(id);
    CheckOrDie(camera != nullptr, "Recorder", "a rendered camera that is not in the rig");
    camera_models_.push_back(camera->model);
  }
  // MotionSensors index the enabled ones (ImuMessage::imu, ScanMessage::laser).
  for (const sim::ImuOptions& imu : imus) {
    if (imu.enabled) imu_ids_.push_back(imu.id);
  }
  for (const sim::LaserOptions& laser : lasers) {
    if (laser.enabled) laser_ids_.push_back(laser.id);
  }
  if (!options.bag_file.empty()) bag_.emplace(options.bag_file);
  if (options.mcap) WriteMcapHeader(file, options, info);
  WriteStatic(rig, imus, lasers, world);
}

// The MCAP file, its metadata (the run's) and the scenario as an attachment; a bag has neither.
void Recorder::WriteMcapHeader(const std::filesystem::path& file, const RecordOptions& options,
                               const RecordingInfo& info) {
  mcap::WriterOptions mcap_options;
  mcap_options.compression = options.compression;
  writer_.emplace(file, mcap_options);
  writer_->AddMetadata("corridorsim", {{"format", "1"},
                                       {"scenario_file", info.scenario_file},
                                       {"seed", std::to_string(info.seed)},
                                       {"cameras",
                                        [&] {
                                          std::string s;
                                          for (const std::string& c : info.cameras) {
                                            s += (s.empty() ? "" : ",") + c;
                                          }
                                          return s;
                                        }()},
                                       {"topics", info.topics}});
  writer_->AddMetadata("provenance", {{"json", info.provenance_json}});
  const std::string& yaml = info.scenario_yaml;
  writer_->AddAttachment(0, 0, "scenario.yaml", "application/yaml",
                         {reinterpret_cast<const std::uint8_t*>(yaml.data()), yaml.size()});
}

Recorder::~Recorder() = default;

template <ros::Message T>
void Recorder::Write(const std::string& topic, TimeNs stamp_ns, const T& message) {
  if (!filter_.Keeps(topic)) return;
  const WallClock::time_point t0 = WallClock::now();
  if (writer_) {
    auto channel = channels_.find(topic);
    if (channel == channels_.end()) {
      auto schema = schemas_.find(T::kType);
      if (schema == schemas_.end()) {
        schema = schemas_
                     .emplace(T::kType,
                              writer_->AddSchema(T::kType, "ros2msg", ros::Ros2Schema(T::kType)))
                     .first;
      }
      channel = channels_.emplace(topic, writer_->AddChannel(schema->second, topic, "cdr")).first;
    }
    ros::ToCdr(message, &cdr_buffer_);
    const auto t = static_cast<std::uint64_t>(stamp_ns < 0 ? 0 : stamp_ns);
    writer_->Write(channel->second, t, t, cdr_buffer_);
  }
  if (bag_) bag_->Write(topic, stamp_ns, message);
  encode_seconds_ += SecondsSince(t0);
}

void Recorder::WriteStatic(const render::RigOptions& rig, const std::vector<sim::ImuOptions>& imus,
                           const std::vector<sim::LaserOptions>& lasers,
                           const worlds::World& world) {
  ros::TFMessage tf;
  for (const render::CameraOptions& camera : rig.cameras) {
    if (!camera.enabled) continue;
    tf.transforms.push_back(ros::ToTransformStamped(0, kBaseFrame, OpticalFrame(camera.id),
                                                    camera.mount.RobotFromCamera()));
  }
  for (const sim::ImuOptions& imu : imus) {
    if (!imu.enabled) continue;
    tf.transforms.push_back(
        ros::ToTransformStamped(0, kBaseFrame, SensorFrame(imu.id), imu.mount.RobotFromBody()));
  }
  for (const sim::LaserOptions& laser : lasers) {
    if (!laser.enabled) continue;
    tf.transforms.push_back(
        ros::ToTransformStamped(0, kBaseFrame, SensorFrame(laser.id), laser.mount.RobotFromBody()));
  }
  Write(kTfStaticTopic, 0, tf);
  for (std::size_t k = 0; k < camera_ids_.size(); ++k) {
    Write(SensorTopic(camera_ids_[k], "camera_info"), 0,
          ros::ToCameraInfo(0, OpticalFrame(camera_ids_[k]), camera_models_[k]));
  }
  Write(kWorldTopic, 0, WorldMarkers(world));
}

void Recorder::WriteTruth(const sim::TruthSample& truth, std::uint8_t kind) {
  Write(kTruthTopic, truth.stamp_ns, ros::ToTruth(truth, kind));
  if (kind == 2) return;  // the end repeats the last sample's pose for replay only
  ros::TFMessage tf;
  tf.transforms.push_back(
      ros::ToTransformStamped(truth.stamp_ns, kMapFrame, kBaseFrame, truth.state.world_from_robot));
  Write(kTfTopic, truth.stamp_ns, tf);
  ros::Odometry odom;
  odom.header.stamp.ns = truth.stamp_ns;
  odom.header.frame_id = kMapFrame;
  odom.child_frame_id = kBaseFrame;
  odom.pose.pose = ros::ToPose(truth.state.world_from_robot);
  const Eigen::Matrix3d robot_from_world = truth.state.world_from_robot.rotation().transpose();
  odom.twist.twist.linear = ros::ToVector3(robot_from_world * truth.state.linear_velocity_in_world);
  odom.twist.twist.angular =
      ros::ToVector3(robot_from_world * truth.state.angular_velocity_in_world);
  Write(kTruthOdomTopic, truth.stamp_ns, odom);
}

void Recorder::OnStart(const sim::TruthSample& truth) { WriteTruth(truth, 0); }
void Recorder::OnTruth(const sim::TruthSample& truth) { WriteTruth(truth, 1); }

void Recorder::OnStepEnd(const sim::TruthSample& truth, bool last) {
  if (last) WriteTruth(truth, 2);
}

void Recorder::OnOdometry(const WheelOdometry& o) {
  Write(kWheelTopic, o.stamp_ns, ros::ToWheelOdometry(o));
  // Dead reckoning with the nominal wheelbase (the midpoint rule), as a robot driver publishes.
  const double ds = 0.5 * (o.left_distance_m + o.right_distance_m);
  const double dyaw =
      wheelbase_m_ > 0 ? (o.right_distance_m - o.left_distance_m) / wheelbase_m_ : 0.0;
  const double heading = odom_pose_.yaw() + 0.5 * dyaw;
  odom_pose_ = SE2(odom_pose_.x() + ds * std::cos(heading), odom_pose_.y() + ds * std::sin(heading),
                   odom_pose_.yaw() + dyaw);
  ros::Odometry odom;
  odom.header.stamp.ns = o.stamp_ns;
  odom.header.frame_id = kOdomFrame;
  odom.child_frame_id = kBaseFrame;
  odom.pose.pose = ros::ToPose(SE3::FromSE2(odom_pose_));
  const double dt = ToSeconds(o.interval_ns);
  if (dt > 0) {
    odom.twist.twist.linear.x = ds / dt;
    odom.twist.twist.angular.z = dyaw / dt;
  }
  Write(kOdomTopic, o.stamp_ns, odom);
}

void Recorder::OnCameraSet(const CameraSet& set) {
  ros::CameraSet record;
  record.header.stamp.ns = set.stamp_ns;
  record.header.frame_id = kBaseFrame;
  for (const CameraSlot& slot : set.cameras) {
    record.cameras.push_back(slot.camera_id);
    record.dropped.push_back(slot.message == nullptr);
    if (!slot.message) continue;
    const sim::CameraMessage& m = *slot.message;
    const render::CameraFrame& f = m.frame;
    const std::string& id = slot.camera_id;
    const std::string frame = OpticalFrame(id);
    Write(SensorTopic(id, "image_raw"), m.stamp_ns, ros::ViewRgbImage(m.stamp_ns, frame, f.rgb));
    if (!f.noisy_depth_m.data.empty()) {
      Write(SensorTopic(id, "depth/image_raw"), m.stamp_ns,
            ros::ViewFloatImage(m.stamp_ns, frame, f.noisy_depth_m));
    }
    if (!f.depth_m.data.empty()) {
      Write(SensorTruthTopic(id, "depth_truth"), m.stamp_ns,
            ros::ViewFloatImage(m.stamp_ns, frame, f.depth_m));
    }
    if (!f.instance.empty()) {
      Write(SensorTruthTopic(id, "instance"), m.stamp_ns,
            ros::ViewLabelImage(m.stamp_ns, frame, f.rgb.width, f.rgb.height, f.instance,
                                &narrow_labels_));
    }
    if (!f.semantic.empty()) {
      Write(SensorTruthTopic(id, "semantic"), m.stamp_ns,
            ros::ViewMono8Image(m.stamp_ns, frame, f.rgb.width, f.rgb.height, f.semantic));
    }
    ros::CameraFrame info;
    info.header.stamp.ns = m.stamp_ns;
    info.header.frame_id = frame;
    info.frame_index = m.frame_index;
    info.world_from_camera = ros::ToPose(f.world_from_camera);
    info.world_from_robot = ros::ToPose(m.world_from_robot);
    Write(SensorTruthTopic(id, "frame"), m.stamp_ns, info);
  }
  Write(kCameraSetTopic, set.stamp_ns, record);
}

void Recorder::OnImu(const sim::ImuMessage& imu) {
  const std::string& id = imu_ids_.at(imu.imu);
  Write(SensorTopic(id, "imu"), imu.sample.stamp_ns,
        ros::ToImu(imu.sample, SensorFrame(id), 0.0, 0.0));
  Write(SensorTruthTopic(id, "truth"), imu.sample.stamp_ns, ros::ToImuTruth(imu, SensorFrame(id)));
}

void Recorder::OnScan(const sim::ScanMessage& scan) {
  const std::string& id = laser_ids_.at(scan.laser);
  // Stamped at the sweep's first beam (sensor_msgs/LaserScan), logged when it is delivered.
  Write(SensorTopic(id, "scan"), scan.complete_ns, ros::ToLaserScan(scan.scan, SensorFrame(id)));
  Write(SensorTruthTopic(id, "truth"), scan.complete_ns, ros::ToScanTruth(scan, SensorFrame(id)));
}

void Recorder::OnEvent(const sim::Event& event) {
  Write(kEventsTopic, event.stamp_ns, ros::ToEvent(event));
}

void Recorder::AddPipelines(const std::vector<PipelineRecord>& records) {
  for (const PipelineRecord& record : records) {
    ros::Path path;
    path.header.frame_id = kMapFrame;
    for (const EstimateSample& e : record.estimates) {
      ros::PoseWithCovarianceStamped pose;
      pose.header.stamp.ns = e.stamp_ns;
      pose.header.frame_id = kMapFrame;
      pose.pose.pose = ros::ToPose(SE3::FromSE2(e.world_from_robot));
      pose.pose.covariance = Covariance6(e.covariance);
      Write(PipelineTopic(record.name, "pose"), e.stamp_ns, pose);
      path.poses.push_back({pose.header, pose.pose.pose});
      path.header.stamp = pose.header.stamp;
    }
    Write(PipelineTopic(record.name, "path"), path.header.stamp.ns, path);
    ros::MarkerArray landmarks;
    for (const slam::LandmarkEstimate& l : record.landmarks) {
      ros::Marker m = MapMarker(slam::LandmarkTypeName(l.type), l.id, ros::Marker::kSphere);
      m.header.stamp = path.header.stamp;
      m.pose.position = {l.position_in_world.x(), l.position_in_world.y(), l.position_in_world.z()};
      // The sphere spans two standard deviations of the largest variance, at least 5 cm.
      const double sigma = std::sqrt(std::max(0.0, l.covariance.diagonal().maxCoeff()));
      const double d = std::max(0.05, 4.0 * sigma);
      m.scale = {d, d, d};
      m.color = {1.0f, 0.3f, 0.1f, 0.8f};
      m.text = l.label;
      landmarks.markers.push_back(std::move(m));
    }
    Write(PipelineTopic(record.name, "landmarks"), path.header.stamp.ns, landmarks);
  }
}

void Recorder::Close() {
  if (closed_) return;
  closed_ = true;
  if (writer_) writer_->Close();
  if (bag_) bag_->Close();
}

}  // namespace corridorsim::record

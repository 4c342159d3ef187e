#include "harness/record/ros_convert.h"

#include "common/error.h"
#include "common/io/input_text.h"

#include <algorithm>
#include <cstring>
#include <limits>

namespace corridorsim::ros {
namespace {

[[noreturn]] void Fail(const std::string& what, const std::string& why) {
  throw CdrError(what + ": " + why);
}

Header MakeHeader(TimeNs stamp_ns, const std::string& frame_id) {
  Header h;
  h.stamp.ns = stamp_ns;
  h.frame_id = frame_id;
  return h;
}

template <class T>
ImageView RawImage(TimeNs stamp_ns, const std::string& frame_id, int width, int height,
                   int channels, const char* encoding, const std::vector<T>& values) {
  ImageView image;
  image.header = MakeHeader(stamp_ns, frame_id);
  image.width = static_cast<std::uint32_t>(width);
  image.height = static_cast<std::uint32_t>(height);
  image.encoding = encoding;
  image.step = static_cast<std::uint32_t>(width * channels * static_cast<int>(sizeof(T)));
  image.data = {reinterpret_cast<const std::uint8_t*>(values.data()), values.size() * sizeof(T)};
  return image;
}

// The pixels of `image` as `count_per_pixel` values of T, after checking its encoding and sizes.
template <class T>
std::vector<T> Pixels(const ImageView& image, const char* encoding, std::uint32_t count_per_pixel,
                      const std::string& what) {
  if (image.encoding != encoding) {
    Fail(what, "encoding '" + image.encoding + "', expected '" + encoding + "'");
  }
  if (image.is_bigendian) Fail(what, "a big-endian image");
  const std::uint64_t row = std::uint64_t{image.width} * count_per_pixel * sizeof(T);
  if (image.width == 0 || image.height == 0 || image.width > 1 << 15 || image.height > 1 << 15 ||
      image.step != row || image.data.size() != row * image.height) {
    Fail(what, "an image of " + std::to_string(image.width) + " x " + std::to_string(image.height) +
                   " px with step " + std::to_string(image.step) + " and " +
                   std::to_string(image.data.size()) + " bytes");
  }
  if constexpr (sizeof(T) == 1) {
    return std::vector<T>(image.data.begin(), image.data.end());
  } else {
    std::vector<T> values(image.data.size() / sizeof(T));
    std::memcpy(values.data(), image.data.data(), image.data.size());
    return values;
  }
}

}  // namespace

Pose ToPose(const SE3& pose) {
  Pose p;
  p.position = {pose.translation().x(), pose.translation().y(), pose.translation().z()};
  const Eigen::Quaterniond& q = pose.quaternion();
  p.orientation = {q.x(), q.y(), q.z(), q.w()};
  return p;
}

SE3 FromPose(const Pose& p) {
  return SE3::FromStored(
      Eigen::Quaterniond(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z),
      Eigen::Vector3d(p.position.x, p.position.y, p.position.z));
}

Transform ToTransform(const SE3& pose) {
  const Pose p = ToPose(pose);
  return {{p.position.x, p.position.y, p.position.z}, p.orientation};
}

TransformStamped ToTransformStamped(TimeNs stamp_ns, const std::string& parent,
                                    const std::string& child, const SE3& parent_from_child) {
  TransformStamped t;
  t.header = MakeHeader(stamp_ns, parent);
  t.child_frame_id = child;
  t.transform = ToTransform(parent_from_child);
  return t;
}

Vector3 ToVector3(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
Eigen::Vector3d FromVector3(const Vector3& v) { return {v.x, v.y, v.z}; }

ImageView ViewRgbImage(TimeNs stamp_ns, const std::string& frame_id, const Image8& rgb) {
  CheckOrDie(rgb.channels == 3, "ViewRgbImage", "not an RGB image");
  return RawImage(stamp_ns, frame_id, rgb.width, rgb.height, 3, "rgb8", rgb.data);
}

ImageView ViewFloatImage(TimeNs stamp_ns, const std::string& frame_id, const ImageF& image) {
  return RawImage(stamp_ns, frame_id, image.width, image.height, 1, "32FC1", image.data);
}

ImageView ViewLabelImage(TimeNs stamp_ns, const std::string& frame_id, int width, int height,
                         const std::vector<std::uint32_t>& instance,
                         std::vector<std::uint16_t>* narrow) {
  const bool fits =
      std::all_of(instance.begin(), instance.end(), [](std::uint32_t id) { return id <= 0xFFFFu; });
  if (!fits) return RawImage(stamp_ns, frame_id, width, height, 1, "32SC1", instance);
  narrow->assign(instance.begin(), instance.end());
  return RawImage(stamp_ns, frame_id, width, height, 1, "16UC1", *narrow);
}

ImageView ViewMono8Image(TimeNs stamp_ns, const std::string& frame_id, int width, int height,
                         const std::vector<std::uint8_t>& values) {
  return RawImage(stamp_ns, frame_id, width, height, 1, "mono8", values);
}

Image ToRgbImage(TimeNs stamp_ns, const std::string& frame_id, const Image8& rgb) {
  return ViewRgbImage(stamp_ns, frame_id, rgb).As<Image>();
}

Image ToFloatImage(TimeNs stamp_ns, const std::string& frame_id, const ImageF& image) {
  return ViewFloatImage(stamp_ns, frame_id, image).As<Image>();
}

Image8 FromRgbImage(const Image& image, const std::string& what) {
  return FromRgbImage(image.As<ImageView>(), what);
}

Image8 FromRgbImage(const ImageView& image, const std::string& what) {
  Image8 rgb;
  rgb.data = Pixels<std::uint8_t>(image, "rgb8", 3, what);
  rgb.width = static_cast<int>(image.width);
  rgb.height = static_cast<int>(image.height);
  rgb.channels = 3;
  return rgb;
}

ImageF FromFloatImage(const Image& image, const std::string& what) {
  return FromFloatImage(image.As<ImageView>(), what);
}

ImageF FromFloatImage(const ImageView& image, const std::string& what) {
  ImageF f;
  f.data = Pixels<float>(image, "32FC1", 1, what);
  f.width = static_cast<int>(image.width);
  f.height = static_cast<int>(image.height);
  return f;
}

std::vector<std::uint32_t> FromLabelImage(const Image& image, const std::string& what) {
  return FromLabelImage(image.As<ImageView>(), what);
}

std::vector<std::uint32_t> FromLabelImage(const ImageView& image, const std::string& what) {
  if (image.encoding == "16UC1") {
    const std::vector<std::uint16_t> narrow = Pixels<std::uint16_t>(image, "16UC1", 1, what);
    return std::vector<std::uint32_t>(narrow.begin(), narrow.end());
  }
  return Pixels<std::uint32_t>(image, "32SC1", 1, what);
}

std::vector<std::uint8_t> FromMono8Image(const Image& image, const std::string& what) {
  return FromMono8Image(image.As<ImageView>(), what);
}

std::vector<std::uint8_t> FromMono8Image(const ImageView& image, const std::string& what) {
  return Pixels<std::uint8_t>(image, "mono8", 1, what);
}

CameraInfo ToCameraInfo(TimeNs stamp_ns, const std::string& frame_id, const CameraModel& model) {
  CameraInfo info;
  info.header = MakeHeader(stamp_ns, frame_id);
  double fx = 0, fy = 0, cx = 0, cy = 0;
  if (const PinholeRadTan* p = model.pinhole()) {
    info.distortion_model = "plumb_bob";
    info.d = {p->k1, p->k2, p->p1, p->p2, p->k3};
    fx = p->fx, fy = p->fy, cx = p->cx, cy = p->cy;
  } else if (const KannalaBrandt* k = model.kannala_brandt()) {
    info.distortion_model = "equidistant";  // OpenCV's fisheye model: k1..k4 of theta^3..theta^9
    info.d = {k->k1, k->k2, k->k3, k->k4};
    fx = k->fx, fy = k->fy, cx = k->cx, cy = k->cy;
  }
  info.width = static_cast<std::uint32_t>(model.width());
  info.height = static_cast<std::uint32_t>(model.height());
  info.k = {fx, 0, cx, 0, fy, cy, 0, 0, 1};
  info.r = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.p = {fx, 0, cx, 0, 0, fy, cy, 0, 0, 0, 1, 0};
  return info;
}

Truth ToTruth(const sim::TruthSample& truth, std::uint8_t kind) {
  Truth t;
  t.header = MakeHeader(truth.stamp_ns, "map");
  t.kind = kind;
  t.x = truth.world_from_robot_2d.x();
  t.y = truth.world_from_robot_2d.y();
  t.yaw = truth.world_from_robot_2d.yaw();
  t.pose = ToPose(truth.state.world_from_robot);
  t.linear_velocity = ToVector3(truth.state.linear_velocity_in_world);
  t.angular_velocity = ToVector3(truth.state.angular_velocity_in_world);
  t.left_wheel_angle = truth.state.left_wheel_angle_rad;
  t.right_wheel_angle = truth.state.right_wheel_angle_rad;
  for (const SE3& camera : truth.world_from_camera) t.camera_poses.push_back(ToPose(camera));
  return t;
}

sim::TruthSample FromTruth(const Truth& t) {
  sim::TruthSample truth;
  truth.stamp_ns = t.header.stamp.ns;
  truth.world_from_robot_2d = SE2(t.x, t.y, t.yaw);  // yaw is in (-pi, pi]: kept exactly
  truth.state.world_from_robot = FromPose(t.pose);
  truth.state.linear_velocity_in_world = FromVector3(t.linear_velocity);
  truth.state.angular_velocity_in_world = FromVector3(t.angular_velocity);
  truth.state.left_wheel_angle_rad = t.left_wheel_angle;
  truth.state.right_wheel_angle_rad = t.right_wheel_angle;
  for (const Pose& p : t.camera_poses) truth.world_from_camera.push_back(FromPose(p));
  return truth;
}

WheelOdometry ToWheelOdometry(const ::corridorsim::WheelOdometry& o) {
  WheelOdometry w;
  w.header = MakeHeader(o.stamp_ns, "base_link");
  w.interval_ns = o.interval_ns;
  w.left_distance = o.left_distance_m;
  w.right_distance = o.right_distance_m;
  w.left_ticks = o.left_ticks;
  w.right_ticks = o.right_ticks;
  return w;
}

::corridorsim::WheelOdometry FromWheelOdometry(const WheelOdometry& w) {
  ::corridorsim::WheelOdometry o;
  o.stamp_ns = w.header.stamp.ns;
  o.interval_ns = w.interval_ns;
  o.left_distance_m = w.left_distance;
  o.right_distance_m = w.right_distance;
  o.left_ticks = w.left_ticks;
  o.right_ticks = w.right_ticks;
  return o;
}

Imu ToImu(const ImuSample& sample, const std::string& frame_id, double gyroscope_variance,
          double accelerometer_variance) {
  Imu imu;
  imu.header = MakeHeader(sample.stamp_ns, frame_id);
  imu.orientation = {0, 0, 0, 0};
  imu.orientation_covariance[0] = -1.0;
  imu.angular_velocity = ToVector3(sample.angular_velocity_rad_s);
  imu.linear_acceleration = ToVector3(sample.linear_acceleration_m_s2);
  for (int i = 0; i < 3; ++i) {
    imu.angular_velocity_covariance[4 * i] = gyroscope_variance;
    imu.linear_acceleration_covariance[4 * i] = accelerometer_variance;
  }
  return imu;
}

ImuTruth ToImuTruth(const sim::ImuMessage& m, const std::string& frame_id) {
  ImuTruth t;
  t.header = MakeHeader(m.sample.stamp_ns, frame_id);
  t.exact_angular_velocity = ToVector3(m.exact.angular_velocity_rad_s);
  t.exact_linear_acceleration = ToVector3(m.exact.linear_acceleration_m_s2);
  t.gyroscope_bias = ToVector3(m.gyroscope_bias);
  t.accelerometer_bias = ToVector3(m.accelerometer_bias);
  t.world_from_imu = ToPose(m.world_from_imu);
  t.velocity_in_world = ToVector3(m.velocity_in_world);
  return t;
}

sim::ImuMessage FromImu(const Imu& imu, const ImuTruth& t, std::size_t index,
                        const std::string& sensor_id, const std::string& what) {
  if (imu.header.stamp.ns != t.header.stamp.ns) Fail(what, "its truth has another stamp");
  sim::ImuMessage m;
  m.imu = index;
  m.sample.stamp_ns = imu.header.stamp.ns;
  m.sample.sensor_id = sensor_id;
  m.sample.angular_velocity_rad_s = FromVector3(imu.angular_velocity);
  m.sample.linear_acceleration_m_s2 = FromVector3(imu.linear_acceleration);
  m.exact = m.sample;
  m.exact.angular_velocity_rad_s = FromVector3(t.exact_angular_velocity);
  m.exact.linear_acceleration_m_s2 = FromVector3(t.exact_linear_acceleration);
  m.gyroscope_bias = FromVector3(t.gyroscope_bias);
  m.accelerometer_bias = FromVector3(t.accelerometer_bias);
  m.world_from_imu = FromPose(t.world_from_imu);
  m.velocity_in_world = FromVector3(t.velocity_in_world);
  return m;
}

LaserScan ToLaserScan(const ::corridorsim::LaserScan& scan, const std::string& frame_id) {
  LaserScan s;
  s.header = MakeHeader(scan.stamp_ns, frame_id);
  const std::size_t n = scan.ranges_m.size();
  s.angle_min = static_cast<float>(scan.angle_min_rad);
  s.angle_max = static_cast<float>(scan.angle_min_rad +
                                   scan.angle_increment_rad * static_cast<double>(n ? n - 1 : 0));
  s.angle_increment = static_cast<float>(scan.angle_increment_rad);
  s.time_increment = static_cast<float>(ToSeconds(scan.time_increment_ns));
  s.scan_time = static_cast<float>(ToSeconds(scan.scan_time_ns));
  s.range_min = static_cast<float>(scan.range_min_m);
  s.range_max = static_cast<float>(scan.range_max_m);
  s.ranges = scan.ranges_m;
  return s;
}

ScanTruth ToScanTruth(const sim::ScanMessage& m, const std::string& frame_id) {
  ScanTruth t;
  t.header = MakeHeader(m.scan.stamp_ns, frame_id);
  t.angle_min = m.scan.angle_min_rad;
  t.angle_increment = m.scan.angle_increment_rad;
  t.time_increment_ns = m.scan.time_increment_ns;
  t.scan_time_ns = m.scan.scan_time_ns;
  t.complete_ns = m.complete_ns;
  t.range_min = m.scan.range_min_m;
  t.range_max = m.scan.range_max_m;
  for (const sim::BeamTruth& b : m.truth) {
    t.true_ranges.push_back(b.range_m);
    t.instance_ids.push_back(b.instance_id);
    t.semantic_classes.push_back(static_cast<std::uint8_t>(b.semantic_class));
    t.incidences.push_back(b.incidence_rad);
  }
  for (const SE3& pose : m.world_from_laser) t.world_from_laser.push_back(ToPose(pose));
  return t;
}

sim::ScanMessage FromScan(const LaserScan& s, const ScanTruth& t, std::size_t index,
                          const std::string& sensor_id, const std::string& what) {
  const std::size_t n = s.ranges.size();
  if (s.header.stamp.ns != t.header.stamp.ns) Fail(what, "its truth has another stamp");
  if (t.true_ranges.size() != n || t.instance_ids.size() != n || t.semantic_classes.size() != n ||
      t.incidences.size() != n || (t.world_from_laser.size() != n && !t.world_from_laser.empty())) {
    Fail(what, "its truth does not have one entry per beam (" + std::to_string(n) + ")");
  }
  sim::ScanMessage m;
  m.laser = index;
  m.scan.stamp_ns = s.header.stamp.ns;
  m.scan.sensor_id = sensor_id;
  m.scan.angle_min_rad = t.angle_min;
  m.scan.angle_increment_rad = t.angle_increment;
  m.scan.time_increment_ns = t.time_increment_ns;
  m.scan.scan_time_ns = t.scan_time_ns;
  m.scan.range_min_m = t.range_min;
  m.scan.range_max_m = t.range_max;
  m.scan.ranges_m = s.ranges;
  m.complete_ns = t.complete_ns;
  m.truth.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    m.truth[i].range_m = t.true_ranges[i];
    m.truth[i].instance_id = t.instance_ids[i];
    m.truth[i].semantic_class = static_cast<worlds::SemanticClass>(t.semantic_classes[i]);
    m.truth[i].incidence_rad = t.incidences[i];
  }
  for (const Pose& p : t.world_from_laser) m.world_from_laser.push_back(FromPose(p));
  return m;
}

Event ToEvent(const sim::Event& e) {
  Event out;
  out.header = MakeHeader(e.stamp_ns, "map");
  out.kind = sim::EventKindName(e.kind);
  out.instance_id = e.instance_id;
  out.semantic_class = static_cast<std::uint8_t>(e.semantic_class);
  out.position = {e.position_in_world.x(), e.position_in_world.y(), e.position_in_world.z()};
  out.depth = e.depth_m;
  out.left_wheel = e.left_wheel;
  out.distance = e.distance_m;
  out.camera_id = e.camera_id;
  return out;
}

sim::Event FromEvent(const Event& in, const std::string& what) {
  sim::Event e;
  bool known = false;
  for (int k = 0; k <= static_cast<int>(sim::EventKind::kFrameDropped); ++k) {
    if (sim::EventKindName(static_cast<sim::EventKind>(k)) == in.kind) {
      e.kind = static_cast<sim::EventKind>(k);
      known = true;
    }
  }
  if (!known) Fail(what, "an event of kind '" + InputExcerpt(in.kind, 60) + "'");
  e.stamp_ns = in.header.stamp.ns;
  e.instance_id = in.instance_id;
  e.semantic_class = static_cast<worlds::SemanticClass>(in.semantic_class);
  e.position_in_world = {in.position.x, in.position.y, in.position.z};
  e.depth_m = in.depth;
  e.left_wheel = in.left_wheel;
  e.distance_m = in.distance;
  e.camera_id = in.camera_id;
  return e;
}

}  // namespace corridorsim::ros

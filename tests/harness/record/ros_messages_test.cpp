// ROS 2 CDR of the recording's messages (harness/record/ros_messages.h): byte layouts checked
// against the encoding's rules, round trips that keep every bit, the readers' bounds, and the
// schemas' dependency lists.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "common/io/cdr.h"
#include "harness/record/ros_convert.h"
#include "harness/record/ros_messages.h"

namespace corridorsim::ros {
namespace {

TEST_CASE("CDR: the encapsulation header, alignment relative to it, strings with their NUL",
          "[record]") {
  CdrWriter w;
  w.Primitive<std::uint8_t>(7);
  w.Primitive<double>(1.5);  // aligned to 8 after the 4-byte header: 7 pad bytes
  w.String("ab");
  const std::vector<std::uint8_t>& d = w.data();
  REQUIRE(d.size() == 4 + 1 + 7 + 8 + 4 + 3);
  CHECK(d[0] == 0x00);
  CHECK(d[1] == 0x01);
  CHECK(d[4] == 7);
  CHECK(d[12 + 7] == 0x3F);  // 1.5's top byte, little-endian
  CHECK(d[20] == 3);         // the length counts the NUL
  CHECK(d[24] == 'a');
  CHECK(d[26] == 0);
}

TEST_CASE("A header and a stamp: builtin_interfaces/Time as int32 sec, uint32 nanosec",
          "[record]") {
  Header h;
  h.stamp.ns = 12'345'678'901;
  h.frame_id = "map";
  const std::vector<std::uint8_t> d = ToCdr(h);
  REQUIRE(d.size() == 4 + 4 + 4 + 4 + 4);
  CHECK(d[4] == 12);
  const std::uint32_t nanosec =
      d[8] | d[9] << 8 | d[10] << 16 | static_cast<std::uint32_t>(d[11]) << 24;
  CHECK(nanosec == 345'678'901u);
  CHECK(FromCdr<Header>(d, "header").stamp.ns == h.stamp.ns);
}

TEST_CASE("Round trips keep every bit: truth, scans with REP 117's non-finite ranges, images",
          "[record]") {
  sim::TruthSample truth;
  truth.stamp_ns = 1'010'000'000;
  truth.world_from_robot_2d = SE2(1.0 / 3.0, -2.0 / 7.0, 3.0);
  truth.state.world_from_robot =
      SE3(Eigen::Quaterniond(0.9, 0.1, -0.2, 0.3), Eigen::Vector3d(1e-17, 5.5, -0.25));
  truth.state.linear_velocity_in_world = {0.34, -1e-9, 0};
  truth.state.left_wheel_angle_rad = 123.456789;
  truth.world_from_camera = {truth.state.world_from_robot, SE3::Identity()};
  const sim::TruthSample back = FromTruth(FromCdr<Truth>(ToCdr(ToTruth(truth, 1)), "truth"));
  CHECK(back.stamp_ns == truth.stamp_ns);
  CHECK(back.world_from_robot_2d.yaw() == truth.world_from_robot_2d.yaw());
  CHECK(back.world_from_robot_2d.x() == truth.world_from_robot_2d.x());
  CHECK(back.state.world_from_robot.quaternion().coeffs() ==
        truth.state.world_from_robot.quaternion().coeffs());
  CHECK(back.state.world_from_robot.translation() == truth.state.world_from_robot.translation());
  CHECK(back.state.linear_velocity_in_world == truth.state.linear_velocity_in_world);
  CHECK(back.state.left_wheel_angle_rad == truth.state.left_wheel_angle_rad);
  REQUIRE(back.world_from_camera.size() == 2);

  corridorsim::LaserScan scan;
  scan.stamp_ns = 100;
  scan.angle_min_rad = -M_PI / 2;
  scan.angle_increment_rad = M_PI / 180;
  scan.ranges_m = {1.25f, std::numeric_limits<float>::infinity(),
                   -std::numeric_limits<float>::infinity(), std::nanf("")};
  const LaserScan s = FromCdr<LaserScan>(ToCdr(ToLaserScan(scan, "laser_link")), "scan");
  REQUIRE(s.ranges.size() == 4);
  CHECK(s.ranges[0] == 1.25f);
  CHECK(std::isinf(s.ranges[1]));
  CHECK(s.ranges[2] < 0);
  CHECK(std::isnan(s.ranges[3]));
  CHECK(s.header.frame_id == "laser_link");

  Image8 rgb(3, 2, 3);
  for (std::size_t i = 0; i < rgb.data.size(); ++i) rgb.data[i] = static_cast<std::uint8_t>(i * 13);
  const Image image = FromCdr<Image>(ToCdr(ToRgbImage(5, "cam", rgb)), "image");
  CHECK(image.step == 9);
  CHECK(FromRgbImage(image, "image").data == rgb.data);
}

TEST_CASE("The reader refuses short data and huge counts before allocating", "[record]") {
  Path path;
  path.poses.resize(3);
  std::vector<std::uint8_t> d = ToCdr(path);
  for (std::size_t cut = 0; cut < d.size(); ++cut) {
    const std::vector<std::uint8_t> part(d.begin(), d.begin() + static_cast<long>(cut));
    CHECK_THROWS_AS(FromCdr<Path>(part, "cut"), CdrError);
  }
  // A sequence count of 2^31 elements in a few bytes.
  std::vector<std::uint8_t> huge = ToCdr(Image{});
  const std::size_t data_count = huge.size() - 4;  // the empty uint8[]'s count is last
  huge[data_count + 3] = 0x80;
  CHECK_THROWS_WITH(FromCdr<Image>(huge, "huge"), Catch::Contains("sequence of 2147483648"));
  // An image whose step does not match its width.
  Image bad = ToRgbImage(0, "cam", Image8(4, 4, 3));
  bad.step = 11;
  CHECK_THROWS_AS(FromRgbImage(bad, "bad"), CdrError);
  bad = ToRgbImage(0, "cam", Image8(4, 4, 3));
  bad.encoding = "bgr8";
  CHECK_THROWS_WITH(FromRgbImage(bad, "bad"), Catch::Contains("bgr8"));
}

TEST_CASE("Schemas embed every definition they use, once, after 80 '='", "[record]") {
  const std::string schema = Ros2Schema(Odometry::kType);
  CHECK(schema.rfind("std_msgs/Header header\n", 0) == 0);
  for (const char* dep : {"MSG: std_msgs/Header", "MSG: builtin_interfaces/Time",
                          "MSG: geometry_msgs/PoseWithCovariance", "MSG: geometry_msgs/Pose",
                          "MSG: geometry_msgs/Point", "MSG: geometry_msgs/Quaternion",
                          "MSG: geometry_msgs/TwistWithCovariance", "MSG: geometry_msgs/Twist",
                          "MSG: geometry_msgs/Vector3"}) {
    INFO(dep);
    const std::string line = std::string(dep) + "\n";
    const std::size_t at = schema.find(line);
    REQUIRE(at != std::string::npos);
    CHECK(schema.find(line, at + 1) == std::string::npos);
    CHECK(schema.compare(at - 81, 81, std::string(80, '=') + "\n") == 0);
  }
  // Every type the recorder writes has a definition whose dependencies resolve.
  for (const char* type :
       {Image::kType, CameraInfo::kType, Imu::kType, LaserScan::kType, TFMessage::kType,
        Path::kType, PoseWithCovarianceStamped::kType, MarkerArray::kType, Truth::kType,
        WheelOdometry::kType, CameraFrame::kType, CameraSet::kType, ImuTruth::kType,
        ScanTruth::kType, Event::kType}) {
    INFO(type);
    CHECK_FALSE(Ros2Schema(type).empty());
  }
}

}  // namespace
}  // namespace corridorsim::ros

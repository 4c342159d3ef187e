// Tests harness/record/bag_writer.cpp: ROS 1 serialization, the ROS 1 types (genmsg's MD5 against
// the installed ROS 1 headers), and a bag of every message type read back by python3-rosbag.
#include "harness/record/bag_writer.h"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

// The installed ROS 1 headers' traits (their structs do not compile as C++20; the traits do).
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/LaserScan.h>
#include <std_msgs/ColorRGBA.h>
#include <std_msgs/Header.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/MarkerArray.h>

#include "common/io/child_process.h"
#include "tests/support/scratch_dir.h"

namespace corridorsim::record {
namespace {

namespace fs = std::filesystem;

struct InstalledType {
  std::string ros2_type;
  std::string datatype, md5sum, definition;
};

template <class Ros2, class Ros1>
InstalledType Installed() {
  return {Ros2::kType, ::ros::message_traits::DataType<Ros1>::value(),
          ::ros::message_traits::MD5Sum<Ros1>::value(),
          ::ros::message_traits::Definition<Ros1>::value()};
}

// Every standard message of ros_messages.h with its ROS 1 header's traits.
std::vector<InstalledType> InstalledTypes() {
  return {
      Installed<ros::Header, ::std_msgs::Header>(),
      Installed<ros::ColorRGBA, ::std_msgs::ColorRGBA>(),
      Installed<ros::Vector3, ::geometry_msgs::Vector3>(),
      Installed<ros::Point, ::geometry_msgs::Point>(),
      Installed<ros::Quaternion, ::geometry_msgs::Quaternion>(),
      Installed<ros::Pose, ::geometry_msgs::Pose>(),
      Installed<ros::PoseWithCovariance, ::geometry_msgs::PoseWithCovariance>(),
      Installed<ros::Twist, ::geometry_msgs::Twist>(),
      Installed<ros::TwistWithCovariance, ::geometry_msgs::TwistWithCovariance>(),
      Installed<ros::Transform, ::geometry_msgs::Transform>(),
      Installed<ros::TransformStamped, ::geometry_msgs::TransformStamped>(),
      Installed<ros::PoseStamped, ::geometry_msgs::PoseStamped>(),
      Installed<ros::PoseWithCovarianceStamped, ::geometry_msgs::PoseWithCovarianceStamped>(),
      Installed<ros::TFMessage, ::tf2_msgs::TFMessage>(),
      Installed<ros::Path, ::nav_msgs::Path>(),
      Installed<ros::Odometry, ::nav_msgs::Odometry>(),
      Installed<ros::Image, ::sensor_msgs::Image>(),
      Installed<ros::RegionOfInterest, ::sensor_msgs::RegionOfInterest>(),
      Installed<ros::CameraInfo, ::sensor_msgs::CameraInfo>(),
      Installed<ros::Imu, ::sensor_msgs::Imu>(),
      Installed<ros::LaserScan, ::sensor_msgs::LaserScan>(),
      Installed<ros::Marker, ::visualization_msgs::Marker>(),
      Installed<ros::MarkerArray, ::visualization_msgs::MarkerArray>(),
  };
}

const char* const kCorridorsimTypes[] = {
    ros::Truth::kType,    ros::WheelOdometry::kType, ros::CameraFrame::kType, ros::CameraSet::kType,
    ros::ImuTruth::kType, ros::ScanTruth::kType,     ros::Event::kType};

// ROS 2's schema of `ros2_type` (ros_schemas.cpp) as a ROS 1 full definition: each section
// converted, std_msgs/Header as ROS 1 has it (with seq).
std::string Ros1DefinitionFromRos2Schema(const std::string& ros2_type) {
  const std::string separator(80, '=');
  const std::string schema = ros::Ros2Schema(ros2_type);
  std::string out;
  std::size_t start = 0;
  std::string name;
  while (start <= schema.size()) {
    std::size_t end = schema.find(separator + "\nMSG: ", start);
    if (end == std::string::npos) end = schema.size();
    std::string text = schema.substr(start, end - start);
    if (name == "std_msgs/Header" || (name.empty() && ros2_type == ros::Header::kType)) {
      text = "uint32 seq\ntime stamp\nstring frame_id\n";
    }
    if (!name.empty()) out += separator + "\nMSG: " + name + "\n";
    out += Ros1TextFromRos2(text) + "\n";
    if (end == schema.size()) break;
    const std::size_t name_start = end + separator.size() + 6;
    const std::size_t name_end = schema.find('\n', name_start);
    name = schema.substr(name_start, name_end - name_start);
    start = name_end + 1;
  }
  return out;
}

TEST_CASE("genmsg's MD5 of every installed ROS 1 definition equals the header's MD5", "[record]") {
  for (const InstalledType& type : InstalledTypes()) {
    INFO(type.datatype);
    CHECK(Ros1Md5(type.datatype, type.definition) == type.md5sum);
    // What a bag's connection says of the type: the installed header's, exactly.
    const Ros1Type& bag_type = Ros1TypeOf(type.ros2_type);
    CHECK(bag_type.datatype == type.datatype);
    CHECK(bag_type.md5sum == type.md5sum);
    CHECK(bag_type.definition == type.definition);
  }
  CHECK(Ros1Md5("std_msgs/Header", "uint32 seq\ntime stamp\nstring frame_id\n") ==
        "2176decaecbce78abc3b96ef049fabed");
}

TEST_CASE("our ROS 2 definitions made ROS 1's give ROS 1's MD5 where the field names agree",
          "[record]") {
  for (const InstalledType& type : InstalledTypes()) {
    INFO(type.datatype);
    const std::string generated = Ros1DefinitionFromRos2Schema(type.ros2_type);
    if (type.datatype == "sensor_msgs/CameraInfo" ||
        type.datatype.rfind("visualization_msgs/", 0) == 0) {
      // ROS 2 renamed CameraInfo's D, K, R, P to d, k, r, p and made Marker's constants int32
      // (ROS 1: uint8): the bytes are the same, but names and constants enter the MD5.
      CHECK(Ros1Md5(type.datatype, generated) != type.md5sum);
    } else {
      CHECK(Ros1Md5(type.datatype, generated) == type.md5sum);
    }
  }
}

TEST_CASE("corridorsim_msgs get a ROS 1 definition with the standard messages they use",
          "[record]") {
  for (const char* ros2_type : kCorridorsimTypes) {
    INFO(ros2_type);
    const Ros1Type& type = Ros1TypeOf(ros2_type);
    CHECK(type.datatype == Ros1Name(ros2_type));
    CHECK(type.datatype.rfind("corridorsim_msgs/", 0) == 0);
    CHECK(type.md5sum.size() == 32);
    CHECK(type.md5sum == Ros1Md5(type.datatype, type.definition));
    CHECK((type.definition.rfind("Header header\n", 0) == 0 ||
           type.definition.find("\nHeader header\n") != std::string::npos));
    // The installed std_msgs/Header text (with seq) is embedded, not ROS 2's.
    CHECK(type.definition.find("MSG: std_msgs/Header\n") != std::string::npos);
    CHECK(type.definition.find("uint32 seq") != std::string::npos);
    CHECK(type.definition.find("builtin_interfaces") == std::string::npos);
  }
  const Ros1Type& truth = Ros1TypeOf(ros::Truth::kType);
  CHECK(truth.definition.rfind("uint8 START=0\nuint8 SAMPLE=1\nuint8 END=2\nHeader header\n", 0) ==
        0);
  CHECK(truth.definition.find("MSG: geometry_msgs/Pose\n") != std::string::npos);
  CHECK(truth.definition.find("MSG: geometry_msgs/Quaternion\n") != std::string::npos);
}

TEST_CASE("Ros1Out writes ROS 1's bytes: no alignment, seq first in the message's own header",
          "[record]") {
  ros::CameraSet set;
  set.header.stamp.ns = 1'500'000'000;
  set.header.frame_id = "a";
  set.cameras = {"xy"};
  set.dropped = {true, false};
  Ros1Out out(7);
  out(set);
  const std::vector<std::uint8_t> expected = {7, 0,    0,    0,          // seq
                                              1, 0,    0,    0,          // stamp secs
                                              0, 0x65, 0xCD, 0x1D,       // stamp nsecs 500000000
                                              1, 0,    0,    0,    'a',  // frame_id
                                              1, 0,    0,    0,    2,   0,
                                              0, 0,    'x',  'y',            // cameras
                                              2, 0,    0,    0,    1,   0};  // dropped
  CHECK(out.Take() == expected);

  ros::TFMessage tf;
  tf.transforms.resize(1);
  tf.transforms[0].header.stamp.ns = 3;
  Ros1Out nested(9);
  nested(tf);
  const std::vector<std::uint8_t> bytes = nested.Take();
  REQUIRE(bytes.size() == 4 + 4 + 4 + 4 + 4 + 4 + 7 * 8);
  CHECK(std::vector<std::uint8_t>(bytes.begin() + 4, bytes.begin() + 16) ==
        std::vector<std::uint8_t>{0, 0, 0, 0, 0, 0, 0, 0, 3, 0, 0, 0});  // nested seq 0
  ros::Marker marker;
  marker.lifetime.ns = -1'250'000'000;  // ROS 1's normalized duration: -2 s + 750000000 ns
  Ros1Out duration(0);
  duration(marker.lifetime);
  CHECK(duration.Take() ==
        std::vector<std::uint8_t>{0xFE, 0xFF, 0xFF, 0xFF, 0x80, 0x17, 0xB4, 0x2C});
}

// Gives every field of a message a distinct value (a few elements per sequence).
struct Fill {
  std::int64_t n = 0;
  template <class T>
  requires std::is_arithmetic_v<T>
  void operator()(T& value) {
    ++n;
    if constexpr (std::is_floating_point_v<T>) {
      value = static_cast<T>(n) * static_cast<T>(0.37) - static_cast<T>(3);
    } else if constexpr (std::is_signed_v<T>) {
      value = static_cast<T>((n % 2 == 0 ? 1 : -1) * (n % 100));
    } else {
      value = static_cast<T>(n % 200 + 1);
    }
  }
  void operator()(bool& value) { value = ++n % 2 == 0; }
  void operator()(std::string& value) { value = "s" + std::to_string(++n); }
  void operator()(ros::Time& t) { t.ns = ++n * 1'000'000'007; }
  void operator()(ros::Duration& d) { d.ns = -(++n) * 333'333'333; }
  template <class T, std::size_t N>
  void operator()(std::array<T, N>& values) {
    for (T& value : values) (*this)(value);
  }
  void operator()(std::vector<bool>& values) {
    values.resize(3);
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = ++n % 3 == 0;
  }
  template <class T>
  void operator()(std::vector<T>& values) {
    values.resize(static_cast<std::size_t>(2 + n % 2));
    for (T& value : values) (*this)(value);
  }
  template <ros::Message T>
  void operator()(T& message) {
    ros::VisitFields(*this, message);
  }
};

// Compares a message with python3-rosbag's reading of it (bag_dump.py: fields in order).
struct MatchesBag {
  const nlohmann::json& values;
  std::uint32_t seq = 0;  // the header's, at depth 0
  int depth = 0;
  std::size_t next = 0;

  const nlohmann::json& Next() {
    REQUIRE(values.is_array());
    REQUIRE(next < values.size());
    return values[next++];
  }
  template <class T>
  requires std::is_arithmetic_v<T>
  void operator()(const T& value) {
    const nlohmann::json& j = Next();
    if constexpr (std::is_floating_point_v<T>) {
      CHECK(j.get<double>() == static_cast<double>(value));
    } else {
      CHECK(j.get<T>() == value);
    }
  }
  void operator()(const bool& value) {
    const nlohmann::json& j = Next();
    CHECK((j.is_boolean() ? j.get<bool>() : j.get<int>() != 0) == value);
  }
  void operator()(const std::string& value) { CHECK(Next().get<std::string>() == value); }
  void operator()(const ros::Time& t) { CHECK(Next().get<std::int64_t>() == t.ns); }
  void operator()(const ros::Duration& d) { CHECK(Next().get<std::int64_t>() == d.ns); }
  template <class Container>
  void Elements(const Container& values_in) {
    const nlohmann::json& j = Next();
    REQUIRE(j.is_array());
    REQUIRE(j.size() == values_in.size());
    MatchesBag inner{j, 0, depth + 1};
    for (std::size_t i = 0; i < values_in.size(); ++i) {
      using T = typename Container::value_type;
      inner(static_cast<const T&>(values_in[i]));
    }
  }
  template <class T, std::size_t N>
  void operator()(const std::array<T, N>& values_in) {
    Elements(values_in);
  }
  template <class T>
  void operator()(const std::vector<T>& values_in) {
    Elements(values_in);
  }
  template <ros::Message T>
  void operator()(const T& message) {
    MatchesBag inner{Next(), 0, depth + 1};
    ros::VisitFields(inner, message);
    CHECK(inner.next == inner.values.size());
  }
  void operator()(const ros::Header& header) {
    const nlohmann::json& j = Next();
    REQUIRE(j.size() == 3);
    CHECK(j[0].get<std::uint32_t>() == (depth == 0 ? seq : 0));
    CHECK(j[1].get<std::int64_t>() == header.stamp.ns);
    CHECK(j[2].get<std::string>() == header.frame_id);
  }
};

struct Written {
  std::string topic, ros2_type;
  TimeNs stamp_ns;
  std::uint32_t seq;
  std::function<void(MatchesBag&)> match;
};

template <class T>
void WriteFilled(BagWriter& bag, std::vector<Written>* written, std::int64_t seed,
                 const std::string& topic, TimeNs stamp_ns, std::uint32_t seq) {
  T message;
  Fill fill{seed};
  ros::VisitFields(fill, message);
  bag.Write(topic, stamp_ns, message);
  written->push_back(
      {topic, T::kType, stamp_ns, seq, [message](MatchesBag& m) { ros::VisitFields(m, message); }});
}

template <class... T>
void WriteEach(BagWriter& bag, std::vector<Written>* written) {
  std::int64_t k = 0;
  ((++k,
    WriteFilled<T>(bag, written, 1000 * k, "/" + Ros1Name(T::kType), k * 1'000'000'000 + 7, 0)),
   ...);
}

#ifdef CORRIDORSIM_ROSBAG_PYTHON
TEST_CASE("a bag of every message type reads back equal through python3-rosbag", "[record]") {
  const test::ScratchDir dir("corridorsim_bag_writer");
  const fs::path bag_file = dir.path() / "every_type.bag";
  std::vector<Written> written;
  {
    BagWriter bag(bag_file);
    WriteEach<ros::Vector3, ros::Point, ros::Quaternion, ros::Pose, ros::PoseWithCovariance,
              ros::Twist, ros::TwistWithCovariance, ros::Transform, ros::TransformStamped,
              ros::TFMessage, ros::PoseStamped, ros::PoseWithCovarianceStamped, ros::Path,
              ros::Odometry, ros::Image, ros::RegionOfInterest, ros::CameraInfo, ros::Imu,
              ros::LaserScan, ros::ColorRGBA, ros::Marker, ros::MarkerArray, ros::Truth,
              ros::WheelOdometry, ros::CameraFrame, ros::CameraSet, ros::ImuTruth, ros::ScanTruth,
              ros::Event>(bag, &written);
    // A second and third message on one topic: the header's seq counts them; a stamp of 0 is
    // recorded at 1 ns (ROS 1 has no earlier time), the header's stamp stays 0.
    WriteFilled<ros::Image>(bag, &written, 7, "/sensor_msgs/Image", 0, 1);
    WriteFilled<ros::Image>(bag, &written, 8, "/sensor_msgs/Image", 40'000'000'123, 2);
    bag.Close();
    CHECK(bag.bytes() == fs::file_size(bag_file));
  }
  // rosbag reads in time order.
  std::stable_sort(written.begin(), written.end(), [](const Written& a, const Written& b) {
    return std::max<TimeNs>(a.stamp_ns, 1) < std::max<TimeNs>(b.stamp_ns, 1);
  });
  const fs::path json_file = dir.path() / "every_type.json";
  const ChildStatus status =
      RunChildProcess({CORRIDORSIM_ROSBAG_PYTHON,
                       std::string(CORRIDORSIM_SOURCE_DIR) + "/tests/recordings/bag_dump.py",
                       bag_file.string(), json_file.string()});
  REQUIRE(status.succeeded());
  std::ifstream in(json_file);
  const nlohmann::json read = nlohmann::json::parse(in);
  REQUIRE(read.size() == written.size());
  for (std::size_t i = 0; i < written.size(); ++i) {
    const Written& w = written[i];
    const nlohmann::json& r = read[i];
    INFO(w.topic << " #" << w.seq);
    const Ros1Type& type = Ros1TypeOf(w.ros2_type);
    CHECK(r["topic"] == w.topic);
    CHECK(r["datatype"] == type.datatype);
    CHECK(r["md5sum"] == type.md5sum);
    CHECK(r["genpy_md5sum"] == type.md5sum);  // genmsg's own MD5 of the stored definition
    CHECK(r["time_ns"].get<std::int64_t>() == std::max<TimeNs>(w.stamp_ns, 1));
    MatchesBag match{r["message"], w.seq, 0};
    w.match(match);
    CHECK(match.next == r["message"].size());
  }
}
#endif

TEST_CASE("a bag that cannot be created is a runtime_error naming the file", "[record]") {
  const test::ScratchDir dir("corridorsim_bag_writer_bad");
  const fs::path file = dir.path() / "missing_folder" / "x.bag";
  try {
    BagWriter bag(file);
    FAIL("no error");
  } catch (const std::runtime_error& e) {
    CHECK(std::string(e.what()).find(file.string()) != std::string::npos);
  }
}

}  // namespace
}  // namespace corridorsim::record

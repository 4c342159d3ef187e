#include "harness/record/bag_writer.h"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <mutex>
#include <set>
#include <sstream>
#include <stdexcept>

// ROS 1 (Debian's librosbag-storage-dev and the message headers): only here. The message structs
// of these headers do not compile as C++20 (std::allocator<void>::rebind); only their traits
// (type name, MD5, definition) are used, which never instantiate them.
#include <geometry_msgs/Point.h>
#include <geometry_msgs/Pose.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/PoseWithCovariance.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <geometry_msgs/Quaternion.h>
#include <geometry_msgs/Transform.h>
#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/Twist.h>
#include <geometry_msgs/TwistWithCovariance.h>
#include <geometry_msgs/Vector3.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <rosbag/bag.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/RegionOfInterest.h>
#include <std_msgs/ColorRGBA.h>
#include <std_msgs/Header.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/Marker.h>
#include <visualization_msgs/MarkerArray.h>

#include "common/io/serial_worker.h"

namespace corridorsim::record {

/// A message already in ROS 1's bytes, with its type: what rosbag::Bag::write takes (as
/// topic_tools::ShapeShifter, through the traits below).
struct SerializedMessage {
  const Ros1Type* type = nullptr;
  const std::vector<std::uint8_t>* bytes = nullptr;
};

}  // namespace corridorsim::record

namespace ros::message_traits {
template <>
struct MD5Sum<corridorsim::record::SerializedMessage> {
  static const char* value(const corridorsim::record::SerializedMessage& m) {
    return m.type->md5sum.c_str();
  }
};
template <>
struct DataType<corridorsim::record::SerializedMessage> {
  static const char* value(const corridorsim::record::SerializedMessage& m) {
    return m.type->datatype.c_str();
  }
};
template <>
struct Definition<corridorsim::record::SerializedMessage> {
  static const char* value(const corridorsim::record::SerializedMessage& m) {
    return m.type->definition.c_str();
  }
};
}  // namespace ros::message_traits

namespace ros::serialization {
template <>
struct Serializer<corridorsim::record::SerializedMessage> {
  template <typename Stream>
  static void write(Stream& stream, const corridorsim::record::SerializedMessage& m) {
    if (m.bytes->empty()) return;
    std::memcpy(stream.advance(static_cast<std::uint32_t>(m.bytes->size())), m.bytes->data(),
                m.bytes->size());
  }
  static std::uint32_t serializedLength(const corridorsim::record::SerializedMessage& m) {
    return static_cast<std::uint32_t>(m.bytes->size());
  }
};
}  // namespace ros::serialization

namespace corridorsim::record {
namespace {

// --- MD5 (RFC 1321), for genmsg's message MD5 sums ---

std::string Md5Hex(const std::string& text) {
  static constexpr std::uint32_t kShift[64] = {
      7,  12, 17, 22, 7,  12, 17, 22, 7,  12, 17, 22, 7,  12, 17, 22, 5,  9,  14, 20, 5,  9,
      14, 20, 5,  9,  14, 20, 5,  9,  14, 20, 4,  11, 16, 23, 4,  11, 16, 23, 4,  11, 16, 23,
      4,  11, 16, 23, 6,  10, 15, 21, 6,  10, 15, 21, 6,  10, 15, 21, 6,  10, 15, 21};
  static constexpr std::uint32_t k[64] = {
      0xd76aa478, 0xe8c7b756, 0x242070db, 0xc1bdceee, 0xf57c0faf, 0x4787c62a, 0xa8304613,
      0xfd469501, 0x698098d8, 0x8b44f7af, 0xffff5bb1, 0x895cd7be, 0x6b901122, 0xfd987193,
      0xa679438e, 0x49b40821, 0xf61e2562, 0xc040b340, 0x265e5a51, 0xe9b6c7aa, 0xd62f105d,
      0x02441453, 0xd8a1e681, 0xe7d3fbc8, 0x21e1cde6, 0xc33707d6, 0xf4d50d87, 0x455a14ed,
      0xa9e3e905, 0xfcefa3f8, 0x676f02d9, 0x8d2a4c8a, 0xfffa3942, 0x8771f681, 0x6d9d6122,
      0xfde5380c, 0xa4beea44, 0x4bdecfa9, 0xf6bb4b60, 0xbebfbc70, 0x289b7ec6, 0xeaa127fa,
      0xd4ef3085, 0x04881d05, 0xd9d4d039, 0xe6db99e5, 0x1fa27cf8, 0xc4ac5665, 0xf4292244,
      0x432aff97, 0xab9423a7, 0xfc93a039, 0x655b59c3, 0x8f0ccc92, 0xffeff47d, 0x85845dd1,
      0x6fa87e4f, 0xfe2ce6e0, 0xa3014314, 0x4e0811a1, 0xf7537e82, 0xbd3af235, 0x2ad7d2bb,
      0xeb86d391};
  std::string message = text;
  const std::uint64_t bit_length = static_cast<std::uint64_t>(text.size()) * 8;
  message.push_back(static_cast<char>(0x80));
  while (message.size() % 64 != 56) message.push_back('\0');
  for (int i = 0; i < 8; ++i) message.push_back(static_cast<char>((bit_length >> (8 * i)) & 0xFF));
  std::uint32_t a0 = 0x67452301, b0 = 0xefcdab89, c0 = 0x98badcfe, d0 = 0x10325476;
  for (std::size_t chunk = 0; chunk < message.size(); chunk += 64) {
    std::uint32_t m[16];
    for (int i = 0; i < 16; ++i) {
      m[i] = 0;
      for (int b = 0; b < 4; ++b) {
        m[i] |= static_cast<std::uint32_t>(static_cast<std::uint8_t>(message[chunk + 4 * i + b]))
                << (8 * b);
      }
    }
    std::uint32_t a = a0, b = b0, c = c0, d = d0;
    for (int i = 0; i < 64; ++i) {
      std::uint32_t f;
      int g;
      if (i < 16) {
        f = (b & c) | (~b & d);
        g = i;
      } else if (i < 32) {
        f = (d & b) | (~d & c);
        g = (5 * i + 1) % 16;
      } else if (i < 48) {
        f = b ^ c ^ d;
        g = (3 * i + 5) % 16;
      } else {
        f = c ^ (b | ~d);
        g = (7 * i) % 16;
      }
      f += a + k[i] + m[g];
      a = d;
      d = c;
      c = b;
      b += std::rotl(f, static_cast<int>(kShift[i]));
    }
    a0 += a;
    b0 += b;
    c0 += c;
    d0 += d;
  }
  std::string hex;
  static constexpr char kDigits[] = "0123456789abcdef";
  for (const std::uint32_t word : {a0, b0, c0, d0}) {
    for (int byte = 0; byte < 4; ++byte) {
      const auto v = static_cast<std::uint8_t>(word >> (8 * byte));
      hex.push_back(kDigits[v >> 4]);
      hex.push_back(kDigits[v & 0xF]);
    }
  }
  return hex;
}

// --- ROS 1 message definitions as genmsg reads them (msg_loader.py, gentools.py) ---

const std::string kSeparator(80, '=');

std::string Trim(const std::string& s) {
  const char* space = " \t\r\n\f\v";
  const std::size_t begin = s.find_first_not_of(space);
  if (begin == std::string::npos) return "";
  return s.substr(begin, s.find_last_not_of(space) - begin + 1);
}

std::vector<std::string> SplitLines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) lines.push_back(line);
  if (!text.empty() && text.back() == '\n') lines.push_back("");
  return lines;
}

// A line's words as genmsg splits them: on spaces, each stripped, empty ones dropped.
std::vector<std::string> Words(const std::string& line) {
  std::vector<std::string> words;
  std::size_t start = 0;
  while (start <= line.size()) {
    std::size_t end = line.find(' ', start);
    if (end == std::string::npos) end = line.size();
    const std::string word = Trim(line.substr(start, end - start));
    if (!word.empty()) words.push_back(word);
    start = end + 1;
  }
  return words;
}

bool IsBuiltin(const std::string& type) {
  static const std::set<std::string> builtins = {
      "int8",    "uint8",   "int16",  "uint16", "int32", "uint32", "int64", "uint64",
      "float32", "float64", "string", "bool",   "char",  "byte",   "time",  "duration"};
  return builtins.count(type) > 0;
}

std::string BareType(const std::string& type) { return type.substr(0, type.find('[')); }

struct Ros1Field {
  std::string type;  // package-qualified when it is a message: "std_msgs/Header", "pkg/Name[]"
  std::string name;
};
struct Ros1Spec {
  std::vector<std::string> constants;  // "type NAME=value", as genmsg's MD5 text has them
  std::vector<Ros1Field> fields;
};

Ros1Spec ParseSpec(const std::string& datatype, const std::string& text) {
  const std::string package = datatype.substr(0, datatype.find('/'));
  Ros1Spec spec;
  for (const std::string& line : SplitLines(text)) {
    const std::string clean = Trim(line.substr(0, line.find('#')));
    if (clean.empty()) continue;
    const std::vector<std::string> words = Words(clean);
    if (clean.find('=') != std::string::npos) {
      std::string name, value;
      if (words[0] == "string") {  // everything right of '=' is the value, '#' included
        const std::size_t equals = line.find('=');
        const std::size_t space = line.find(' ') + 1;
        name = line.substr(space, equals > space ? equals - space : 0);
        value = Trim(line.substr(equals + 1));
      } else {
        std::string rest;
        for (std::size_t i = 1; i < words.size(); ++i) rest += (i > 1 ? " " : "") + words[i];
        const std::size_t equals = rest.find('=');
        name = Trim(rest.substr(0, equals));
        value = Trim(rest.substr(equals + 1));
        if (name.empty() || value.empty() || value.find('=') != std::string::npos) {
          throw std::runtime_error(datatype + ": invalid constant '" + line + "'");
        }
      }
      spec.constants.push_back(words[0] + " " + name + "=" + value);
      continue;
    }
    if (words.size() != 2) throw std::runtime_error(datatype + ": invalid field '" + line + "'");
    std::string type = words[0];
    if (type == "Header") {
      type = "std_msgs/Header";
    } else if (type.find('/') == std::string::npos && !IsBuiltin(BareType(type))) {
      type = package + "/" + type;
    }
    spec.fields.push_back({type, words[1]});
  }
  return spec;
}

// A full definition's sections: the top text is `datatype`'s, then each "MSG: pkg/Name" one
// (each section's text as genmsg had it before compute_full_text joined them with a newline).
std::map<std::string, std::string> Sections(const std::string& datatype,
                                            const std::string& full_definition) {
  std::vector<std::pair<std::string, std::vector<std::string>>> sections = {{datatype, {}}};
  bool expect_name = false;
  for (const std::string& line : SplitLines(full_definition)) {
    if (line == kSeparator) {
      expect_name = true;
      continue;
    }
    if (expect_name) {
      expect_name = false;
      if (line.rfind("MSG: ", 0) != 0) {
        throw std::runtime_error(datatype + ": a definition section without 'MSG: '");
      }
      sections.push_back({Trim(line.substr(5)), {}});
      continue;
    }
    sections.back().second.push_back(line);
  }
  std::map<std::string, std::string> texts;
  for (auto& [name, lines] : sections) {
    if (!lines.empty() && lines.back().empty()) lines.pop_back();  // the joining newline
    std::string text;
    for (const std::string& line : lines) text += line + "\n";
    texts.emplace(name, text);
  }
  return texts;
}

std::string Md5Of(const std::string& type, const std::map<std::string, std::string>& sections,
                  std::map<std::string, std::string>* memo, int depth) {
  if (depth > 32) throw std::runtime_error(type + ": message types nested too deep");
  const auto known = memo->find(type);
  if (known != memo->end()) return known->second;
  const auto section = sections.find(type);
  if (section == sections.end()) {
    throw std::runtime_error("the definition lacks " + type + " ('MSG: " + type + "')");
  }
  const Ros1Spec spec = ParseSpec(type, section->second);
  std::string text;
  for (const std::string& constant : spec.constants) text += constant + "\n";
  for (const Ros1Field& field : spec.fields) {
    const std::string bare = BareType(field.type);
    text += (IsBuiltin(bare) ? field.type : Md5Of(bare, sections, memo, depth + 1)) + " " +
            field.name + "\n";
  }
  const std::string md5 = Md5Hex(Trim(text));
  memo->emplace(type, md5);
  return md5;
}

// --- The types of ros_messages.h in ROS 1 ---

template <class M>
Ros1Type FromTraits() {
  return {::ros::message_traits::DataType<M>::value(), ::ros::message_traits::MD5Sum<M>::value(),
          ::ros::message_traits::Definition<M>::value()};
}

// Standard messages: the installed ROS 1 headers' own (by ROS 2 name).
const std::map<std::string, Ros1Type>& StandardTypes() {
  static const std::map<std::string, Ros1Type> types = {
      {ros::Header::kType, FromTraits<::std_msgs::Header>()},
      {ros::ColorRGBA::kType, FromTraits<::std_msgs::ColorRGBA>()},
      {ros::Vector3::kType, FromTraits<::geometry_msgs::Vector3>()},
      {ros::Point::kType, FromTraits<::geometry_msgs::Point>()},
      {ros::Quaternion::kType, FromTraits<::geometry_msgs::Quaternion>()},
      {ros::Pose::kType, FromTraits<::geometry_msgs::Pose>()},
      {ros::PoseWithCovariance::kType, FromTraits<::geometry_msgs::PoseWithCovariance>()},
      {ros::Twist::kType, FromTraits<::geometry_msgs::Twist>()},
      {ros::TwistWithCovariance::kType, FromTraits<::geometry_msgs::TwistWithCovariance>()},
      {ros::Transform::kType, FromTraits<::geometry_msgs::Transform>()},
      {ros::TransformStamped::kType, FromTraits<::geometry_msgs::TransformStamped>()},
      {ros::PoseStamped::kType, FromTraits<::geometry_msgs::PoseStamped>()},
      {ros::PoseWithCovarianceStamped::kType,
       FromTraits<::geometry_msgs::PoseWithCovarianceStamped>()},
      {ros::TFMessage::kType, FromTraits<::tf2_msgs::TFMessage>()},
      {ros::Path::kType, FromTraits<::nav_msgs::Path>()},
      {ros::Odometry::kType, FromTraits<::nav_msgs::Odometry>()},
      {ros::Image::kType, FromTraits<::sensor_msgs::Image>()},
      {ros::RegionOfInterest::kType, FromTraits<::sensor_msgs::RegionOfInterest>()},
      {ros::CameraInfo::kType, FromTraits<::sensor_msgs::CameraInfo>()},
      {ros::Imu::kType, FromTraits<::sensor_msgs::Imu>()},
      {ros::LaserScan::kType, FromTraits<::sensor_msgs::LaserScan>()},
      {ros::Marker::kType, FromTraits<::visualization_msgs::Marker>()},
      {ros::MarkerArray::kType, FromTraits<::visualization_msgs::MarkerArray>()},
  };
  return types;
}

// Every standard message's own text by ROS 1 name, from the installed full definitions.
const std::map<std::string, std::string>& StandardTexts() {
  static const std::map<std::string, std::string> texts = [] {
    std::map<std::string, std::string> all;
    for (const auto& [ros2_type, type] : StandardTypes()) {
      for (auto& [name, text] : Sections(type.datatype, type.definition)) all.emplace(name, text);
    }
    return all;
  }();
  return texts;
}

// A corridorsim_msgs type: its ROS 2 text made ROS 1's, the standard messages it uses as the
// installed headers define them, its MD5 by genmsg's rule.
Ros1Type Generated(const std::string& ros2_type) {
  Ros1Type type;
  type.datatype = Ros1Name(ros2_type);
  const std::string text = Ros1TextFromRos2(ros::Ros2Definition(ros2_type));
  // Dependencies depth first, each once (genmsg's compute_full_text).
  std::vector<std::string> order;
  std::set<std::string> seen = {type.datatype};
  std::map<std::string, std::string> texts = {{type.datatype, text}};
  const auto text_of = [&](const std::string& name) -> std::string {
    const auto standard = StandardTexts().find(name);
    if (standard != StandardTexts().end()) return standard->second;
    const std::string package = name.substr(0, name.find('/'));
    return Ros1TextFromRos2(
        ros::Ros2Definition(package + "/msg/" + name.substr(name.find('/') + 1)));
  };
  const auto visit = [&](const auto& self, const std::string& name) -> void {
    for (const Ros1Field& field : ParseSpec(name, texts.at(name)).fields) {
      const std::string bare = BareType(field.type);
      if (IsBuiltin(bare) || !seen.insert(bare).second) continue;
      order.push_back(bare);
      texts.emplace(bare, text_of(bare));
      self(self, bare);
    }
  };
  visit(visit, type.datatype);
  type.definition = text + "\n";
  for (const std::string& name : order) {
    type.definition += kSeparator + "\nMSG: " + name + "\n" + texts.at(name) + "\n";
  }
  type.definition.pop_back();
  type.md5sum = Ros1Md5(type.datatype, type.definition);
  return type;
}

}  // namespace

std::string Ros1Name(const std::string& ros2_type) {
  const std::size_t slash = ros2_type.find("/msg/");
  CheckOrDie(slash != std::string::npos, "Ros1Name", "a ROS 2 type without /msg/");
  return ros2_type.substr(0, slash) + "/" + ros2_type.substr(slash + 5);
}

std::string Ros1TextFromRos2(const std::string& ros2_text) {
  std::string text;
  for (const std::string& line : SplitLines(ros2_text)) {
    const std::string clean = Trim(line.substr(0, line.find('#')));
    if (clean.empty()) continue;
    if (clean.find('=') != std::string::npos) {
      text += clean + "\n";
      continue;
    }
    const std::vector<std::string> words = Words(clean);
    CheckOrDie(words.size() >= 2, "Ros1TextFromRos2", "a ROS 2 field without a name");
    const std::string bare = BareType(words[0]);
    const std::string array = words[0].substr(bare.size());
    std::string type = bare;
    if (bare == "builtin_interfaces/Time") type = "time";
    if (bare == "builtin_interfaces/Duration") type = "duration";
    if (bare == "std_msgs/Header") type = "Header";
    text += type + array + " " + words[1] + "\n";  // a ROS 2 default value (words[2]) is dropped
  }
  return text;
}

std::string Ros1Md5(const std::string& datatype, const std::string& full_definition) {
  std::map<std::string, std::string> memo;
  return Md5Of(datatype, Sections(datatype, full_definition), &memo, 0);
}

const Ros1Type& Ros1TypeOf(const std::string& ros2_type) {
  const auto standard = StandardTypes().find(ros2_type);
  if (standard != StandardTypes().end()) return standard->second;
  CheckOrDie(ros2_type.rfind("corridorsim_msgs/msg/", 0) == 0, "Ros1TypeOf",
             ("no ROS 1 type for " + ros2_type).c_str());
  static std::mutex mutex;
  static std::map<std::string, Ros1Type> generated;
  const std::lock_guard<std::mutex> lock(mutex);
  auto it = generated.find(ros2_type);
  if (it == generated.end()) it = generated.emplace(ros2_type, Generated(ros2_type)).first;
  return it->second;
}

// --- Ros1Out ---

void Ros1Out::operator()(const ros::Time& t) {
  CheckOrDie(t.ns >= 0 && t.ns / 1'000'000'000 <= 0xFFFFFFFF, "Ros1Out",
             "a stamp outside ROS 1's time (0 to 2^32 s)");
  (*this)(static_cast<std::uint32_t>(t.ns / 1'000'000'000));
  (*this)(static_cast<std::uint32_t>(t.ns % 1'000'000'000));
}

void Ros1Out::operator()(const ros::Duration& d) {
  // ROS 1's normalized duration: nsecs in [0, 1e9), secs carrying the sign.
  TimeNs sec = d.ns / 1'000'000'000;
  TimeNs nsec = d.ns % 1'000'000'000;
  if (nsec < 0) {
    nsec += 1'000'000'000;
    --sec;
  }
  CheckOrDie(sec >= INT32_MIN && sec <= INT32_MAX, "Ros1Out", "a duration beyond 2^31 s");
  (*this)(static_cast<std::int32_t>(sec));
  (*this)(static_cast<std::int32_t>(nsec));
}

// --- BagWriter ---

// The messages queued for the writer's thread: at most this many bytes (in units of 64 KiB).
constexpr std::size_t kQueueUnitBytes = 64 * 1024;
constexpr std::size_t kMaxQueuedUnits = 1024;  // 64 MiB

struct BagWriter::Bag {
  rosbag::Bag bag;                               // used on the worker's thread only, once open
  std::map<std::string, const Ros1Type*> types;  // ROS 2 type -> its ROS 1 description
  bool open = true;
  std::atomic<std::uint64_t> bytes{0};
  SerialWorker worker{kMaxQueuedUnits};
};

BagWriter::BagWriter(const std::filesystem::path& file)
    : bag_(std::make_unique<Bag>()), file_(file) {
  try {
    bag_->bag.open(file.string(), rosbag::bagmode::Write);
    bag_->bag.setCompression(rosbag::compression::LZ4);
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot create the bag " + file.string() + ": " + e.what());
  }
}

BagWriter::~BagWriter() {
  try {
    Close();
  } catch (const std::exception&) {
    // A destructor must not throw; Close() reports a failure when called.
  }
}

void BagWriter::WriteSerialized(const std::string& topic, TimeNs stamp_ns,
                                const std::string& ros2_type, std::vector<std::uint8_t> bytes) {
  CheckOrDie(bag_->open, "BagWriter", "a message written after Close()");
  CheckOrDie(bytes.size() <= 0xFFFFFFFFu, "BagWriter", "a message of 4 GiB or more");
  const Ros1Type*& type = bag_->types[ros2_type];
  if (type == nullptr) type = &Ros1TypeOf(ros2_type);
  ::ros::Time time;
  time.fromNSec(static_cast<std::uint64_t>(std::max<TimeNs>(stamp_ns, 1)));
  const std::size_t units = 1 + bytes.size() / kQueueUnitBytes;
  // std::function needs a copyable job: the bytes travel behind a shared_ptr.
  auto data = std::make_shared<const std::vector<std::uint8_t>>(std::move(bytes));
  Bag* bag = bag_.get();
  bag_->worker.Submit(
      [bag, topic, time, type, data, file = file_] {
        try {
          bag->bag.write(topic, time, SerializedMessage{type, data.get()});
        } catch (const std::exception& e) {
          throw std::runtime_error("cannot write " + topic + " to the bag " + file.string() + ": " +
                                   e.what());
        }
        bag->bytes = bag->bag.getSize();
      },
      std::min(units, kMaxQueuedUnits));
}

void BagWriter::Close() {
  if (!bag_->open) return;
  bag_->open = false;
  bag_->worker.Drain();  // rethrows a write's error
  try {
    bag_->bag.close();
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot close the bag " + file_.string() + ": " + e.what());
  }
  std::error_code error;
  const std::uintmax_t size = std::filesystem::file_size(file_, error);
  if (!error) bag_->bytes = static_cast<std::uint64_t>(size);
}

std::uint64_t BagWriter::bytes() const { return bag_->bytes; }

double BagWriter::busy_seconds() const { return bag_->worker.busy_seconds(); }

}  // namespace corridorsim::record

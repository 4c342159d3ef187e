#pragma once
// `--record-bag`: the recording's topics as a ROS 1 bag (format 2.0, LZ4 chunks) through Debian's
// librosbag-storage (docs/recordings.md). Messages are the structs of ros_messages.h serialized as
// ROS 1 does (Ros1Out); each connection carries the ROS 1 type name, MD5 sum and full definition:
// the installed ROS 1 headers' for the standard messages, generated from ros_schemas.cpp's ROS 2
// text with genmsg's MD5 rule for corridorsim_msgs. Messages are serialized on the caller's thread
// and written (rosbag's LZ4 chunks) on the writer's own, in order. ROS's headers stay in
// bag_writer.cpp.

#include <array>
#include <bit>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "common/error.h"
#include "common/time.h"
#include "harness/record/ros_messages.h"

namespace corridorsim::record {

/// ROS 1 serialization (roscpp_serialization): little-endian, no alignment, strings as a uint32
/// length and their bytes (no NUL), variable arrays as a uint32 count and the elements, fixed
/// arrays as their elements, time as uint32 secs and nsecs, duration as int32 secs and nsecs.
/// std_msgs/Header gains ROS 1's `uint32 seq` first: `seq` for the message's own header, 0 for
/// the headers nested in it (a Path's poses, a MarkerArray's markers, a TFMessage's transforms).
class Ros1Out {
 public:
  explicit Ros1Out(std::uint32_t seq) : seq_(seq) {}

  template <class T>
  requires std::is_arithmetic_v<T>
  void operator()(const T& value) { Append(&value, sizeof(T)); }
  void operator()(const bool& value) { (*this)(static_cast<std::uint8_t>(value ? 1 : 0)); }
  void operator()(const std::string& value) {
    Length(value.size());
    Append(value.data(), value.size());
  }
  void operator()(const ros::Time& t);
  void operator()(const ros::Duration& d);
  template <class T, std::size_t N>
  void operator()(const std::array<T, N>& values) {
    Elements(values);
  }
  template <class T>
  void operator()(const std::vector<T>& values) {
    Length(values.size());
    Elements(values);
  }
  void operator()(const std::span<const std::uint8_t>& bytes) {  // uint8[] of an ImageView
    Length(bytes.size());
    Append(bytes.data(), bytes.size());
  }
  template <ros::Message T>
  void operator()(const T& message) {
    ++depth_;
    ros::VisitFields(*this, message);
    --depth_;
  }
  void operator()(const ros::Header& header) {
    (*this)(depth_ <= 1 ? seq_ : std::uint32_t{0});
    ros::VisitFields(*this, header);
  }

  std::vector<std::uint8_t> Take() { return std::move(data_); }

 private:
  static_assert(std::endian::native == std::endian::little, "ROS 1 serialization is little-endian");
  template <class Container>
  void Elements(const Container& values) {
    using T = typename Container::value_type;
    if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
      Append(values.data(), values.size() * sizeof(T));
    } else {
      for (const auto& value : values) (*this)(static_cast<const T&>(value));
    }
  }
  void Length(std::size_t size) {
    CheckOrDie(size <= 0xFFFFFFFFu, "Ros1Out", "a string or array longer than 2^32 - 1");
    (*this)(static_cast<std::uint32_t>(size));
  }
  void Append(const void* bytes, std::size_t size) {
    const auto* begin = static_cast<const std::uint8_t*>(bytes);
    data_.insert(data_.end(), begin, begin + size);
  }

  std::vector<std::uint8_t> data_;
  std::uint32_t seq_ = 0;
  int depth_ = 0;
};

/// A message type as a ROS 1 bag's connection describes it.
struct Ros1Type {
  std::string datatype;    // "sensor_msgs/Image"
  std::string md5sum;      // 32 lowercase hex digits
  std::string definition;  // message_definition: its text, then each dependency's after "MSG: "
};

/// The ROS 1 description of a type of ros_messages.h, by its ROS 2 name ("sensor_msgs/msg/
/// Image"): the installed headers' traits for standard messages, generated for corridorsim_msgs.
/// Aborts for a type that is not in ros_messages.h (a bug).
const Ros1Type& Ros1TypeOf(const std::string& ros2_type);

/// genmsg's MD5 of `datatype` ("pkg/Name"), given a full ROS 1 definition that holds it and its
/// dependencies (the top text is `datatype`'s): constants first, then the fields, a field of a
/// message type written as that type's MD5 (genmsg's compute_md5_text). Throws std::runtime_error
/// when a type it uses is not in `full_definition`.
std::string Ros1Md5(const std::string& datatype, const std::string& full_definition);

/// ROS 2 definition text (ros_schemas.cpp) in ROS 1's form: builtin_interfaces/Time and Duration
/// as time and duration, std_msgs/Header as Header, ROS 2's default values dropped.
std::string Ros1TextFromRos2(const std::string& ros2_text);

/// "sensor_msgs/msg/Image" -> "sensor_msgs/Image".
std::string Ros1Name(const std::string& ros2_type);

class BagWriter {
 public:
  /// Creates `file` (replacing it). Throws std::runtime_error naming it when it cannot.
  explicit BagWriter(const std::filesystem::path& file);
  ~BagWriter();
  BagWriter(const BagWriter&) = delete;
  BagWriter& operator=(const BagWriter&) = delete;

  /// Appends `message` on `topic` at `stamp_ns` (the bag's record time; ROS 1 has none below
  /// 1 ns, so 0 is written as 1 ns; the header's stamp stays exact). The header's seq counts the
  /// topic's messages from 0. Throws std::runtime_error when the file cannot be written (here or
  /// at a later Write or Close: the writing runs on the writer's thread).
  template <ros::Message T>
  void Write(const std::string& topic, TimeNs stamp_ns, const T& message) {
    Ros1Out out(seq_[topic]++);
    out(message);
    WriteSerialized(topic, stamp_ns, T::kType, out.Take());
  }
  /// Writes what is queued, the index, and closes the file (the destructor does too, silently).
  void Close();
  /// The file's size so far (what the writer's thread wrote; a lower bound until Close()).
  std::uint64_t bytes() const;
  /// Seconds the writer's thread spent writing and compressing.
  double busy_seconds() const;

 private:
  void WriteSerialized(const std::string& topic, TimeNs stamp_ns, const std::string& ros2_type,
                       std::vector<std::uint8_t> bytes);
  struct Bag;
  std::unique_ptr<Bag> bag_;
  std::filesystem::path file_;
  std::map<std::string, std::uint32_t> seq_;  // topic -> the next header seq
};

}  // namespace corridorsim::record

#pragma once
// The lockstep protocol between corridorsim and a pipeline that is a program (docs/protocol.md
// is its specification; python/corridorsim/ is its reference client). This file holds what the
// protocol says, with no I/O: the framing of a message, the messages corridorsim sends, and the
// checks of the replies it reads, each of which names what is wrong so that a failed pipeline's
// record says why.
//
// A message is a 12-byte header, "CSIM" then two little-endian uint32 lengths, a UTF-8 JSON
// object of the first length and binary bytes (a "blob") of the second. Both lengths are checked
// against their bounds before anything is allocated.

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/pose.h"
#include "common/sensor_messages.h"
#include "common/time.h"
#include "harness/external/reply_keys.h"
#include "slam/pipeline.h"

namespace corridorsim::external {

/// The version every client speaks: the `protocol` of the start message (a version-1 client,
/// written to docs/protocol.md version 1, checks it and runs unchanged).
inline constexpr int kProtocolVersion = 1;
/// The newest version corridorsim speaks: the start message's `protocol_max`. A client that
/// speaks it says so in its `ready` reply (`"protocol": 2`), and only then gets the IMU and scanner
/// messages it asks for and may declare measurement types of its own.
inline constexpr int kProtocolMaxVersion = 2;
inline constexpr char kMagic[4] = {'C', 'S', 'I', 'M'};
inline constexpr std::size_t kHeaderBytes = 12;
/// A message's JSON at most (a finish reply with many landmarks and their points fits).
inline constexpr std::uint32_t kMaxJsonBytes = 64u << 20;
/// A message's blob at most (a reply's map files, a camera set's inline images).
inline constexpr std::uint32_t kMaxBlobBytes = 512u << 20;
/// Counts a reply may carry at most: detections or innovations in one reply, landmarks, points of
/// a landmark, map files, stage names.
inline constexpr std::size_t kMaxReplyItems = 1'000'000;
inline constexpr std::size_t kMaxLandmarkPoints = 64;
inline constexpr std::size_t kMaxMapFiles = 64;
inline constexpr std::size_t kMaxStages = 64;

/// A reply that breaks the protocol: the program's bug. The text says what and where
/// ("estimate reply: covariance: expected 9 finite numbers").
class ProtocolError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Header {
  std::uint32_t json_bytes = 0;
  std::uint32_t blob_bytes = 0;
};
/// The 12 header bytes of a message.
std::string EncodeHeader(std::size_t json_bytes, std::size_t blob_bytes);
/// Reads a header; throws ProtocolError for a wrong magic or a length over its bound.
Header DecodeHeader(const char (&bytes)[kHeaderBytes]);

/// Parses a message's JSON: a JSON object (no NaN or Infinity; nesting and values within
/// common/io/json_input.h's kMaxJsonDepth and kMaxJsonValues) whose "type" is a string. Throws
/// ProtocolError.
nlohmann::json ParseMessage(std::string_view json);

// ---- What corridorsim sends ----------------------------------------------------------------

/// Where one image of a camera set lies: in the shared memory, or in the message's blob.
struct ImageSlice {
  std::string encoding;  // "rgb8" (3 bytes per pixel, R G B) or "depth_f32" (float32 metres, 0 =
                         // invalid), row-major, row 0 on top, no padding
  int width = 0;
  int height = 0;
  std::size_t offset = 0;  // bytes from the start of the shared memory or of the blob
  std::size_t bytes = 0;
};
/// One camera of a camera set as it is sent.
struct CameraSlice {
  std::string camera;
  bool dropped = false;  // the frame due was lost (sensors.<camera>.drop_probability)
  TimeNs stamp_ns = 0;
  std::optional<ImageSlice> rgb, depth;
};

/// The start message: the protocol version, the calibration, the start pose and stamp, the
/// options from the scenario (as given, typed), the run's seed for this pipeline, the cameras it
/// reads and the shared memory (bytes; 0: images travel inline).
/// (Messages keep their keys in the order docs/protocol.md lists them.)
nlohmann::ordered_json StartMessage(const std::string& pipeline,
                                    const slam::Calibration& calibration,
                                    const std::vector<std::string>& cameras, TimeNs stamp_ns,
                                    const SE2& world_from_robot,
                                    const nlohmann::ordered_json& options, std::uint64_t seed,
                                    std::size_t shared_memory_bytes);
nlohmann::ordered_json OdometryMessage(const WheelOdometry& odometry);
nlohmann::ordered_json CamerasMessage(TimeNs stamp_ns, const std::vector<CameraSlice>& cameras,
                                      const std::string& transport);
nlohmann::ordered_json FinishMessage(TimeNs stamp_ns);
/// Version 2: the IMU samples since the last message (those between two odometry messages, or up
/// to a sweep or a camera set), in bus order: {"type": "imu", "stamp_ns": the last sample's,
/// "samples": [{"stamp_ns", "sensor", "angular_velocity_rad_s", "linear_acceleration_m_s2"}]}
/// (slam::ImuSample). One message a batch: a 1 kHz IMU in single-sample messages costs more round
/// trips than the rest of a camera-less run (docs/protocol.md, "Cost").
nlohmann::ordered_json ImuMessage(const std::vector<ImuSample>& samples);
/// Samples in one imu message at most (a batch is sent once it holds this many).
inline constexpr std::size_t kMaxImuBatch = 10000;
/// Version 2: one sweep (slam::LaserScan) whose ranges are float32 little-endian in the blob at
/// `ranges_offset` (REP 117's +-inf and NaN as their IEEE values: JSON has none). ScanBlob gives
/// those bytes.
nlohmann::ordered_json ScanMessage(const LaserScan& scan, std::size_t ranges_offset);
std::string ScanBlob(const LaserScan& scan);

/// The calibration as the start message carries it.
nlohmann::ordered_json CalibrationJson(const slam::Calibration& calibration);

// ---- What corridorsim reads back -----------------------------------------------------------
//
// Each reader takes an optional `problems`. Without it, anything wrong throws ProtocolError.
// With it, an unknown top-level key does not throw: what the reply holds under its valid keys is
// read and returned, and the key goes into `problems` (reply_keys.h: an error when the results
// may be incomplete, a warning when the key misspells one that carries no result); the caller
// keeps the results, then fails the pipeline on an error. A missing or malformed required value
// still throws.

/// Detections and innovations a reply may carry (every reply may).
struct ReplyExtras {
  std::vector<slam::Detection> detections;
  std::vector<slam::Innovation> innovations;
};

/// The reply to start: {"type": "ready"} (and, optionally, "name" and "version" of the program,
/// at most 200 bytes each). Version 2 (`"protocol": 2`) adds what the program wants: "imus" and
/// "lasers" (the sensors it reads, by id: of `offered`, each once; only those are sent) and
/// "measurement_types" ([{"name", "dof"}], checked by slam::MeasurementTypesProblem). These keys
/// in a version-1 reply, a version other than 1 and 2, an unknown sensor or a bad declaration
/// throw ProtocolError.
struct Ready {
  std::string name, version;
  int protocol = kProtocolVersion;
  std::vector<std::string> imus, lasers;
  std::vector<slam::MeasurementType> measurement_types;
};
/// The sensors the start message offered (the calibration's IMUs and scanners).
struct OfferedSensors {
  std::vector<std::string> imus, lasers;
};
OfferedSensors Offered(const slam::Calibration& calibration);
Ready ParseReady(const nlohmann::json& reply, ReplyProblems* problems = nullptr,
                 const OfferedSensors& offered = {});

// Innovations and detections name their type: a shipped landmark type (slam::LandmarkType), or
// a measurement type the program declared in `ready` (`declared`: then slam::Innovation's and
// Detection's `measurement`). Any other name fails, naming the declared ones.

/// The reply to odometry: {"type": "estimate", "stamp_ns": the message's, "pose": [x, y, yaw],
/// "covariance": 9 numbers row-major over (x, y, yaw)}, every number finite. A stamp other than
/// the message's is out of order.
slam::PoseEstimate ParseEstimate(const nlohmann::json& reply, TimeNs expected_stamp_ns,
                                 ReplyExtras* extras, ReplyProblems* problems = nullptr,
                                 const std::vector<slam::MeasurementType>& declared = {});

/// The reply to a camera set: {"type": "processed", "stamp_ns": the set's}, with optional
/// "detections" (each of one of `cameras`) and "innovations". Version 2's `imu` and `scan`
/// messages get the same reply, with `cameras` empty: innovations only.
void ParseProcessed(const nlohmann::json& reply, TimeNs expected_stamp_ns,
                    const std::vector<std::string>& cameras, ReplyExtras* extras,
                    ReplyProblems* problems = nullptr,
                    const std::vector<slam::MeasurementType>& declared = {});

/// The reply to finish: {"type": "finished"} with optional "landmarks", "detections",
/// "innovations", "maps" ([{"suffix", "offset", "bytes"}] into the blob), "health" and
/// "stage_seconds". With `problems`, each of these parts is read on its own: a bad one (an unknown
/// key in a landmark, a map outside the blob) is an error in `problems` and costs only itself
/// (and the items after the bad one in its list).
struct Finished {
  std::vector<slam::LandmarkEstimate> landmarks;
  ReplyExtras extras;
  std::vector<slam::MapFile> maps;
  slam::PipelineHealth health;
  std::map<std::string, double> stage_seconds;
};
Finished ParseFinished(const nlohmann::json& reply, std::string_view blob, TimeNs stamp_ns,
                       const std::vector<std::string>& cameras, ReplyProblems* problems = nullptr,
                       const std::vector<slam::MeasurementType>& declared = {});

/// The "type" of a message (ParseMessage checked it is a string).
std::string MessageType(const nlohmann::json& message);
std::string MessageType(const nlohmann::ordered_json& message);

}  // namespace corridorsim::external

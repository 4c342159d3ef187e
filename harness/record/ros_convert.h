#pragma once
// corridorsim's messages as ROS messages and back (docs/recordings.md). The way back is exact:
// every number a run's consumers read comes back bit for bit (poses keep their stored quaternion:
// SE3::FromStored), so a replayed run writes the live run's files byte for byte. The `From*`
// functions check what they read (encodings, sizes, counts) and throw CdrError naming `what`.

#include <cstdint>
#include <string>
#include <vector>

#include "common/camera_models.h"
#include "common/image.h"
#include "common/pose.h"
#include "common/sensor_messages.h"
#include "harness/record/ros_messages.h"
#include "sim/simulation.h"

namespace corridorsim::ros {

Pose ToPose(const SE3& pose);
SE3 FromPose(const Pose& pose);
Transform ToTransform(const SE3& pose);
TransformStamped ToTransformStamped(TimeNs stamp_ns, const std::string& parent,
                                    const std::string& child, const SE3& parent_from_child);
Vector3 ToVector3(const Eigen::Vector3d& v);
Eigen::Vector3d FromVector3(const Vector3& v);

/// Images: rgb8, 32FC1 (metres), mono8 (semantic classes), instance ids as 16UC1 when every id
/// fits in 16 bits (else 32SC1); row 0 on top. A view's pixels are the frame's: it lives as long.
ImageView ViewRgbImage(TimeNs stamp_ns, const std::string& frame_id, const Image8& rgb);
ImageView ViewFloatImage(TimeNs stamp_ns, const std::string& frame_id, const ImageF& image);
/// `narrow`: where the 16-bit ids are put (its memory is the view's).
ImageView ViewLabelImage(TimeNs stamp_ns, const std::string& frame_id, int width, int height,
                         const std::vector<std::uint32_t>& instance,
                         std::vector<std::uint16_t>* narrow);
ImageView ViewMono8Image(TimeNs stamp_ns, const std::string& frame_id, int width, int height,
                         const std::vector<std::uint8_t>& values);
/// Owning copies (tests, tools).
Image ToRgbImage(TimeNs stamp_ns, const std::string& frame_id, const Image8& rgb);
Image ToFloatImage(TimeNs stamp_ns, const std::string& frame_id, const ImageF& image);
Image8 FromRgbImage(const Image& image, const std::string& what);
Image8 FromRgbImage(const ImageView& image, const std::string& what);
ImageF FromFloatImage(const Image& image, const std::string& what);
ImageF FromFloatImage(const ImageView& image, const std::string& what);
std::vector<std::uint32_t> FromLabelImage(const Image& image, const std::string& what);
std::vector<std::uint32_t> FromLabelImage(const ImageView& image, const std::string& what);
std::vector<std::uint8_t> FromMono8Image(const Image& image, const std::string& what);
std::vector<std::uint8_t> FromMono8Image(const ImageView& image, const std::string& what);

/// The camera's intrinsics (plumb_bob for the pinhole, equidistant for Kannala-Brandt; P without
/// rectification: K with a zero column).
CameraInfo ToCameraInfo(TimeNs stamp_ns, const std::string& frame_id, const CameraModel& model);

Truth ToTruth(const sim::TruthSample& truth, std::uint8_t kind);
sim::TruthSample FromTruth(const Truth& truth);

WheelOdometry ToWheelOdometry(const ::corridorsim::WheelOdometry& odometry);
::corridorsim::WheelOdometry FromWheelOdometry(const WheelOdometry& odometry);

/// An IMU sample as sensor_msgs/Imu (no orientation: covariance[0] = -1, REP 145; the noise's
/// variances on the diagonals when known, else 0) and its truth.
Imu ToImu(const ImuSample& sample, const std::string& frame_id, double gyroscope_variance,
          double accelerometer_variance);
ImuTruth ToImuTruth(const sim::ImuMessage& message, const std::string& frame_id);
sim::ImuMessage FromImu(const Imu& imu, const ImuTruth& truth, std::size_t index,
                        const std::string& sensor_id, const std::string& what);

LaserScan ToLaserScan(const ::corridorsim::LaserScan& scan, const std::string& frame_id);
ScanTruth ToScanTruth(const sim::ScanMessage& message, const std::string& frame_id);
sim::ScanMessage FromScan(const LaserScan& scan, const ScanTruth& truth, std::size_t index,
                          const std::string& sensor_id, const std::string& what);

Event ToEvent(const sim::Event& event);
sim::Event FromEvent(const Event& event, const std::string& what);

}  // namespace corridorsim::ros

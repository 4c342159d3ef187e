#pragma once
// The dataset export (`corridorsim run --export DIR`): a run written in the layouts other SLAM
// systems read (docs/export.md describes every file):
//   tum_rgbd/        the front camera as TUM RGB-D (rgb/, depth/ from the noisy depth, rgb.txt,
//                    depth.txt, associations.txt, groundtruth.txt of world_from_camera), an
//                    ORB-SLAM2/3 settings file (orb_slam.yaml) and sensor.yaml as EuRoC's;
//   euroc/mav0/      the upward camera as cam0/, the lateral camera as cam1/ and the scenario's
//                    other cameras as cam2/, cam3/, ... in the rig's order (EuRoC/ASL:
//                    data/<t_ns>.png, data.csv, sensor.yaml; depth/<t_ns>.png for a depth
//                    camera), cameras.yaml (cam<N> -> camera name) when there is a cam2 or
//                    beyond, and state_groundtruth_estimate0/;
//   every camera's sensor.yaml carries its extrinsics (T_BS, body_from_sensor) and the body's
//   start pose in frame W (T_WB_start: the ground truth's first pose; export_yaml.h);
//   odometry.csv     the wheel odometry messages;
//   labels/<camera>/ per frame: 16-bit labels (as EncodeLabels) and the frame truth as JSON;
//   coco/plates.json door plate boxes and room numbers of the front and lateral images.
// Timestamps are int64 nanoseconds in every file name; TUM files give seconds with nine
// decimals formatted from the integer. Images are written as frames arrive, index files and
// YAMLs once in Finish(); every file is written atomically and none twice. Cameras that are
// disabled, or whose messages carry no images, write nothing.

#include <cstddef>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "common/pose.h"
#include "common/sensor_messages.h"
#include "common/time.h"
#include "harness/run/export_yaml.h"
#include "render/camera_rig.h"
#include "sim/simulation.h"

namespace corridorsim {

class DatasetExporter {
 public:
  /// Creates `dir` (and its parents) and checks it is writable. Throws std::runtime_error naming
  /// the folder when it cannot, or when `dir` already holds a file or folder the export writes
  /// (an export never mixes with an earlier one). `rig` gives each camera's model, mount and rate;
  /// `wheelbase_m` is the nominal wheelbase the odometry is meant for.
  DatasetExporter(const std::filesystem::path& dir, const render::RigOptions& rig,
                  double wheelbase_m);

  /// Writes the frame's images, labels and truth JSON (and keeps what the index files need). A
  /// message without images (the simulation did not render) writes nothing. Throws
  /// std::invalid_argument for a camera the rig does not enable, images of the wrong size, a
  /// negative stamp or one not after the camera's previous frame.
  void AddFrame(const sim::CameraMessage& message, const std::string& camera_id);
  /// One odometry message; stamps must increase (std::invalid_argument otherwise).
  void AddOdometry(const WheelOdometry& odometry);
  /// The robot's true pose (body frame R) at `stamp_ns`; stamps must increase. `biases`: the
  /// first IMU's true gyroscope and accelerometer biases in its own frame at its latest sample
  /// (state_groundtruth_estimate0's b_w and b_a; zero without an IMU).
  void AddTruth(TimeNs stamp_ns, const SE3& world_from_robot,
                const Eigen::Matrix<double, 6, 1>& biases = Eigen::Matrix<double, 6, 1>::Zero());
  /// Writes the index files, YAMLs, ground truth, odometry CSV and COCO JSON. Adding anything
  /// or finishing again afterwards throws std::logic_error.
  void Finish();

  /// Whether the front camera has written a frame (tum_rgbd/ exists): where TUM RGB-D's
  /// accelerometer.txt goes (harness/run/export_imu.h).
  bool has_tum() const;

  /// The EuRoC folder number N (euroc/mav0/cam<N>/) of camera `camera_id` of `rig`: 0 for
  /// upward, 1 for lateral, and 2, 3, ... for the rig's other cameras after front, lateral and
  /// upward, in the rig's order (the scenario's order of names), disabled ones counted so that a
  /// camera keeps its number whichever others are enabled; -1 for front (TUM RGB-D) and for a
  /// name the rig does not have.
  static int EurocCameraNumber(const render::RigOptions& rig, const std::string& camera_id);

 private:
  enum class Layout { kTumRgbd, kEuroc };
  struct PlateBox {
    int plate_id = 0;
    std::string room_number;
    double x = 0, y = 0, w = 0, h = 0;  // COCO bbox: pixel edges, (0, 0) = top-left image corner
    double visible_fraction = 0;
    bool fully_in_image = false;
  };
  struct CocoImage {
    TimeNs stamp_ns = 0;
    std::size_t camera_order = 0;  // in the rig
    std::string file_name;         // relative to the export root
    int width = 0, height = 0;
    std::vector<PlateBox> plates;
  };
  struct CameraOutput {
    render::CameraOptions options;
    std::size_t order = 0;  // in the rig
    Layout layout = Layout::kEuroc;
    int euroc_number = -1;            // kEuroc: N of euroc/mav0/cam<N>/
    std::filesystem::path image_dir;  // where the RGB images go (relative to the root)
    std::filesystem::path depth_dir;  // where the noisy depth goes (depth cameras)
    std::vector<TimeNs> stamps;       // of the frames written, increasing
    std::vector<std::pair<TimeNs, SE3>> world_from_camera;  // front camera: per frame
    std::pair<TimeNs, SE3> first_world_from_robot;          // the robot at the first frame
  };

  CameraOutput& Camera(const std::string& camera_id);
  void MakeDir(const std::filesystem::path& relative) const;
  void CheckOpen(const char* what) const;
  BodyStart StartOf(const CameraOutput& camera) const;
  void FinishTum(const CameraOutput& camera) const;
  void FinishEuroc(const CameraOutput& camera) const;
  void FinishEurocCameraList() const;
  void FinishGroundTruth() const;
  void FinishOdometry() const;
  void FinishCoco() const;

  std::filesystem::path dir_;
  double wheelbase_m_;
  std::vector<CameraOutput> cameras_;          // the rig's enabled cameras, in rig order
  std::vector<std::pair<TimeNs, SE3>> truth_;  // world_from_robot
  std::vector<Eigen::Matrix<double, 6, 1>> truth_biases_;  // per truth_ row: b_w, b_a
  std::vector<WheelOdometry> odometry_;
  std::vector<CocoImage> coco_images_;
  bool finished_ = false;
};

}  // namespace corridorsim

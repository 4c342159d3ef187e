#include "harness/run/sensor_recorder.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <utility>

#include "common/io/atomic_file.h"
#include "harness/run/export_yaml.h"
#include "harness/run/run_io.h"

namespace corridorsim {
namespace {

// One more column of a row (run_io.h: CsvNumber).
void Append(std::string* row, double v) { *row += "," + CsvNumber(v); }

void AppendVector(std::string* row, const Eigen::Vector3d& v) {
  for (int i = 0; i < 3; ++i) Append(row, v[i]);
}

void AppendPose(std::string* row, const SE3& pose) {
  AppendVector(row, pose.translation());
  const Eigen::Quaterniond& q = pose.quaternion();
  for (const double c : {q.x(), q.y(), q.z(), q.w()}) Append(row, c);
}

std::string BeamColumns(const char* prefix, std::size_t beams) {
  std::string s;
  for (std::size_t i = 0; i < beams; ++i) s += "," + std::string(prefix) + std::to_string(i);
  return s;
}

}  // namespace

constexpr const char* kImuHeader =
    "t,wx_rad_s,wy_rad_s,wz_rad_s,ax_m_s2,ay_m_s2,az_m_s2,true_wx_rad_s,true_wy_rad_s,"
    "true_wz_rad_s,true_ax_m_s2,true_ay_m_s2,true_az_m_s2,bias_wx_rad_s,bias_wy_rad_s,"
    "bias_wz_rad_s,bias_ax_m_s2,bias_ay_m_s2,bias_az_m_s2,x_m,y_m,z_m,qx,qy,qz,qw,vx_m_s,vy_m_s,"
    "vz_m_s\n";

SensorRecorder::SensorRecorder(const std::vector<sim::ImuOptions>& imus,
                               const std::vector<sim::LaserOptions>& lasers,
                               const std::filesystem::path& folder)
    : dir_(folder / "sensors") {
  for (const sim::LaserOptions& l : lasers) {
    if (l.enabled) lasers_.push_back(l);
  }
  const bool any = !lasers_.empty() ||
                   std::any_of(imus.begin(), imus.end(), [](const auto& i) { return i.enabled; });
  if (!any) return;
  std::filesystem::create_directories(dir_);
  for (const sim::ImuOptions& imu : imus) {
    if (!imu.enabled) continue;
    Open(imu_, imu.id + "_imu.csv").out << kImuHeader;
    WriteFileAtomic(dir_ / (imu.id + "_imu.yaml"), ImuSensorYaml(imu));
  }
  for (const sim::LaserOptions& l : lasers_) {
    Open(scans_, l.id + "_scans.csv");
    Open(truth_, l.id + "_scans_truth.csv");
    Open(hits_, l.id + "_scans_hits.csv");
  }
}

SensorRecorder::~SensorRecorder() = default;

SensorRecorder::File& SensorRecorder::Open(std::vector<std::unique_ptr<File>>& into,
                                           const std::string& name) {
  File& f = *into.emplace_back(std::make_unique<File>());
  f.path = dir_ / name;
  f.out.open(f.path, std::ios::binary);
  return f;
}

void SensorRecorder::OnImu(const sim::ImuMessage& m) {
  std::string row = StampSeconds(m.sample.stamp_ns);
  AppendVector(&row, m.sample.angular_velocity_rad_s);
  AppendVector(&row, m.sample.linear_acceleration_m_s2);
  AppendVector(&row, m.exact.angular_velocity_rad_s);
  AppendVector(&row, m.exact.linear_acceleration_m_s2);
  AppendVector(&row, m.gyroscope_bias);
  AppendVector(&row, m.accelerometer_bias);
  AppendPose(&row, m.world_from_imu);
  AppendVector(&row, m.velocity_in_world);
  imu_.at(m.imu)->out << row << '\n';
}

void SensorRecorder::OnScan(const sim::ScanMessage& m) {
  const std::size_t k = m.laser;
  const LaserScan& scan = m.scan;
  const std::size_t beams = scan.ranges_m.size();
  if (m.truth.size() != beams || m.world_from_laser.empty()) {
    throw std::logic_error("SensorRecorder: a sweep's truth does not match its beams");
  }
  std::ofstream& scans = scans_.at(k)->out;
  if (scans.tellp() == 0) {  // the first sweep: the headers (the beam count is the scanner's)
    WriteFileAtomic(dir_ / (lasers_.at(k).id + "_laser.yaml"), LaserSensorYaml(lasers_[k], scan));
    scans << "t,angle_min_rad,angle_increment_rad,time_increment_s,scan_time_s,range_min_m,"
             "range_max_m"
          << BeamColumns("r", beams) << '\n';
    truth_[k]->out << "t,first_x_m,first_y_m,first_z_m,first_qx,first_qy,first_qz,first_qw,"
                      "last_x_m,last_y_m,last_z_m,last_qx,last_qy,last_qz,last_qw"
                   << BeamColumns("r", beams) << '\n';
    hits_[k]->out << "t" << BeamColumns("id", beams) << '\n';
  }
  std::string row = StampSeconds(scan.stamp_ns);
  for (const double v :
       {scan.angle_min_rad, scan.angle_increment_rad, ToSeconds(scan.time_increment_ns),
        ToSeconds(scan.scan_time_ns), scan.range_min_m, scan.range_max_m}) {
    Append(&row, v);
  }
  for (const float r : scan.ranges_m) Append(&row, r);
  scans << row << '\n';

  std::string truth = StampSeconds(scan.stamp_ns);
  AppendPose(&truth, m.world_from_laser.front());
  AppendPose(&truth, m.world_from_laser.back());
  std::string hits = StampSeconds(scan.stamp_ns);
  for (const sim::BeamTruth& b : m.truth) {
    Append(&truth, b.range_m);
    hits += "," + std::to_string(b.instance_id);
  }
  truth_[k]->out << truth << '\n';
  hits_[k]->out << hits << '\n';
}

void SensorRecorder::Finish() {
  for (auto* files : {&imu_, &scans_, &truth_, &hits_}) {
    for (const std::unique_ptr<File>& f : *files) {
      f->out.close();
      if (f->out.fail()) {
        throw std::runtime_error("could not write " + f->path.string());
      }
    }
  }
}

}  // namespace corridorsim

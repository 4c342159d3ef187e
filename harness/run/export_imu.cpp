#include "harness/run/export_imu.h"

#include <cstdio>
#include <stdexcept>
#include <string>

#include "common/io/atomic_file.h"
#include "harness/run/export_yaml.h"
#include "harness/run/run_io.h"

namespace corridorsim {

namespace fs = std::filesystem;

struct ImuExport::Imu {
  sim::ImuOptions options;
  fs::path folder;
  std::ofstream csv;
  TimeNs last_ns = -1;
};

namespace {

// Opens `path` for writing, creating its folder; throws naming it when it cannot.
void OpenFile(const fs::path& path, std::ofstream& out) {
  fs::create_directories(path.parent_path());
  out.open(path, std::ios::binary);
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

// Closes `out`; throws naming `path` when it was not written whole.
void CloseFile(const fs::path& path, std::ofstream& out) {
  out.close();
  if (out.fail()) throw std::runtime_error("could not write " + path.string());
}

}  // namespace

ImuExport::ImuExport(const fs::path& dir, const std::vector<sim::ImuOptions>& imus, bool tum) {
  for (const sim::ImuOptions& o : imus) {
    if (!o.enabled) continue;
    auto imu = std::make_unique<Imu>();
    imu->options = o;
    imu->folder = dir / "euroc" / "mav0" / ("imu" + std::to_string(imus_.size()));
    OpenFile(imu->folder / "data.csv", imu->csv);
    imu->csv << "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
                "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n";
    imus_.push_back(std::move(imu));
  }
  if (tum && !imus_.empty()) {
    accelerometer_path_ = dir / "tum_rgbd" / "accelerometer.txt";
    OpenFile(accelerometer_path_, accelerometer_);
    accelerometer_ << "# accelerometer data\n# corridorsim IMU '" << imus_.front()->options.id
                   << "' (euroc/mav0/imu0/): specific force, gravity included, in the IMU's own "
                      "frame (T_BS in its sensor.yaml)\n# timestamp ax ay az\n";
  }
}

ImuExport::~ImuExport() = default;

void ImuExport::Add(std::size_t k, const ImuSample& sample) {
  Imu& imu = *imus_.at(k);
  if (sample.stamp_ns <= imu.last_ns) {
    throw std::invalid_argument("ImuExport: IMU samples out of time order");
  }
  imu.last_ns = sample.stamp_ns;
  char row[256];
  const Eigen::Vector3d& w = sample.angular_velocity_rad_s;
  const Eigen::Vector3d& a = sample.linear_acceleration_m_s2;
  std::snprintf(row, sizeof(row), "%lld,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n",
                static_cast<long long>(sample.stamp_ns), w.x(), w.y(), w.z(), a.x(), a.y(), a.z());
  imu.csv << row;
  if (k == 0 && accelerometer_.is_open()) {
    accelerometer_ << StampSeconds(sample.stamp_ns) << ' ' << CsvNumber(a.x()) << ' '
                   << CsvNumber(a.y()) << ' ' << CsvNumber(a.z()) << '\n';
  }
}

void ImuExport::Finish(bool has_tum) {
  for (const std::unique_ptr<Imu>& imu : imus_) {
    CloseFile(imu->folder / "data.csv", imu->csv);
    WriteFileAtomic(imu->folder / "sensor.yaml", ImuSensorYaml(imu->options));
  }
  if (accelerometer_path_.empty()) return;
  CloseFile(accelerometer_path_, accelerometer_);
  if (!has_tum) {  // no front frame: no sequence for it to stand beside
    fs::remove(accelerometer_path_);
    std::error_code ec;
    fs::remove(accelerometer_path_.parent_path(), ec);  // only when empty
  }
}

struct LaserExport::Laser {
  sim::LaserOptions options;
  fs::path folder;
  std::ofstream csv;
  LaserScan first;  // its first sweep: the geometry of sensor.yaml
  TimeNs last_ns = -1;
  bool any = false;
};

LaserExport::LaserExport(const fs::path& dir, const std::vector<sim::LaserOptions>& lasers) {
  for (const sim::LaserOptions& o : lasers) {
    if (!o.enabled) continue;
    auto laser = std::make_unique<Laser>();
    laser->options = o;
    laser->folder = dir / "euroc" / "mav0" / ("laser" + std::to_string(lasers_.size()));
    lasers_.push_back(std::move(laser));
  }
}

LaserExport::~LaserExport() = default;

void LaserExport::Add(std::size_t k, const LaserScan& scan) {
  Laser& laser = *lasers_.at(k);
  if (!laser.any) {
    OpenFile(laser.folder / "data.csv", laser.csv);
    laser.csv << "#timestamp [ns],angle_min [rad],angle_increment [rad],time_increment [s],"
                 "range_min [m],range_max [m],ranges [m]...\n";
    laser.first = scan;
    laser.any = true;
  } else if (scan.stamp_ns <= laser.last_ns ||
             scan.ranges_m.size() != laser.first.ranges_m.size()) {
    throw std::invalid_argument("LaserExport: " + laser.options.id +
                                ": sweeps out of time order or with another beam count");
  }
  laser.last_ns = scan.stamp_ns;
  std::string row = std::to_string(scan.stamp_ns);
  for (const double v : {scan.angle_min_rad, scan.angle_increment_rad,
                         ToSeconds(scan.time_increment_ns), scan.range_min_m, scan.range_max_m}) {
    row += "," + CsvNumber(v);
  }
  for (const float r : scan.ranges_m) row += "," + CsvNumber(r);
  laser.csv << row << '\n';
}

void LaserExport::Finish() {
  for (const std::unique_ptr<Laser>& laser : lasers_) {
    if (!laser->any) continue;
    CloseFile(laser->folder / "data.csv", laser->csv);
    WriteFileAtomic(laser->folder / "sensor.yaml", LaserSensorYaml(laser->options, laser->first));
  }
}

}  // namespace corridorsim

#include "harness/run/export_imu.h"

#include <cstdio>
#include <stdexcept>
#include <string>

#include "common/io/atomic_file.h"
#include "harness/run/export_yaml.h"

namespace corridorsim {

namespace fs = std::filesystem;

struct ImuExport::Imu {
  sim::ImuOptions options;
  fs::path folder;
  std::ofstream csv;
  TimeNs last_ns = -1;
};

ImuExport::ImuExport(const fs::path& dir, const std::vector<sim::ImuOptions>& imus) {
  for (const sim::ImuOptions& o : imus) {
    if (!o.enabled) continue;
    auto imu = std::make_unique<Imu>();
    imu->options = o;
    imu->folder = dir / "euroc" / "mav0" / ("imu" + std::to_string(imus_.size()));
    fs::create_directories(imu->folder);
    imu->csv.open(imu->folder / "data.csv", std::ios::binary);
    if (!imu->csv) throw std::runtime_error("cannot write " + (imu->folder / "data.csv").string());
    imu->csv << "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
                "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n";
    imus_.push_back(std::move(imu));
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
}

void ImuExport::Finish() {
  for (const std::unique_ptr<Imu>& imu : imus_) {
    imu->csv.close();
    if (imu->csv.fail()) {
      throw std::runtime_error("could not write " + (imu->folder / "data.csv").string());
    }
    WriteFileAtomic(imu->folder / "sensor.yaml", ImuSensorYaml(imu->options));
  }
}

}  // namespace corridorsim

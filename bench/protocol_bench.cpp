// bench_protocol: the cost of the lockstep protocol (docs/protocol.md) as an external pipeline
// pays it: the round trip of one 640 x 480 RGB-D camera set (colour 900 KiB and depth 1.2 MiB,
// copied into the shared memory or sent inline) and of one odometry message, to a program that
// answers at once, and (protocol version 2) of the 20 samples of a 1 kHz IMU between two 50 Hz
// odometry messages (one imu message) with that odometry message, and of one 720-beam laser
// sweep (its ranges as float32 in the blob): what a 1 kHz IMU costs over the protocol. Two
// programs: this benchmark itself as a minimal C++ client (--client: the transport's own cost), and
// the reference Python client (python/corridorsim with a pipeline that does nothing; skipped
// without /usr/bin/python3 and numpy). Reports the median and the 90th percentile of the wall time
// per round trip.
//
//   bench_protocol [--frames N] [--odometry N] [--imu N] [--scans N] [--json FILE]
//
// The figures of this machine are in docs/protocol.md ("Cost").

#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/camera_models.h"
#include "harness/external/external_pipeline.h"
#include "harness/external/protocol.h"

namespace {

namespace ext = corridorsim::external;
using Clock = std::chrono::steady_clock;

// --client: reads each message and answers it at once (no parsing beyond the type and stamp).
int Client() {
  const int fd = 3;
  const auto read_exactly = [fd](char* data, std::size_t n) {
    std::size_t done = 0;
    while (done < n) {
      const ssize_t got = ::recv(fd, data + done, n - done, 0);
      if (got <= 0) return false;
      done += static_cast<std::size_t>(got);
    }
    return true;
  };
  const auto send = [fd](const nlohmann::json& reply) {
    const std::string text = reply.dump();
    const std::string message = ext::EncodeHeader(text.size(), 0) + text;
    return ::send(fd, message.data(), message.size(), MSG_NOSIGNAL) ==
           static_cast<ssize_t>(message.size());
  };
  std::string json, blob;
  for (;;) {
    char header[ext::kHeaderBytes];
    if (!read_exactly(header, sizeof header)) return 0;
    const ext::Header h = ext::DecodeHeader(header);
    json.resize(h.json_bytes);
    blob.resize(h.blob_bytes);
    if (!read_exactly(json.data(), json.size()) || !read_exactly(blob.data(), blob.size()))
      return 1;
    const nlohmann::json message = nlohmann::json::parse(json);
    const std::string type = message.at("type");
    if (type == "start") {
      send({{"type", "ready"}, {"protocol", 2}, {"imus", {"imu0"}}, {"lasers", {"scanner"}}});
    } else if (type == "odometry") {
      send({{"type", "estimate"},
            {"stamp_ns", message.at("stamp_ns")},
            {"pose", {0.0, 0.0, 0.0}},
            {"covariance", {1e-4, 0, 0, 0, 1e-4, 0, 0, 0, 1e-5}}});
    } else if (type == "cameras" || type == "imu" || type == "scan") {
      send({{"type", "processed"}, {"stamp_ns", message.at("stamp_ns")}});
    } else if (type == "finish") {
      send({{"type", "finished"}});
    }
  }
}

struct Figures {
  double median_ms = 0, p90_ms = 0;
};

Figures Summarise(std::vector<double> ms) {
  std::sort(ms.begin(), ms.end());
  return {ms[ms.size() / 2], ms[ms.size() * 9 / 10]};
}

// IMU samples between two odometry messages: 1 kHz against 50 Hz.
constexpr int kSamplesPerOdometry = 20;

struct Counts {
  int frames, odometry, imu, scans;
};

template <class F>
double Milliseconds(F&& call) {
  const Clock::time_point t0 = Clock::now();
  call();
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

void Measure(const std::string& name, const std::vector<std::string>& command,
             ext::ImageTransport transport, const Counts& n, nlohmann::json* out) {
  corridorsim::slam::Calibration calibration{0.381, 0.195, 0, {}, {}, {}};
  // An IMU at 1 kHz and a scanner of 720 beams (0.25 deg over 180 deg) at 40 Hz.
  calibration.imus.push_back({"imu0", corridorsim::SE3(), 1000.0, 1.7e-4, 1.9e-5, 2e-3, 3e-3});
  calibration.lasers.push_back({"scanner", corridorsim::SE3(), 40.0, 720, 0.01});
  corridorsim::slam::CameraCalibration front;
  front.id = "front";
  front.model = corridorsim::PinholeRadTan::FromFov(640, 480, 1.0);
  front.depth = corridorsim::slam::DepthRange{0.5, 8.0};
  calibration.cameras.push_back(front);
  ext::ExternalPipelineOptions options;
  options.command = command;
  options.cameras = {"front"};
  options.transport = transport;
  ext::ExternalPipeline pipeline(options, calibration, 1);
  pipeline.set_name("bench");
  pipeline.Initialize(0, corridorsim::SE2(0, 0, 0));

  corridorsim::slam::CameraInput input;
  input.image.camera_id = "front";
  input.image.image = corridorsim::Image8(640, 480, 3);
  for (std::size_t i = 0; i < input.image.image.data.size(); ++i) {
    input.image.image.data[i] = static_cast<std::uint8_t>(i * 7);
  }
  input.depth = corridorsim::StampedDepth{0, "front", corridorsim::ImageF(640, 480, 2.5f)};
  std::vector<double> frame_ms, odometry_ms, imu_ms, scan_ms;
  corridorsim::TimeNs stamp = 0;
  for (int i = 0; i < n.frames; ++i) {
    stamp += 1000000;
    input.image.stamp_ns = input.depth->stamp_ns = stamp;
    frame_ms.push_back(Milliseconds([&] {
      pipeline.OnCameraSet(stamp, {ext::SetFrame{"front", &input}});
    }));
  }
  for (int i = 0; i < n.odometry; ++i) {
    stamp += 1000000;
    corridorsim::WheelOdometry o;
    o.stamp_ns = stamp;
    o.interval_ns = 1000000;
    o.left_distance_m = 0.001;
    o.right_distance_m = 0.0011;
    odometry_ms.push_back(Milliseconds([&] { pipeline.OnOdometry(o); }));
  }
  // A 1 kHz IMU between 50 Hz odometry messages: 20 samples, sent as one imu message before
  // the odometry message (the imu round trip is this figure less the odometry one); and, to
  // compare, one sample a message (what one message per sample would cost: 20 of these).
  const auto imu_interval = [&](int samples) {
    return Milliseconds([&] {
      for (int k = 0; k < samples; ++k) {
        stamp += 1000000;
        corridorsim::ImuSample sample;
        sample.stamp_ns = stamp;
        sample.sensor_id = "imu0";
        sample.angular_velocity_rad_s = Eigen::Vector3d(0.01, -0.002, 0.3 + 1e-6 * k);
        sample.linear_acceleration_m_s2 = Eigen::Vector3d(0.12, -0.05, 9.81);
        pipeline.OnImu(sample);
      }
      corridorsim::WheelOdometry o;
      o.stamp_ns = stamp;
      o.interval_ns = 1000000 * samples;
      pipeline.OnOdometry(o);
    });
  };
  std::vector<double> imu1_ms;
  for (int i = 0; i < n.imu; ++i) imu_ms.push_back(imu_interval(kSamplesPerOdometry));
  for (int i = 0; i < n.imu; ++i) imu1_ms.push_back(imu_interval(1));
  corridorsim::LaserScan scan;
  scan.sensor_id = "scanner";
  scan.angle_min_rad = -1.5707963;
  scan.angle_increment_rad = 0.0043633;
  scan.time_increment_ns = 17361;
  scan.scan_time_ns = 25000000;
  scan.range_min_m = 0.1;
  scan.range_max_m = 80.0;
  scan.ranges_m.assign(720, 3.25f);
  for (int i = 0; i < n.scans; ++i) {
    stamp += 25000000;
    scan.stamp_ns = stamp;
    scan_ms.push_back(Milliseconds([&] { pipeline.OnScan(scan); }));
  }
  pipeline.Finish();
  const Figures f = Summarise(frame_ms), o = Summarise(odometry_ms), m = Summarise(imu_ms),
                m1 = Summarise(imu1_ms), s = Summarise(scan_ms);
  std::printf(
      "%-30s RGB-D set %6.3f ms (p90 %6.3f)  odometry %6.4f ms (p90 %6.4f)  20 IMU samples + "
      "odometry %6.4f ms (p90 %6.4f)  1 IMU sample + odometry %6.4f ms (p90 %6.4f)  720-beam "
      "sweep %6.4f ms (p90 %6.4f)\n",
      name.c_str(), f.median_ms, f.p90_ms, o.median_ms, o.p90_ms, m.median_ms, m.p90_ms,
      m1.median_ms, m1.p90_ms, s.median_ms, s.p90_ms);
  (*out)[name] = {
      {"frame_round_trip_ms", {{"median", f.median_ms}, {"p90", f.p90_ms}}},
      {"odometry_round_trip_ms", {{"median", o.median_ms}, {"p90", o.p90_ms}}},
      {"imu_20_and_odometry_round_trips_ms", {{"median", m.median_ms}, {"p90", m.p90_ms}}},
      {"imu_1_and_odometry_round_trips_ms", {{"median", m1.median_ms}, {"p90", m1.p90_ms}}},
      {"scan_round_trip_ms", {{"median", s.median_ms}, {"p90", s.p90_ms}}},
      {"frames", n.frames},
      {"odometry_messages", n.odometry},
      {"imu_messages", n.imu},
      {"imu_samples_per_message", kSamplesPerOdometry},
      {"scan_messages", n.scans}};
}

}  // namespace

int main(int argc, char** argv) {
  Counts counts{300, 3000, 1000, 400};
  std::string json_file;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--client") return Client();
    if (a == "--frames" && i + 1 < argc) {
      counts.frames = std::clamp(std::atoi(argv[++i]), 1, 100000);
    } else if (a == "--odometry" && i + 1 < argc) {
      counts.odometry = std::clamp(std::atoi(argv[++i]), 1, 1000000);
    } else if (a == "--imu" && i + 1 < argc) {
      counts.imu = std::clamp(std::atoi(argv[++i]), 1, 1000000);
    } else if (a == "--scans" && i + 1 < argc) {
      counts.scans = std::clamp(std::atoi(argv[++i]), 1, 100000);
    } else if (a == "--json" && i + 1 < argc) {
      json_file = argv[++i];
    } else {
      std::fprintf(stderr,
                   "usage: bench_protocol [--frames N] [--odometry N] [--imu N] [--scans N] "
                   "[--json FILE]\n");
      return 2;
    }
  }
  nlohmann::json out;
  std::printf(
      "bench_protocol: %d camera sets of 640 x 480 RGB-D, %d odometry messages, %d imu messages of "
      "20 samples, %d sweeps of 720 beams\n",
      counts.frames, counts.odometry, counts.imu, counts.scans);
  const std::string self = "/proc/self/exe";
  char exe[4096];
  const ssize_t n = ::readlink(self.c_str(), exe, sizeof exe - 1);
  if (n <= 0) return 1;
  exe[n] = '\0';
  Measure("C++ client, shared memory", {exe, "--client"}, ext::ImageTransport::kSharedMemory,
          counts, &out);
  Measure("C++ client, inline", {exe, "--client"}, ext::ImageTransport::kInline, counts, &out);
  const std::string python = "/usr/bin/python3";
  if (::access(python.c_str(), X_OK) == 0 &&
      std::system("/usr/bin/python3 -c 'import numpy' 2>/dev/null") == 0) {
    const std::string script =
        "import corridorsim\n"
        "class Idle(corridorsim.Pipeline):\n"
        "    imus = lasers = True\n"
        "    def on_cameras(self, frames):\n"
        "        self.pixel = int(frames[0].rgb[0, 0, 0])\n"
        "    def estimate(self):\n"
        "        return ((0.0, 0.0, 0.0), [[1e-4, 0, 0], [0, 1e-4, 0], [0, 0, 1e-5]])\n"
        "corridorsim.serve(Idle)\n";
    Measure("Python client, shared memory", {python, "-c", script},
            ext::ImageTransport::kSharedMemory, counts, &out);
    Measure("Python client, inline", {python, "-c", script}, ext::ImageTransport::kInline, counts,
            &out);
  } else {
    std::printf("(no /usr/bin/python3 with numpy: the Python client is not measured)\n");
  }
  if (!json_file.empty()) std::ofstream(json_file) << out.dump(2) << "\n";
  return 0;
}

// Writes the MCAP file that tests/recordings/read_mcap_test.mjs reads with Foxglove's readers
// (@mcap/core, @foxglove/rosmsg2-serialization): ROS 2 messages encoded here by hand in CDR, so
// that the decoder checks the container and the encoding from outside.
//
//   write_mcap_fixture OUT.mcap none|zstd|lz4
//
// What it writes (read_mcap_test.mjs checks each value):
//   /chatter  std_msgs/msg/String: "hello <i>" for i = 0..kChatter-1
//   /samples  corridorsim_test_msgs/msg/Samples (kSamples of them), message i:
//             values  = [1.5, -2.25, inf, -inf, nan, 1e300, i]
//             blob    = (i + k) mod 256 for k = 0..(100 + i)
//             stamp   = 2^62 + i (int64, beyond a double's exact range)
//             label   = "sample ü <i>"
//   /raw      no schema, "application/octet-stream": 3 bytes {i, 0, 255} (not decoded)
//   metadata  "corridorsim": {scenario: fixture, seed: "7"}; attachment "scenario.yaml"
// Log times go back and forth; chunks hold about 600 bytes (many chunks). Exit 0, or 2 with a
// message on a bad command line.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "common/io/mcap.h"

namespace {

using corridorsim::mcap::Compression;

constexpr int kChatter = 30;
constexpr int kSamples = 20;

// CDR (little endian) after the 4-byte encapsulation header; alignment counts from its end.
class Cdr {
 public:
  Cdr() : bytes_{0x00, 0x01, 0x00, 0x00} {}
  void Align(std::size_t size) {
    while ((bytes_.size() - 4) % size != 0) bytes_.push_back(0);
  }
  void U32(std::uint32_t value) {
    Align(4);
    Raw(&value, 4);
  }
  void I64(std::int64_t value) {
    Align(8);
    Raw(&value, 8);
  }
  void F64(double value) {
    Align(8);
    Raw(&value, 8);
  }
  void String(const std::string& text) {  // length with the NUL, the bytes, the NUL
    U32(static_cast<std::uint32_t>(text.size() + 1));
    Raw(text.data(), text.size());
    bytes_.push_back(0);
  }
  void Raw(const void* data, std::size_t size) {  // the host is little endian (x86-64, arm64)
    const auto* p = static_cast<const std::uint8_t*>(data);
    bytes_.insert(bytes_.end(), p, p + size);
  }
  const std::vector<std::uint8_t>& bytes() const { return bytes_; }

 private:
  std::vector<std::uint8_t> bytes_;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: write_mcap_fixture OUT.mcap none|zstd|lz4\n";
    return 2;
  }
  const std::string name = argv[2];
  corridorsim::mcap::WriterOptions options;
  if (name == "none") {
    options.compression = Compression::kNone;
  } else if (name == "zstd") {
    options.compression = Compression::kZstd;
  } else if (name == "lz4") {
    options.compression = Compression::kLz4;
  } else {
    std::cerr << "write_mcap_fixture: unknown compression '" << name << "' (none, zstd, lz4)\n";
    return 2;
  }
  options.chunk_bytes = 600;
  try {
    corridorsim::mcap::Writer writer(argv[1], options);
    const std::uint16_t string_schema =
        writer.AddSchema("std_msgs/msg/String", "ros2msg", "string data\n");
    const std::uint16_t samples_schema = writer.AddSchema(
        "corridorsim_test_msgs/msg/Samples", "ros2msg",
        "# test values\nfloat64[] values\nuint8[] blob\nint64 stamp\nstring label\n");
    const std::uint16_t chatter = writer.AddChannel(string_schema, "/chatter", "cdr");
    const std::uint16_t samples =
        writer.AddChannel(samples_schema, "/samples", "cdr", {{"offered_qos_profiles", ""}});
    const std::uint16_t raw = writer.AddChannel(0, "/raw", "application/octet-stream");
    writer.AddMetadata("corridorsim", {{"scenario", "fixture"}, {"seed", "7"}});
    const std::string yaml = "seed: 7\n";
    writer.AddAttachment(1, 2, "scenario.yaml", "text/yaml",
                         {reinterpret_cast<const std::uint8_t*>(yaml.data()), yaml.size()});
    const std::uint64_t t0 = 1'700'000'000'000'000'000ull;
    for (int i = 0; i < kChatter; ++i) {
      // Out of order: odd messages are stamped before the even one written before them.
      const std::uint64_t log_time =
          t0 + static_cast<std::uint64_t>(i) * 10'000'000 - (i % 2 == 1 ? 15'000'000 : 0);
      Cdr text;
      text.String("hello " + std::to_string(i));
      writer.Write(chatter, log_time, log_time + 1, text.bytes());
      if (i < kSamples) {
        Cdr sample;
        const std::vector<double> values = {1.5,
                                            -2.25,
                                            std::numeric_limits<double>::infinity(),
                                            -std::numeric_limits<double>::infinity(),
                                            std::numeric_limits<double>::quiet_NaN(),
                                            1e300,
                                            static_cast<double>(i)};
        sample.U32(static_cast<std::uint32_t>(values.size()));
        for (const double v : values) sample.F64(v);
        const std::size_t blob_size = 100 + static_cast<std::size_t>(i);
        sample.U32(static_cast<std::uint32_t>(blob_size));
        for (std::size_t k = 0; k < blob_size; ++k) {
          const auto b = static_cast<std::uint8_t>((static_cast<std::size_t>(i) + k) % 256);
          sample.Raw(&b, 1);
        }
        sample.I64((std::int64_t{1} << 62) + i);
        sample.String("sample \xc3\xbc " + std::to_string(i));
        writer.Write(samples, log_time + 5, log_time + 6, sample.bytes());
      }
      if (i % 10 == 0) {
        const std::vector<std::uint8_t> bytes = {static_cast<std::uint8_t>(i), 0, 255};
        writer.Write(raw, log_time + 7, log_time + 7, bytes);
      }
    }
    writer.Close();
  } catch (const std::exception& e) {
    std::cerr << "write_mcap_fixture: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

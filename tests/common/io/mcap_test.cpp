// Tests common/io/mcap_writer.cpp and mcap_reader.cpp: what is written reads back (every
// compression, many chunks, log times out of order), the bytes depend only on the calls, a file
// cut anywhere reads up to its last complete chunk, and damaged files fail as RecordingErrors
// naming the record and its offset. tests/recordings/read_mcap_test.mjs reads the same kind of
// file with Foxglove's readers.
#include "common/io/mcap.h"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "common/io/mcap_records.h"
#include "tests/support/scratch_dir.h"

namespace corridorsim::mcap {
namespace {

namespace fs = std::filesystem;

struct WrittenMessage {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::uint64_t log_time_ns = 0;
  std::uint64_t publish_time_ns = 0;
  std::vector<std::uint8_t> data;
  bool operator==(const WrittenMessage&) const = default;
};

std::vector<std::uint8_t> Payload(int i) {
  std::vector<std::uint8_t> data(static_cast<std::size_t>(10 + (i * 37) % 90));
  for (std::size_t k = 0; k < data.size(); ++k) data[k] = static_cast<std::uint8_t>(i * 7 + k);
  return data;
}

const std::vector<std::uint8_t> kAttachmentBytes = {'s', 'e', 'e',  'd', ':',
                                                    ' ', '7', '\n', 0,   255};

// Writes the test recording: two schemas, three channels, `messages` messages whose log times
// go back and forth, a metadata record and an attachment between the chunks. Returns the
// messages as written.
std::vector<WrittenMessage> WriteRecording(const fs::path& file, const WriterOptions& options,
                                           int messages = 300) {
  Writer writer(file, options);
  const std::uint16_t string_schema =
      writer.AddSchema("std_msgs/msg/String", "ros2msg", "string data");
  const std::uint16_t imu_schema =
      writer.AddSchema("sensor_msgs/msg/Imu", "ros2msg", "float64[] values\nuint8[] blob\n");
  const std::uint16_t chatter = writer.AddChannel(string_schema, "/chatter", "cdr");
  const std::uint16_t imu = writer.AddChannel(imu_schema, "/imu", "cdr", {{"frame", "base_link"}});
  std::vector<WrittenMessage> written;
  std::map<std::uint16_t, std::uint32_t> sequences;
  std::uint16_t raw = 0;
  for (int i = 0; i < messages; ++i) {
    if (i == messages / 3) {
      raw = writer.AddChannel(0, "/raw", "application/octet-stream");  // no schema
      writer.AddMetadata("corridorsim", {{"scenario", "corridor"}, {"seed", "7"}});
      writer.AddAttachment(5, 6, "scenario.yaml", "text/yaml", kAttachmentBytes);
    }
    const std::uint16_t channel = i % 3 == 0 ? chatter : (i % 3 == 1 || raw == 0 ? imu : raw);
    // Out of order: every fourth message steps back in time.
    const std::uint64_t log_time =
        1'000'000'000ull + static_cast<std::uint64_t>(i) * 1000 - (i % 4 == 3 ? 2500 : 0);
    WrittenMessage message{channel, sequences[channel]++, log_time, log_time + 17, Payload(i)};
    writer.Write(channel, message.log_time_ns, message.publish_time_ns, message.data);
    written.push_back(std::move(message));
  }
  writer.AddMetadata("end", {});
  writer.Close();
  CHECK(writer.bytes_written() == fs::file_size(file));
  CHECK(writer.busy_seconds() >= 0.0);
  return written;
}

std::vector<WrittenMessage> ReadAll(const Reader& reader,
                                    const std::vector<std::uint16_t>& channels = {}) {
  std::vector<WrittenMessage> read;
  reader.ForEachMessage(
      [&](const Message& m) {
        read.push_back(WrittenMessage{m.channel_id,
                                      m.sequence,
                                      m.log_time_ns,
                                      m.publish_time_ns,
                                      {m.data.begin(), m.data.end()}});
        return true;
      },
      channels);
  return read;
}

WriterOptions SmallChunks(Compression compression) {
  WriterOptions options;
  options.compression = compression;
  options.chunk_bytes = 2000;  // about 25 messages a chunk
  options.max_pending_chunks = 2;
  return options;
}

// Writes `bytes` to `file`, a new file: ext4 flushes a file truncated and rewritten on close
// (auto_da_alloc), which made the thousands of cut and damaged files of these tests take minutes.
void WriteBytes(const fs::path& file, const std::string& bytes) {
  fs::remove(file);
  std::ofstream(file, std::ios::binary).write(bytes.data(), std::ssize(bytes));
}

TEST_CASE("MCAP's CRC-32 is zlib's", "[mcap]") {
  const std::string check = "123456789";  // the CRC catalogue's check input
  CHECK(records::ComputeCrc32(
            {reinterpret_cast<const std::uint8_t*>(check.data()), check.size()}) == 0xCBF43926u);
  CHECK(records::ComputeCrc32({}) == 0u);
  // In pieces of every length, eight bytes at a time or not, the same value.
  std::vector<std::uint8_t> bytes(1000);
  for (std::size_t k = 0; k < bytes.size(); ++k) bytes[k] = static_cast<std::uint8_t>(k * 131 + 7);
  const std::uint32_t whole = records::ComputeCrc32(bytes);
  for (std::size_t piece = 1; piece < 20; ++piece) {
    records::Crc32 crc;
    for (std::size_t k = 0; k < bytes.size(); k += piece) {
      crc.Update(std::span(bytes).subspan(k, std::min(piece, bytes.size() - k)));
    }
    CHECK(crc.value() == whole);
  }
  CHECK(whole == 0x1ED57BB9u);  // zlib.crc32 of the same bytes (Python 3.11)
}

TEST_CASE("an MCAP recording reads back as written, in every compression", "[mcap]") {
  const test::ScratchDir dir("corridorsim_mcap_round_trip");
  const Compression compression =
      GENERATE(Compression::kNone, Compression::kZstd, Compression::kLz4);
  CAPTURE(CompressionName(compression));
  const fs::path file = dir.path() / "run.mcap";
  const std::vector<WrittenMessage> written = WriteRecording(file, SmallChunks(compression));

  const Reader reader(file);
  CHECK_FALSE(reader.truncated());
  CHECK(reader.profile() == "ros2");
  CHECK(reader.library() == "corridorsim");
  REQUIRE(reader.schemas().size() == 2);
  CHECK(reader.schemas().at(1).name == "std_msgs/msg/String");
  CHECK(reader.schemas().at(2).data == "float64[] values\nuint8[] blob\n");
  REQUIRE(reader.channels().size() == 3);
  const Channel* imu = reader.FindChannel("/imu");
  REQUIRE(imu != nullptr);
  CHECK(imu->schema_id == 2);
  CHECK(imu->message_encoding == "cdr");
  CHECK(imu->metadata == std::map<std::string, std::string>{{"frame", "base_link"}});
  CHECK(reader.FindChannel("/raw")->schema_id == 0);
  CHECK(reader.FindChannel("/nothing") == nullptr);

  // File order is the order of the calls (chunks are written in order).
  CHECK(ReadAll(reader) == written);
  std::map<std::uint16_t, std::uint64_t> counts;
  for (const WrittenMessage& m : written) ++counts[m.channel_id];
  CHECK(reader.MessageCounts() == counts);

  std::vector<WrittenMessage> imu_only;
  std::copy_if(written.begin(), written.end(), std::back_inserter(imu_only),
               [&](const WrittenMessage& m) { return m.channel_id == imu->id; });
  CHECK(ReadAll(reader, {imu->id}) == imu_only);

  int seen = 0;
  reader.ForEachMessage([&](const Message&) { return ++seen < 5; });
  CHECK(seen == 5);

  REQUIRE(reader.metadata().size() == 2);
  CHECK(reader.metadata()[0].first == "corridorsim");
  CHECK(reader.metadata()[0].second.at("seed") == "7");
  CHECK(reader.metadata()[1].first == "end");
  const std::optional<Attachment> attachment = reader.ReadAttachment("scenario.yaml");
  REQUIRE(attachment.has_value());
  CHECK(attachment->data == kAttachmentBytes);
  CHECK(attachment->media_type == "text/yaml");
  CHECK(attachment->log_time_ns == 5);
  CHECK(attachment->create_time_ns == 6);
  CHECK_FALSE(reader.ReadAttachment("missing").has_value());
}

TEST_CASE("megabyte messages span LZ4 blocks and zstd windows and read back", "[mcap]") {
  const test::ScratchDir dir("corridorsim_mcap_large");
  const Compression compression =
      GENERATE(Compression::kNone, Compression::kZstd, Compression::kLz4);
  CAPTURE(CompressionName(compression));
  const fs::path file = dir.path() / "large.mcap";
  std::vector<std::vector<std::uint8_t>> payloads;
  std::uint32_t state = 12345;
  for (int i = 0; i < 5; ++i) {
    std::vector<std::uint8_t> data(1'500'000 + static_cast<std::size_t>(i) * 1000);
    for (std::size_t k = 0; k < data.size(); ++k) {
      state = state * 1664525u + 1013904223u;  // half noise, half runs (compressible)
      data[k] = (k / 4096) % 2 == 0 ? static_cast<std::uint8_t>(state >> 24) : 7;
    }
    payloads.push_back(std::move(data));
  }
  WriterOptions options;  // the default 4 MiB chunks: several messages a chunk
  options.compression = compression;
  {
    Writer writer(file, options);
    const std::uint16_t channel = writer.AddChannel(0, "/camera", "application/octet-stream");
    for (std::size_t i = 0; i < payloads.size(); ++i)
      writer.Write(channel, 100 - i, i, payloads[i]);
    writer.Close();
  }
  const Reader reader(file);
  std::size_t i = 0;
  std::set<std::uint64_t> chunks;
  reader.ForEachMessage([&](const Message& m) {
    REQUIRE(i < payloads.size());
    CHECK(std::equal(m.data.begin(), m.data.end(), payloads[i].begin(), payloads[i].end()));
    CHECK(m.log_time_ns == 100 - i);
    chunks.insert(m.chunk_offset);
    ++i;
    return true;
  });
  CHECK(i == payloads.size());
  CHECK(chunks.size() == 2);
}

TEST_CASE("the same calls give the same MCAP bytes", "[mcap]") {
  const test::ScratchDir dir("corridorsim_mcap_deterministic");
  const Compression compression =
      GENERATE(Compression::kNone, Compression::kZstd, Compression::kLz4);
  WriterOptions first = SmallChunks(compression);
  WriterOptions second = first;
  second.max_pending_chunks = 1;  // a different pace of the worker
  WriteRecording(dir.path() / "a.mcap", first);
  WriteRecording(dir.path() / "b.mcap", second);
  const std::string a = test::FileBytes(dir.path() / "a.mcap");
  CHECK(a.size() > 1000);
  CHECK(a == test::FileBytes(dir.path() / "b.mcap"));
}

// For each message of a complete file in file order, the end of the chunk record holding it.
std::vector<std::uint64_t> MessageChunkEnds(const fs::path& file, const std::string& bytes) {
  std::vector<std::uint64_t> ends;
  const Reader reader(file);
  reader.ForEachMessage([&](const Message& m) {
    std::uint64_t length = 0;
    for (int i = 0; i < 8; ++i) {
      length |= std::uint64_t{static_cast<std::uint8_t>(bytes[m.chunk_offset + 1 + i])} << (8 * i);
    }
    ends.push_back(m.chunk_offset + 9 + length);
    return true;
  });
  return ends;
}

TEST_CASE("a recording cut anywhere reads up to its last complete chunk", "[mcap][slow]") {
  const test::ScratchDir dir("corridorsim_mcap_cut");
  const Compression compression = GENERATE(Compression::kNone, Compression::kZstd);
  CAPTURE(CompressionName(compression));
  const fs::path whole = dir.path() / "whole.mcap";
  const std::vector<WrittenMessage> written = WriteRecording(whole, SmallChunks(compression), 80);
  const std::string bytes = test::FileBytes(whole);
  const std::vector<std::uint64_t> chunk_ends = MessageChunkEnds(whole, bytes);
  REQUIRE(chunk_ends.size() == written.size());
  REQUIRE(chunk_ends.front() < chunk_ends.back());  // several chunks
  const fs::path cut_file = dir.path() / "cut.mcap";
  for (std::size_t cut = 0; cut < bytes.size(); ++cut) {
    CAPTURE(cut);
    WriteBytes(cut_file, bytes.substr(0, cut));
    if (cut < 8 + 9 + 4 + 4 + 4 + 11) {  // the magic and the Header record
      CHECK_THROWS_AS(Reader(cut_file), RecordingError);
      continue;
    }
    const Reader reader(cut_file);
    CHECK(reader.truncated());
    // Exactly the messages of the chunks that end by the cut, in order.
    const auto expected = static_cast<std::size_t>(std::count_if(
        chunk_ends.begin(), chunk_ends.end(), [&](std::uint64_t end) { return end <= cut; }));
    const std::vector<WrittenMessage> read = ReadAll(reader);
    REQUIRE(read.size() == expected);
    CHECK(std::equal(read.begin(), read.end(), written.begin()));
    std::uint64_t counted = 0;
    for (const auto& [id, count] : reader.MessageCounts()) counted += count;
    CHECK(counted == expected);
    if (expected > 0) CHECK(reader.channels().size() >= 2);
  }
}

// Reads everything the reader offers; a RecordingError is the only failure allowed.
void ReadEverything(const fs::path& file) {
  const Reader reader(file);
  reader.ForEachMessage([](const Message&) { return true; });
  reader.MessageCounts();
  reader.ReadAttachment("scenario.yaml");
}

TEST_CASE("every flipped byte of a recording reads or fails as a RecordingError", "[mcap][slow]") {
  const test::ScratchDir dir("corridorsim_mcap_flip");
  const Compression compression =
      GENERATE(Compression::kNone, Compression::kZstd, Compression::kLz4);
  CAPTURE(CompressionName(compression));
  const fs::path whole = dir.path() / "whole.mcap";
  WriteRecording(whole, SmallChunks(compression), 40);
  const std::string bytes = test::FileBytes(whole);
  const fs::path damaged = dir.path() / "damaged.mcap";
  int errors = 0;
  for (std::size_t at = 0; at < bytes.size(); ++at) {
    for (const int mask : {0xFF, 0x01}) {
      CAPTURE(at, mask);
      std::string copy = bytes;
      copy[at] = static_cast<char>(copy[at] ^ mask);
      WriteBytes(damaged, copy);
      try {
        ReadEverything(damaged);
      } catch (const RecordingError& e) {
        ++errors;
        CHECK(std::string(e.what()).find(damaged.string() + ": ") == 0);
        CHECK(e.offset() < bytes.size());
      }
    }
  }
  // Almost every byte is covered by a CRC, a length or a check.
  CHECK(errors > static_cast<int>(bytes.size()));
}

// The offset of the first record with `opcode` after the magic (top-level records only).
std::uint64_t FindRecord(const std::string& bytes, std::uint8_t opcode) {
  std::uint64_t offset = 8;
  while (offset + 9 <= bytes.size()) {
    if (static_cast<std::uint8_t>(bytes[offset]) == opcode) return offset;
    std::uint64_t length = 0;
    for (int i = 0; i < 8; ++i) {
      length |= std::uint64_t{static_cast<std::uint8_t>(bytes[offset + 1 + i])} << (8 * i);
    }
    offset += 9 + length;
  }
  FAIL("no record with opcode " << int{opcode});
  return 0;
}

void PutU64(std::string& bytes, std::uint64_t at, std::uint64_t value) {
  for (int i = 0; i < 8; ++i) bytes[at + i] = static_cast<char>(value >> (8 * i));
}

// Expects reading `bytes` to fail naming `record` at `offset` and saying `what`.
void ExpectError(const fs::path& file, const std::string& bytes, const std::string& record,
                 std::uint64_t offset, const std::string& what) {
  WriteBytes(file, bytes);
  try {
    ReadEverything(file);
    FAIL("no error for " << what);
  } catch (const RecordingError& e) {
    CHECK(e.record() == record);
    CHECK(e.offset() == offset);
    CHECK_THAT(e.what(), Catch::Contains(what));
  }
}

TEST_CASE("damaged chunks fail naming the chunk, its offset and the fault", "[mcap]") {
  const test::ScratchDir dir("corridorsim_mcap_damaged");
  const fs::path whole = dir.path() / "whole.mcap";
  WriteRecording(whole, SmallChunks(Compression::kZstd), 60);
  const std::string bytes = test::FileBytes(whole);
  const fs::path file = dir.path() / "damaged.mcap";
  const std::uint64_t chunk = FindRecord(bytes, 0x06);
  const std::uint64_t fields = chunk + 9;  // start, end, uncompressed size, crc, compression

  std::string huge_length = bytes;
  PutU64(huge_length, chunk + 1, std::uint64_t{1} << 60);
  ExpectError(file, huge_length, "Chunk", chunk, "runs past the end of the data section");

  std::string huge_size = bytes;
  PutU64(huge_size, fields + 16, std::uint64_t{3} << 30);
  ExpectError(file, huge_size, "Chunk", chunk, "exceeds the limit");

  std::string wrong_size = bytes;
  PutU64(wrong_size, fields + 16, 100);
  ExpectError(file, wrong_size, "Chunk", chunk, "zstd");

  std::string bad_crc = bytes;
  bad_crc[fields + 24] = static_cast<char>(bad_crc[fields + 24] ^ 0x55);
  ExpectError(file, bad_crc, "Chunk", chunk, "CRC");

  std::string bz2 = bytes;
  bz2.replace(fields + 32, 4, "bz2x");  // the compression string "zstd"
  ExpectError(file, bz2, "Chunk", chunk, "unknown compression 'bz2x'");

  std::string long_string = bytes;
  PutU64(long_string, fields + 36, std::uint64_t{1} << 40);  // the records' byte length
  ExpectError(file, long_string, "Chunk", chunk, "field records");

  std::string not_mcap = bytes;
  not_mcap[1] = 'X';
  ExpectError(file, not_mcap, "Magic", 0, "not an MCAP file");
}

TEST_CASE("a complete recording without a summary is read by scanning it, unknown records skipped",
          "[mcap]") {
  const test::ScratchDir dir("corridorsim_mcap_no_summary");
  const fs::path whole = dir.path() / "whole.mcap";
  const std::vector<WrittenMessage> written =
      WriteRecording(whole, SmallChunks(Compression::kLz4), 80);
  const std::string bytes = test::FileBytes(whole);
  // The data section up to its DataEnd record with a record of an opcode the spec does not define
  // after the header (readers skip it), then a footer saying "no summary" and the magic.
  const std::uint64_t data_end = FindRecord(bytes, 0x0F);
  const std::size_t header_end = 8 + 9 + 4 + 4 + 4 + 11;
  std::string no_summary = bytes.substr(0, header_end) +
                           std::string("\x80\x03\0\0\0\0\0\0\0abc", 12) +
                           bytes.substr(header_end, data_end + 9 + 4 - header_end);
  no_summary += std::string("\x02\x14\0\0\0\0\0\0\0", 9) + std::string(20, '\0');
  no_summary += bytes.substr(bytes.size() - 8);
  const fs::path file = dir.path() / "no_summary.mcap";
  WriteBytes(file, no_summary);
  const Reader reader(file);
  CHECK_FALSE(reader.truncated());
  CHECK(reader.channels().size() == 3);
  CHECK(reader.metadata().size() == 2);
  CHECK(reader.ReadAttachment("scenario.yaml")->data == kAttachmentBytes);
  CHECK(ReadAll(reader) == written);
}

TEST_CASE("a writer dropped without Close leaves its chunks readable", "[mcap]") {
  const test::ScratchDir dir("corridorsim_mcap_unclosed");
  const fs::path file = dir.path() / "unclosed.mcap";
  {
    Writer writer(file, SmallChunks(Compression::kLz4));
    const std::uint16_t schema = writer.AddSchema("std_msgs/msg/String", "ros2msg", "string data");
    const std::uint16_t channel = writer.AddChannel(schema, "/chatter", "cdr");
    for (int i = 0; i < 100; ++i) writer.Write(channel, 10 + i, 10 + i, Payload(i));
  }
  const Reader reader(file);
  CHECK(reader.truncated());
  REQUIRE(reader.FindChannel("/chatter") != nullptr);
  const std::vector<WrittenMessage> read = ReadAll(reader);
  CHECK(read.size() > 50);  // every full chunk; the open one was never written
  CHECK(read.size() < 100);
  for (std::size_t i = 0; i < read.size(); ++i) CHECK(read[i].sequence == i);
}

TEST_CASE("the MCAP writer refuses bad calls and unwritable files", "[mcap]") {
  const test::ScratchDir dir("corridorsim_mcap_writer_errors");
  CHECK_THROWS_WITH(Writer(dir.path() / "missing" / "x.mcap", WriterOptions{}),
                    Catch::Contains("missing/x.mcap: cannot create the recording"));
  WriterOptions bad_level;
  bad_level.zstd_level = 30;
  CHECK_THROWS_AS(Writer(dir.path() / "level.mcap", bad_level), std::invalid_argument);
  Writer writer(dir.path() / "calls.mcap", WriterOptions{});
  CHECK_THROWS_AS(writer.AddChannel(3, "/t", "cdr"), std::invalid_argument);
  CHECK_THROWS_AS(writer.Write(1, 0, 0, {}), std::invalid_argument);
  writer.Close();
  CHECK_THROWS_AS(writer.AddSchema("a", "b", "c"), std::logic_error);
  const Reader reader(dir.path() / "calls.mcap");  // an empty recording is a valid one
  CHECK_FALSE(reader.truncated());
  CHECK(reader.MessageCounts().empty());
  CHECK(ReadAll(reader).empty());
}

TEST_CASE("a file that is not there is a RecordingError", "[mcap]") {
  const test::ScratchDir dir("corridorsim_mcap_missing");
  CHECK_THROWS_AS(Reader(dir.path() / "none.mcap"), RecordingError);
}

}  // namespace
}  // namespace corridorsim::mcap

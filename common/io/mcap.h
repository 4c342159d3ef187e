#pragma once
// MCAP files (https://mcap.dev/spec, version 0): the container rosbag2 made its default storage
// and Foxglove, Lichtblick and Rerun open directly (docs/recordings.md). No C++ MCAP library is
// packaged in Debian 12, so corridorsim writes and reads the records itself; compression is
// Debian's libzstd and liblz4.
//
// The writer: magic, Header, then Schema/Channel records as they are added and the messages in
// chunks (each with its MessageIndex records), Metadata and Attachment records, then DataEnd and
// the summary section (every Schema and Channel again, Statistics, ChunkIndex, AttachmentIndex,
// MetadataIndex), the SummaryOffset records, the Footer and the closing magic: readers seek with
// it. Chunks are compressed on a background thread (common/io/serial_worker.h) and written in the
// order they were filled, so the file's bytes depend only on the calls made, never on timing.
//
// The reader: checks the magic, reads the summary when the file has one and otherwise scans the
// data section (a recording cut short by a killed run reads up to its last complete chunk, and
// says it was truncated). Every malformed record is a RecordingError naming the file, the record
// (its opcode's name) and its byte offset; lengths, counts and sizes are checked against the file
// and bounded before anything is allocated.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace corridorsim::mcap {

enum class Compression { kNone, kZstd, kLz4 };
/// "", "zstd", "lz4": the chunk record's compression field.
std::string CompressionName(Compression compression);

/// A malformed, truncated or unreadable recording: "<file>: <record> at byte <offset>: <what>".
class RecordingError : public std::runtime_error {
 public:
  RecordingError(const std::filesystem::path& file, const std::string& record, std::uint64_t offset,
                 const std::string& what);
  const std::string& record() const { return record_; }
  std::uint64_t offset() const { return offset_; }

 private:
  std::string record_;
  std::uint64_t offset_ = 0;
};

struct WriterOptions {
  std::string profile = "ros2";  // the Header's profile (mcap.dev/spec/registry: "ros1", "ros2")
  std::string library = "corridorsim";
  Compression compression = Compression::kZstd;
  int zstd_level = 1;                         // 1 to 19
  std::size_t chunk_bytes = 4 * 1024 * 1024;  // uncompressed chunk size that closes a chunk
  std::size_t max_pending_chunks = 4;         // chunks queued for compression (bounds memory)
};

/// Writes one MCAP file. Throws std::runtime_error naming the file when it cannot be written.
/// Not thread-safe: one thread makes the calls.
class Writer {
 public:
  Writer(const std::filesystem::path& file, const WriterOptions& options);
  /// Without Close(), the file is left as it is (the chunks written so far are readable).
  ~Writer();
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  /// Ids count from 1 in the order of the calls.
  std::uint16_t AddSchema(const std::string& name, const std::string& encoding,
                          const std::string& data);
  std::uint16_t AddChannel(std::uint16_t schema_id, const std::string& topic,
                           const std::string& message_encoding,
                           const std::map<std::string, std::string>& metadata = {});
  /// A message of `channel_id`; its sequence number counts per channel from 0. Log times need not
  /// increase (the chunk and message indexes carry each chunk's range).
  void Write(std::uint16_t channel_id, std::uint64_t log_time_ns, std::uint64_t publish_time_ns,
             std::span<const std::uint8_t> data);
  void AddMetadata(const std::string& name, const std::map<std::string, std::string>& metadata);
  void AddAttachment(std::uint64_t log_time_ns, std::uint64_t create_time_ns,
                     const std::string& name, const std::string& media_type,
                     std::span<const std::uint8_t> data);
  /// Writes the last chunk, the summary and the footer, and closes the file.
  void Close();

  /// Bytes in the file so far (after Close: its size).
  std::uint64_t bytes_written() const;
  /// Seconds the background thread spent compressing and writing chunks.
  double busy_seconds() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

struct Schema {
  std::uint16_t id = 0;
  std::string name;
  std::string encoding;
  std::string data;
};

struct Channel {
  std::uint16_t id = 0;
  std::uint16_t schema_id = 0;
  std::string topic;
  std::string message_encoding;
  std::map<std::string, std::string> metadata;
};

struct Message {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::uint64_t log_time_ns = 0;
  std::uint64_t publish_time_ns = 0;
  std::span<const std::uint8_t> data;  // valid during the callback only
  std::uint64_t chunk_offset = 0;      // the file offset of the chunk that holds it (0: none)
};

struct Attachment {
  std::uint64_t log_time_ns = 0;
  std::uint64_t create_time_ns = 0;
  std::string name;
  std::string media_type;
  std::vector<std::uint8_t> data;
};

/// Reads one MCAP file. The constructor reads the header and the summary (or, without one, scans
/// the data section for schemas, channels, metadata and attachments).
class Reader {
 public:
  explicit Reader(const std::filesystem::path& file);
  ~Reader();
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  const std::string& profile() const;
  const std::string& library() const;
  const std::map<std::uint16_t, Schema>& schemas() const;
  const std::map<std::uint16_t, Channel>& channels() const;
  /// The channel of `topic`, or null.
  const Channel* FindChannel(const std::string& topic) const;
  /// Metadata records in file order (name, key-value map).
  const std::vector<std::pair<std::string, std::map<std::string, std::string>>>& metadata() const;
  /// The attachment named `name` (the first one), or nothing.
  std::optional<Attachment> ReadAttachment(const std::string& name) const;
  /// No footer or summary: the file was cut short (messages read up to its last complete chunk
  /// or record).
  bool truncated() const;
  /// The messages in file order (chunk by chunk, each chunk's records in order), streaming: one
  /// chunk is decompressed at a time. `channels`: only these (empty: all). The callback may
  /// return false to stop early.
  void ForEachMessage(const std::function<bool(const Message&)>& callback,
                      const std::vector<std::uint16_t>& channels = {}) const;
  /// Message counts per channel (from the summary's Statistics, or counted by a scan).
  std::map<std::uint16_t, std::uint64_t> MessageCounts() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace corridorsim::mcap

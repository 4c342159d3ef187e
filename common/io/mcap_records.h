#pragma once
// Private to common/io/mcap_*.cpp: MCAP's record opcodes, its little-endian field encoding, the
// CRC-32 every CRC field holds and the chunk compressions (https://mcap.dev/spec, version 0).

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "common/io/mcap.h"

namespace corridorsim::mcap::records {

/// 0x89 "MCAP" '0' "\r\n": the first and last eight bytes of every file.
inline constexpr std::array<std::uint8_t, 8> kMagic = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
/// A record's opcode (uint8) and content length (uint64).
inline constexpr std::uint64_t kRecordPrefixBytes = 9;
/// The Footer's content: summary_start, summary_offset_start (uint64), summary_crc (uint32).
inline constexpr std::uint64_t kFooterContentBytes = 20;
/// The reader refuses a chunk that says it holds more than this once decompressed.
inline constexpr std::uint64_t kMaxChunkUncompressedBytes = std::uint64_t{1} << 30;

enum Opcode : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

/// "Chunk", "Message", ...; "record 0x51" for an opcode the spec does not define.
std::string OpcodeName(std::uint8_t opcode);

/// CRC-32 as zlib computes it (IEEE 802.3, reflected polynomial 0xEDB88320), incrementally.
class Crc32 {
 public:
  void Update(std::span<const std::uint8_t> bytes);
  std::uint32_t value() const { return ~state_; }

 private:
  std::uint32_t state_ = 0xFFFFFFFFu;
};
std::uint32_t ComputeCrc32(std::span<const std::uint8_t> bytes);

/// Appends fields in MCAP's encoding: little-endian integers, String = uint32 length + bytes,
/// Map<string, string> = uint32 byte length + (String key, String value) pairs.
class FieldWriter {
 public:
  explicit FieldWriter(std::vector<std::uint8_t>& out) : out_(out) {}
  void U8(std::uint8_t value) { out_.push_back(value); }
  void U16(std::uint16_t value) { Little(value, 2); }
  void U32(std::uint32_t value) { Little(value, 4); }
  void U64(std::uint64_t value) { Little(value, 8); }
  void String(const std::string& text);
  void Bytes(std::span<const std::uint8_t> bytes) {
    out_.insert(out_.end(), bytes.begin(), bytes.end());
  }
  void StringMap(const std::map<std::string, std::string>& map);

 private:
  void Little(std::uint64_t value, int bytes);
  std::vector<std::uint8_t>& out_;
};

/// Starts a record (opcode and a length to be patched) in `out`; Finish patches the length.
class RecordBuilder {
 public:
  RecordBuilder(std::vector<std::uint8_t>& out, Opcode opcode);
  FieldWriter& fields() { return fields_; }
  void Finish();

 private:
  std::vector<std::uint8_t>& out_;
  std::size_t start_;
  FieldWriter fields_;
};

/// Where a record lies, for the errors: the file, the record's name and its byte offset.
struct RecordPlace {
  const std::filesystem::path* file = nullptr;
  std::string record;
  std::uint64_t offset = 0;
  std::string context;  // e.g. "the Message at byte 40 of its records: ", put before `what`
  [[noreturn]] void Fail(const std::string& what) const;
};

/// Reads fields of one record's content; any field that runs past the content is a
/// RecordingError naming the record and the field.
class FieldReader {
 public:
  FieldReader(std::span<const std::uint8_t> content, const RecordPlace& place)
      : content_(content), place_(place) {}
  std::uint8_t U8(const char* field) { return static_cast<std::uint8_t>(Little(field, 1)); }
  std::uint16_t U16(const char* field) { return static_cast<std::uint16_t>(Little(field, 2)); }
  std::uint32_t U32(const char* field) { return static_cast<std::uint32_t>(Little(field, 4)); }
  std::uint64_t U64(const char* field) { return Little(field, 8); }
  std::string String(const char* field);
  std::span<const std::uint8_t> Bytes(std::uint64_t size, const char* field);
  std::map<std::string, std::string> StringMap(const char* field);
  /// The rest of the content.
  std::span<const std::uint8_t> Rest();
  std::size_t position() const { return position_; }
  std::size_t remaining() const { return content_.size() - position_; }
  const RecordPlace& place() const { return place_; }

 private:
  std::uint64_t Little(const char* field, int bytes);
  std::span<const std::uint8_t> content_;
  std::size_t position_ = 0;
  const RecordPlace& place_;
};

/// Compresses a chunk's records (zstd at `zstd_level`, LZ4's frame format, or a copy).
std::vector<std::uint8_t> Compress(Compression compression, int zstd_level,
                                   std::span<const std::uint8_t> records);
/// Bytes left uninitialised until written: a chunk that declares a large uncompressed size
/// costs memory only for what its records really decompress to.
class ChunkBuffer {
 public:
  explicit ChunkBuffer(std::size_t size)
      : data_(size > 0 ? new std::uint8_t[size] : nullptr), size_(size) {}
  std::uint8_t* data() { return data_.get(); }
  std::size_t size() const { return size_; }
  std::span<const std::uint8_t> bytes() const { return {data_.get(), size_}; }

 private:
  std::unique_ptr<std::uint8_t[]> data_;
  std::size_t size_ = 0;
};

/// Decompresses a chunk's records into exactly `uncompressed_size` bytes (at most
/// kMaxChunkUncompressedBytes); anything else fails at `place`. `compression` is the chunk's
/// field: "", "zstd" or "lz4".
ChunkBuffer Decompress(const std::string& compression, std::span<const std::uint8_t> compressed,
                       std::uint64_t uncompressed_size, const RecordPlace& place);

}  // namespace corridorsim::mcap::records

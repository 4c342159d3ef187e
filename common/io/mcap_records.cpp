#include "common/io/mcap_records.h"

#include <lz4frame.h>
#include <zstd.h>

#include <cstring>
#include <memory>
#include <stdexcept>

namespace corridorsim::mcap {

std::string CompressionName(Compression compression) {
  switch (compression) {
    case Compression::kNone:
      return "";
    case Compression::kZstd:
      return "zstd";
    case Compression::kLz4:
      return "lz4";
  }
  return "";
}

RecordingError::RecordingError(const std::filesystem::path& file, const std::string& record,
                               std::uint64_t offset, const std::string& what)
    : std::runtime_error(file.string() + ": " + record + " at byte " + std::to_string(offset) +
                         ": " + what),
      record_(record),
      offset_(offset) {}

namespace records {

std::string OpcodeName(std::uint8_t opcode) {
  static const char* const kNames[] = {
      "Header",     "Footer",       "Schema",        "Channel",       "Message",
      "Chunk",      "MessageIndex", "ChunkIndex",    "Attachment",    "AttachmentIndex",
      "Statistics", "Metadata",     "MetadataIndex", "SummaryOffset", "DataEnd"};
  if (opcode >= kHeader && opcode <= kDataEnd) return kNames[opcode - 1];
  static const char* const kHex = "0123456789abcdef";
  return std::string("record 0x") + kHex[opcode >> 4] + kHex[opcode & 15];
}

namespace {

// Slicing-by-8 (Intel's, Kounavis and Berry 2008): table k advances the CRC over a byte followed
// by k zero bytes, so eight table lookups take in eight bytes at once.
using CrcTables = std::array<std::array<std::uint32_t, 256>, 8>;

CrcTables MakeCrcTables() {
  CrcTables t{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    t[0][i] = c;
  }
  for (std::size_t k = 1; k < 8; ++k) {
    for (std::size_t i = 0; i < 256; ++i) t[k][i] = (t[k - 1][i] >> 8) ^ t[0][t[k - 1][i] & 0xFFu];
  }
  return t;
}

std::uint32_t Load32(const std::uint8_t* p) {
  return std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 |
         std::uint32_t{p[3]} << 24;
}

}  // namespace

void Crc32::Update(std::span<const std::uint8_t> bytes) {
  static const CrcTables kT = MakeCrcTables();
  std::uint32_t c = state_;
  const std::uint8_t* p = bytes.data();
  std::size_t n = bytes.size();
  for (; n >= 8; n -= 8, p += 8) {
    const std::uint32_t a = c ^ Load32(p);
    const std::uint32_t b = Load32(p + 4);
    c = kT[7][a & 0xFFu] ^ kT[6][(a >> 8) & 0xFFu] ^ kT[5][(a >> 16) & 0xFFu] ^ kT[4][a >> 24] ^
        kT[3][b & 0xFFu] ^ kT[2][(b >> 8) & 0xFFu] ^ kT[1][(b >> 16) & 0xFFu] ^ kT[0][b >> 24];
  }
  for (; n > 0; --n, ++p) c = kT[0][(c ^ *p) & 0xFFu] ^ (c >> 8);
  state_ = c;
}

std::uint32_t ComputeCrc32(std::span<const std::uint8_t> bytes) {
  Crc32 crc;
  crc.Update(bytes);
  return crc.value();
}

void FieldWriter::Little(std::uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out_.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
}

void FieldWriter::String(const std::string& text) {
  if (text.size() > 0xFFFFFFFFu) throw std::length_error("mcap: a string longer than 4 GiB");
  U32(static_cast<std::uint32_t>(text.size()));
  out_.insert(out_.end(), text.begin(), text.end());
}

void FieldWriter::StringMap(const std::map<std::string, std::string>& map) {
  std::vector<std::uint8_t> entries;
  FieldWriter inner(entries);
  for (const auto& [key, value] : map) {
    inner.String(key);
    inner.String(value);
  }
  if (entries.size() > 0xFFFFFFFFu) throw std::length_error("mcap: a map larger than 4 GiB");
  U32(static_cast<std::uint32_t>(entries.size()));
  Bytes(entries);
}

RecordBuilder::RecordBuilder(std::vector<std::uint8_t>& out, Opcode opcode)
    : out_(out), start_(out.size()), fields_(out) {
  fields_.U8(opcode);
  fields_.U64(0);  // patched by Finish
}

void RecordBuilder::Finish() {
  const std::uint64_t length = out_.size() - start_ - kRecordPrefixBytes;
  for (int i = 0; i < 8; ++i) out_[start_ + 1 + i] = static_cast<std::uint8_t>(length >> (8 * i));
}

void RecordPlace::Fail(const std::string& what) const {
  throw RecordingError(file ? *file : std::filesystem::path(), record, offset, context + what);
}

std::uint64_t FieldReader::Little(const char* field, int bytes) {
  if (remaining() < static_cast<std::size_t>(bytes)) {
    place_.Fail(std::string("field ") + field + " (" + std::to_string(bytes) +
                " bytes) runs past the record's end (" + std::to_string(remaining()) +
                " bytes left)");
  }
  std::uint64_t value = 0;
  for (int i = 0; i < bytes; ++i) {
    value |= std::uint64_t{content_[position_ + static_cast<std::size_t>(i)]} << (8 * i);
  }
  position_ += static_cast<std::size_t>(bytes);
  return value;
}

std::span<const std::uint8_t> FieldReader::Bytes(std::uint64_t size, const char* field) {
  if (size > remaining()) {
    place_.Fail(std::string("field ") + field + " (" + std::to_string(size) +
                " bytes) runs past the record's end (" + std::to_string(remaining()) +
                " bytes left)");
  }
  const std::span<const std::uint8_t> bytes =
      content_.subspan(position_, static_cast<std::size_t>(size));
  position_ += static_cast<std::size_t>(size);
  return bytes;
}

std::string FieldReader::String(const char* field) {
  const std::uint32_t size = U32(field);
  const std::span<const std::uint8_t> bytes = Bytes(size, field);
  return std::string(bytes.begin(), bytes.end());
}

std::map<std::string, std::string> FieldReader::StringMap(const char* field) {
  const std::uint32_t size = U32(field);
  FieldReader entries(Bytes(size, field), place_);
  std::map<std::string, std::string> map;
  while (entries.remaining() > 0) {
    std::string key = entries.String(field);
    std::string value = entries.String(field);
    if (!map.emplace(std::move(key), std::move(value)).second) {
      place_.Fail(std::string("field ") + field + " holds a key twice");
    }
  }
  return map;
}

std::span<const std::uint8_t> FieldReader::Rest() { return Bytes(remaining(), "data"); }

std::vector<std::uint8_t> Compress(Compression compression, int zstd_level,
                                   std::span<const std::uint8_t> records) {
  std::vector<std::uint8_t> out;
  if (compression == Compression::kNone) return {records.begin(), records.end()};
  if (compression == Compression::kZstd) {
    out.resize(ZSTD_compressBound(records.size()));
    // The frame carries its own checksum (XXH64 of the content, checked by every zstd decoder):
    // the chunk's CRC-32, a second pass over the uncompressed bytes, is then left out (0).
    const std::unique_ptr<ZSTD_CCtx, decltype(&ZSTD_freeCCtx)> context(ZSTD_createCCtx(),
                                                                       &ZSTD_freeCCtx);
    if (!context) throw std::runtime_error("zstd: cannot create a compression context");
    ZSTD_CCtx_setParameter(context.get(), ZSTD_c_compressionLevel, zstd_level);
    ZSTD_CCtx_setParameter(context.get(), ZSTD_c_checksumFlag, 1);
    const std::size_t size =
        ZSTD_compress2(context.get(), out.data(), out.size(), records.data(), records.size());
    if (ZSTD_isError(size)) {
      throw std::runtime_error(std::string("zstd compression failed: ") + ZSTD_getErrorName(size));
    }
    out.resize(size);
    return out;
  }
  LZ4F_preferences_t preferences{};
  preferences.frameInfo.contentSize = records.size();
  preferences.frameInfo.contentChecksumFlag = LZ4F_contentChecksumEnabled;  // as zstd's above
  out.resize(LZ4F_compressFrameBound(records.size(), &preferences));
  const std::size_t size =
      LZ4F_compressFrame(out.data(), out.size(), records.data(), records.size(), &preferences);
  if (LZ4F_isError(size)) {
    throw std::runtime_error(std::string("lz4 compression failed: ") + LZ4F_getErrorName(size));
  }
  out.resize(size);
  return out;
}

namespace {

void DecompressLz4(std::span<const std::uint8_t> compressed, ChunkBuffer& out,
                   const RecordPlace& place) {
  LZ4F_dctx* raw = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION))) {
    throw std::runtime_error("lz4: cannot create a decompression context");
  }
  const std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> context(
      raw, &LZ4F_freeDecompressionContext);
  std::size_t in_done = 0;
  std::size_t out_done = 0;
  for (;;) {
    std::size_t in_size = compressed.size() - in_done;
    std::size_t out_size = out.size() - out_done;
    const std::size_t hint = LZ4F_decompress(context.get(), out.data() + out_done, &out_size,
                                             compressed.data() + in_done, &in_size, nullptr);
    if (LZ4F_isError(hint)) place.Fail(std::string("lz4: ") + LZ4F_getErrorName(hint));
    in_done += in_size;
    out_done += out_size;
    if (hint == 0) {  // a frame ended; another may follow
      if (in_done == compressed.size()) break;
      continue;
    }
    if (in_done == compressed.size()) place.Fail("lz4: the compressed records end mid-frame");
    if (in_size == 0 && out_size == 0) {  // no progress: the output is full
      place.Fail("lz4: the records decompress to more than the declared uncompressed size " +
                 std::to_string(out.size()));
    }
  }
  if (out_done != out.size()) {
    place.Fail("the records decompress to " + std::to_string(out_done) +
               " bytes, not the declared uncompressed size " + std::to_string(out.size()));
  }
}

}  // namespace

ChunkBuffer Decompress(const std::string& compression, std::span<const std::uint8_t> compressed,
                       std::uint64_t uncompressed_size, const RecordPlace& place) {
  if (compression != "" && compression != "zstd" && compression != "lz4") {
    place.Fail("unknown compression '" + compression + "'");
  }
  if (uncompressed_size > kMaxChunkUncompressedBytes) {
    place.Fail("declared uncompressed size " + std::to_string(uncompressed_size) +
               " exceeds the limit of " + std::to_string(kMaxChunkUncompressedBytes) + " bytes");
  }
  const std::string declared =
      " bytes, not the declared uncompressed size " + std::to_string(uncompressed_size);
  ChunkBuffer out(static_cast<std::size_t>(uncompressed_size));
  if (compression.empty()) {
    if (compressed.size() != uncompressed_size) {
      place.Fail("uncompressed records of " + std::to_string(compressed.size()) + declared);
    }
    if (!compressed.empty()) std::memcpy(out.data(), compressed.data(), compressed.size());
    return out;
  }
  if (compression == "lz4") {
    DecompressLz4(compressed, out, place);
    return out;
  }
  // One frame (what writers write) that gives its content size must give the declared one.
  const std::size_t frame_bytes =
      ZSTD_findFrameCompressedSize(compressed.data(), compressed.size());
  if (ZSTD_isError(frame_bytes)) {
    place.Fail(std::string("zstd: ") + ZSTD_getErrorName(frame_bytes));
  }
  const unsigned long long framed = ZSTD_getFrameContentSize(compressed.data(), compressed.size());
  if (frame_bytes == compressed.size() && framed != ZSTD_CONTENTSIZE_UNKNOWN &&
      framed != ZSTD_CONTENTSIZE_ERROR && framed != uncompressed_size) {
    place.Fail("the zstd frame holds " + std::to_string(framed) + declared);
  }
  const std::size_t size =
      ZSTD_decompress(out.data(), out.size(), compressed.data(), compressed.size());
  if (ZSTD_isError(size)) {
    place.Fail(std::string("zstd: ") + ZSTD_getErrorName(size) + " (declared uncompressed size " +
               std::to_string(uncompressed_size) + ")");
  }
  if (size != out.size())
    place.Fail("the records decompress to " + std::to_string(size) + declared);
  return out;
}

}  // namespace records
}  // namespace corridorsim::mcap

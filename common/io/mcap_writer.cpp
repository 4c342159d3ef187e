// The MCAP writer (common/io/mcap.h). The calling thread builds records; every byte reaches the
// file through one SerialWorker job at a time, in the order of the calls, so a chunk compressed
// on the worker lands exactly where it would have inline. The worker alone touches the file
// (offset, data-section CRC, the index records that need file offsets) until Close() drains it.
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "common/io/mcap.h"
#include "common/io/mcap_records.h"
#include "common/io/serial_worker.h"

namespace corridorsim::mcap {

using records::FieldWriter;
using records::RecordBuilder;

namespace {

// What the summary section's ChunkIndex record says of one chunk.
struct ChunkIndexEntry {
  std::uint64_t message_start_time = 0;
  std::uint64_t message_end_time = 0;
  std::uint64_t chunk_start_offset = 0;
  std::uint64_t chunk_length = 0;
  std::map<std::uint16_t, std::uint64_t> message_index_offsets;
  std::uint64_t message_index_length = 0;
  std::uint64_t compressed_size = 0;
  std::uint64_t uncompressed_size = 0;
};

struct AttachmentIndexEntry {
  std::uint64_t offset = 0;
  std::uint64_t length = 0;
  std::uint64_t log_time = 0;
  std::uint64_t create_time = 0;
  std::uint64_t data_size = 0;
  std::string name;
  std::string media_type;
};

struct MetadataIndexEntry {
  std::uint64_t offset = 0;
  std::uint64_t length = 0;
  std::string name;
};

// A chunk being filled by the calling thread.
struct OpenChunk {
  std::vector<std::uint8_t> records;
  std::uint64_t start_time = std::numeric_limits<std::uint64_t>::max();
  std::uint64_t end_time = 0;
  // channel -> (log time, offset of the Message record in `records`), in the order written.
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> message_index;
};

}  // namespace

struct Writer::Impl {
  std::filesystem::path path;
  WriterOptions options;
  std::FILE* file = nullptr;
  bool closed = false;

  // The calling thread's state.
  std::map<std::uint16_t, Schema> schemas;
  std::map<std::uint16_t, Channel> channels;
  std::map<std::uint16_t, std::uint32_t> next_sequence;
  std::map<std::uint16_t, std::uint64_t> channel_message_counts;
  std::uint64_t message_count = 0;
  std::uint64_t message_start_time = std::numeric_limits<std::uint64_t>::max();
  std::uint64_t message_end_time = 0;
  std::uint32_t metadata_count = 0;
  std::uint32_t attachment_count = 0;
  OpenChunk chunk;

  // The worker's state (the calling thread reads it only after Drain).
  std::uint64_t offset = 0;
  std::atomic<std::uint64_t> bytes{0};
  records::Crc32 data_crc;
  std::vector<ChunkIndexEntry> chunk_indexes;
  std::vector<AttachmentIndexEntry> attachment_indexes;
  std::vector<MetadataIndexEntry> metadata_indexes;

  std::unique_ptr<SerialWorker> worker;

  Impl() = default;
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl();

  void Append(std::span<const std::uint8_t> data) {
    if (!data.empty() && std::fwrite(data.data(), 1, data.size(), file) != data.size()) {
      throw std::runtime_error(path.string() +
                               ": cannot write the recording: " + std::strerror(errno));
    }
    offset += data.size();
    bytes.store(offset);
  }
  // Appends bytes of the data section (they count in DataEnd's CRC).
  void AppendData(std::span<const std::uint8_t> data) {
    data_crc.Update(data);
    Append(data);
  }
  // Queues a small record for the file, behind everything queued before it.
  void SubmitRecord(std::vector<std::uint8_t> record) {
    worker->Submit([this, record = std::move(record)] { AppendData(record); }, 0);
  }
  void CheckOpen() const {
    if (closed) throw std::logic_error(path.string() + ": the MCAP writer is closed");
  }

  void FlushChunk();
  void WriteChunk(OpenChunk& full);  // on the worker
  void WriteSummary();
};

void Writer::Impl::FlushChunk() {
  if (chunk.records.empty()) return;
  auto full = std::make_shared<OpenChunk>(std::move(chunk));
  chunk = OpenChunk{};
  worker->Submit([this, full] { WriteChunk(*full); }, 1);
}

void Writer::Impl::WriteChunk(OpenChunk& full) {
  const std::vector<std::uint8_t> compressed =
      records::Compress(options.compression, options.zstd_level, full.records);
  std::vector<std::uint8_t> out;
  out.reserve(compressed.size() + 128);
  {
    RecordBuilder record(out, records::kChunk);
    FieldWriter& f = record.fields();
    f.U64(full.start_time);
    f.U64(full.end_time);
    f.U64(full.records.size());
    // uncompressed_crc: 0 ("not computed", MCAP spec) for zstd and lz4 chunks, whose frames
    // carry their own content checksum (records::Compress); the CRC-32 for uncompressed ones.
    f.U32(options.compression == Compression::kNone ? records::ComputeCrc32(full.records) : 0);
    f.String(CompressionName(options.compression));
    f.U64(compressed.size());
    f.Bytes(compressed);
    record.Finish();
  }
  ChunkIndexEntry index;
  index.message_start_time = full.start_time;
  index.message_end_time = full.end_time;
  index.chunk_start_offset = offset;
  index.chunk_length = out.size();
  index.compressed_size = compressed.size();
  index.uncompressed_size = full.records.size();
  for (const auto& [channel_id, entries] : full.message_index) {
    index.message_index_offsets[channel_id] = offset + out.size();
    RecordBuilder record(out, records::kMessageIndex);
    FieldWriter& f = record.fields();
    f.U16(channel_id);
    f.U32(static_cast<std::uint32_t>(entries.size() * 16));
    for (const auto& [log_time, message_offset] : entries) {
      f.U64(log_time);
      f.U64(message_offset);
    }
    record.Finish();
  }
  index.message_index_length = out.size() - index.chunk_length;
  AppendData(out);
  // A killed run keeps every chunk written so far (the reader reads a file without a footer).
  if (std::fflush(file) != 0) {
    throw std::runtime_error(path.string() +
                             ": cannot write the recording: " + std::strerror(errno));
  }
  chunk_indexes.push_back(std::move(index));
}

Writer::Writer(const std::filesystem::path& file, const WriterOptions& options)
    : impl_(std::make_unique<Impl>()) {
  if (options.zstd_level < 1 || options.zstd_level > 19) {
    throw std::invalid_argument("mcap: zstd_level " + std::to_string(options.zstd_level) +
                                " is not in 1..19");
  }
  if (options.chunk_bytes < 1) throw std::invalid_argument("mcap: chunk_bytes must be positive");
  impl_->path = file;
  impl_->options = options;
  impl_->file = std::fopen(file.c_str(), "wb");
  if (!impl_->file) {
    throw std::runtime_error(file.string() +
                             ": cannot create the recording: " + std::strerror(errno));
  }
  std::vector<std::uint8_t> head(records::kMagic.begin(), records::kMagic.end());
  RecordBuilder header(head, records::kHeader);
  header.fields().String(options.profile);
  header.fields().String(options.library);
  header.Finish();
  impl_->AppendData(head);
  // A run killed before its first chunk still leaves a file the reader opens (as truncated).
  if (std::fflush(impl_->file) != 0) {
    throw std::runtime_error(file.string() +
                             ": cannot write the recording: " + std::strerror(errno));
  }
  impl_->worker = std::make_unique<SerialWorker>(options.max_pending_chunks);
}

Writer::~Writer() = default;

Writer::Impl::~Impl() {
  try {
    if (worker) worker->Drain();
  } catch (...) {
    // The file stays as far as it got; the error was the caller's to see through Close().
  }
  worker.reset();  // before the file closes: its queued jobs write to it
  if (file) std::fclose(file);
}

std::uint16_t Writer::AddSchema(const std::string& name, const std::string& encoding,
                                const std::string& data) {
  impl_->CheckOpen();
  if (impl_->schemas.size() >= 0xFFFF) throw std::length_error("mcap: more than 65535 schemas");
  const auto id = static_cast<std::uint16_t>(impl_->schemas.size() + 1);
  impl_->schemas[id] = Schema{id, name, encoding, data};
  std::vector<std::uint8_t> out;
  RecordBuilder record(out, records::kSchema);
  FieldWriter& f = record.fields();
  f.U16(id);
  f.String(name);
  f.String(encoding);
  f.String(data);  // uint32 length + bytes, as a String
  record.Finish();
  impl_->SubmitRecord(std::move(out));
  return id;
}

std::uint16_t Writer::AddChannel(std::uint16_t schema_id, const std::string& topic,
                                 const std::string& message_encoding,
                                 const std::map<std::string, std::string>& metadata) {
  impl_->CheckOpen();
  if (schema_id != 0 && impl_->schemas.count(schema_id) == 0) {
    throw std::invalid_argument("mcap: channel '" + topic + "' names schema " +
                                std::to_string(schema_id) + ", which was never added");
  }
  if (impl_->channels.size() >= 0xFFFF) throw std::length_error("mcap: more than 65535 channels");
  const auto id = static_cast<std::uint16_t>(impl_->channels.size() + 1);
  impl_->channels[id] = Channel{id, schema_id, topic, message_encoding, metadata};
  impl_->next_sequence[id] = 0;
  std::vector<std::uint8_t> out;
  RecordBuilder record(out, records::kChannel);
  FieldWriter& f = record.fields();
  f.U16(id);
  f.U16(schema_id);
  f.String(topic);
  f.String(message_encoding);
  f.StringMap(metadata);
  record.Finish();
  impl_->SubmitRecord(std::move(out));
  return id;
}

void Writer::Write(std::uint16_t channel_id, std::uint64_t log_time_ns,
                   std::uint64_t publish_time_ns, std::span<const std::uint8_t> data) {
  Impl& m = *impl_;
  m.CheckOpen();
  const auto sequence = m.next_sequence.find(channel_id);
  if (sequence == m.next_sequence.end()) {
    throw std::invalid_argument("mcap: a message on channel " + std::to_string(channel_id) +
                                ", which was never added");
  }
  OpenChunk& chunk = m.chunk;
  chunk.message_index[channel_id].emplace_back(log_time_ns, chunk.records.size());
  RecordBuilder record(chunk.records, records::kMessage);
  FieldWriter& f = record.fields();
  f.U16(channel_id);
  f.U32(sequence->second++);
  f.U64(log_time_ns);
  f.U64(publish_time_ns);
  f.Bytes(data);
  record.Finish();
  chunk.start_time = std::min(chunk.start_time, log_time_ns);
  chunk.end_time = std::max(chunk.end_time, log_time_ns);
  m.message_start_time = std::min(m.message_start_time, log_time_ns);
  m.message_end_time = std::max(m.message_end_time, log_time_ns);
  ++m.message_count;
  ++m.channel_message_counts[channel_id];
  if (chunk.records.size() >= m.options.chunk_bytes) m.FlushChunk();
}

void Writer::AddMetadata(const std::string& name,
                         const std::map<std::string, std::string>& metadata) {
  Impl& m = *impl_;
  m.CheckOpen();
  ++m.metadata_count;
  std::vector<std::uint8_t> out;
  RecordBuilder record(out, records::kMetadata);
  record.fields().String(name);
  record.fields().StringMap(metadata);
  record.Finish();
  m.worker->Submit(
      [&m, name, out = std::move(out)] {
        m.metadata_indexes.push_back(MetadataIndexEntry{m.offset, out.size(), name});
        m.AppendData(out);
      },
      0);
}

void Writer::AddAttachment(std::uint64_t log_time_ns, std::uint64_t create_time_ns,
                           const std::string& name, const std::string& media_type,
                           std::span<const std::uint8_t> data) {
  Impl& m = *impl_;
  m.CheckOpen();
  ++m.attachment_count;
  std::vector<std::uint8_t> out;
  RecordBuilder record(out, records::kAttachment);
  FieldWriter& f = record.fields();
  f.U64(log_time_ns);
  f.U64(create_time_ns);
  f.String(name);
  f.String(media_type);
  f.U64(data.size());
  f.Bytes(data);
  // The CRC of every field before it.
  f.U32(records::ComputeCrc32(std::span(out).subspan(records::kRecordPrefixBytes)));
  record.Finish();
  AttachmentIndexEntry index{0,           out.size(), log_time_ns, create_time_ns,
                             data.size(), name,       media_type};
  // Weighed like a chunk: an attachment may be large.
  m.worker->Submit(
      [&m, index, out = std::move(out)]() mutable {
        index.offset = m.offset;
        m.attachment_indexes.push_back(std::move(index));
        m.AppendData(out);
      },
      1);
}

void Writer::Impl::WriteSummary() {
  // DataEnd closes the data section with the CRC of every byte before it.
  std::vector<std::uint8_t> out;
  {
    RecordBuilder record(out, records::kDataEnd);
    record.fields().U32(data_crc.value());
    record.Finish();
  }
  Append(out);
  const std::uint64_t summary_start = offset;
  out.clear();
  // Each group: its opcode, where it starts and its length in bytes.
  std::vector<std::tuple<records::Opcode, std::uint64_t, std::uint64_t>> groups;
  auto group = [&](records::Opcode opcode, auto&& write_records) {
    const std::size_t begin = out.size();
    write_records();
    if (out.size() > begin) groups.emplace_back(opcode, summary_start + begin, out.size() - begin);
  };
  group(records::kSchema, [&] {
    for (const auto& [id, schema] : schemas) {
      RecordBuilder record(out, records::kSchema);
      FieldWriter& f = record.fields();
      f.U16(id);
      f.String(schema.name);
      f.String(schema.encoding);
      f.String(schema.data);
      record.Finish();
    }
  });
  group(records::kChannel, [&] {
    for (const auto& [id, channel] : channels) {
      RecordBuilder record(out, records::kChannel);
      FieldWriter& f = record.fields();
      f.U16(id);
      f.U16(channel.schema_id);
      f.String(channel.topic);
      f.String(channel.message_encoding);
      f.StringMap(channel.metadata);
      record.Finish();
    }
  });
  group(records::kStatistics, [&] {
    RecordBuilder record(out, records::kStatistics);
    FieldWriter& f = record.fields();
    f.U64(message_count);
    f.U16(static_cast<std::uint16_t>(schemas.size()));
    f.U32(static_cast<std::uint32_t>(channels.size()));
    f.U32(attachment_count);
    f.U32(metadata_count);
    f.U32(static_cast<std::uint32_t>(chunk_indexes.size()));
    f.U64(message_count > 0 ? message_start_time : 0);
    f.U64(message_end_time);
    f.U32(static_cast<std::uint32_t>(channel_message_counts.size() * 10));
    for (const auto& [id, count] : channel_message_counts) {
      f.U16(id);
      f.U64(count);
    }
    record.Finish();
  });
  group(records::kChunkIndex, [&] {
    for (const ChunkIndexEntry& index : chunk_indexes) {
      RecordBuilder record(out, records::kChunkIndex);
      FieldWriter& f = record.fields();
      f.U64(index.message_start_time);
      f.U64(index.message_end_time);
      f.U64(index.chunk_start_offset);
      f.U64(index.chunk_length);
      f.U32(static_cast<std::uint32_t>(index.message_index_offsets.size() * 10));
      for (const auto& [id, message_index_offset] : index.message_index_offsets) {
        f.U16(id);
        f.U64(message_index_offset);
      }
      f.U64(index.message_index_length);
      f.String(CompressionName(options.compression));
      f.U64(index.compressed_size);
      f.U64(index.uncompressed_size);
      record.Finish();
    }
  });
  group(records::kAttachmentIndex, [&] {
    for (const AttachmentIndexEntry& index : attachment_indexes) {
      RecordBuilder record(out, records::kAttachmentIndex);
      FieldWriter& f = record.fields();
      f.U64(index.offset);
      f.U64(index.length);
      f.U64(index.log_time);
      f.U64(index.create_time);
      f.U64(index.data_size);
      f.String(index.name);
      f.String(index.media_type);
      record.Finish();
    }
  });
  group(records::kMetadataIndex, [&] {
    for (const MetadataIndexEntry& index : metadata_indexes) {
      RecordBuilder record(out, records::kMetadataIndex);
      FieldWriter& f = record.fields();
      f.U64(index.offset);
      f.U64(index.length);
      f.String(index.name);
      record.Finish();
    }
  });
  const std::uint64_t summary_offset_start = summary_start + out.size();
  for (const auto& [opcode, start, length] : groups) {
    RecordBuilder record(out, records::kSummaryOffset);
    record.fields().U8(opcode);
    record.fields().U64(start);
    record.fields().U64(length);
    record.Finish();
  }
  // The footer's CRC covers the summary, the summary offsets and the footer up to the CRC.
  out.push_back(records::kFooter);
  FieldWriter f(out);
  f.U64(records::kFooterContentBytes);
  f.U64(summary_start);
  f.U64(summary_offset_start);
  f.U32(records::ComputeCrc32(out));
  f.Bytes(records::kMagic);
  Append(out);
}

void Writer::Close() {
  Impl& m = *impl_;
  if (m.closed) return;
  m.FlushChunk();
  m.worker->Drain();
  m.closed = true;
  m.WriteSummary();
  std::FILE* file = std::exchange(m.file, nullptr);
  if (std::fclose(file) != 0) {
    throw std::runtime_error(m.path.string() +
                             ": cannot write the recording: " + std::strerror(errno));
  }
}

std::uint64_t Writer::bytes_written() const { return impl_->bytes.load(); }

double Writer::busy_seconds() const { return impl_->worker ? impl_->worker->busy_seconds() : 0.0; }

}  // namespace corridorsim::mcap

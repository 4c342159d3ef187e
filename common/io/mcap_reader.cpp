// The MCAP reader (common/io/mcap.h). Every length read from the file is checked against the
// bytes that hold it (the file, the record, the chunk's records) before anything is read or
// allocated; every failure is a RecordingError naming the record and its offset.
#include <algorithm>
#include <fstream>
#include <set>
#include <system_error>
#include <utility>

#include "common/io/mcap.h"
#include "common/io/mcap_records.h"

namespace corridorsim::mcap {

using records::FieldReader;
using records::RecordPlace;

namespace {

// A record's opcode, content length and the file offset of its opcode.
struct RecordHead {
  std::uint8_t opcode = 0;
  std::uint64_t length = 0;
  std::uint64_t offset = 0;
  std::uint64_t end() const { return offset + records::kRecordPrefixBytes + length; }
};

// A chunk's records may be a little larger compressed than uncompressed.
constexpr std::uint64_t kMaxChunkRecordBytes =
    records::kMaxChunkUncompressedBytes + records::kMaxChunkUncompressedBytes / 8 + 4096;

}  // namespace

struct Reader::Impl {
  std::filesystem::path path;
  mutable std::ifstream file;
  std::uint64_t size = 0;
  std::string profile;
  std::string library;
  std::map<std::uint16_t, Schema> schemas;
  std::map<std::uint16_t, Channel> channels;
  std::vector<std::pair<std::string, std::map<std::string, std::string>>> metadata;
  struct AttachmentPlace {
    std::uint64_t offset = 0;
    std::string name;
  };
  std::vector<AttachmentPlace> attachments;
  bool truncated = false;
  // The data section's records lie in [data_start, data_end).
  std::uint64_t data_start = 0;
  std::uint64_t data_end = 0;
  // Chunk offset -> the channels its messages are on (from the summary's ChunkIndex records).
  std::map<std::uint64_t, std::set<std::uint16_t>> chunk_channels;
  mutable std::optional<std::map<std::uint16_t, std::uint64_t>> counts;

  RecordPlace Place(const std::string& record, std::uint64_t offset) const {
    return RecordPlace{&path, record, offset, ""};
  }
  std::vector<std::uint8_t> ReadAt(std::uint64_t offset, std::uint64_t length,
                                   const RecordPlace& place) const {
    if (offset > size || length > size - offset) {
      place.Fail("bytes " + std::to_string(offset) + " to " + std::to_string(offset + length) +
                 " lie past the file's end (" + std::to_string(size) + " bytes)");
    }
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(length));
    file.clear();
    file.seekg(static_cast<std::streamoff>(offset));
    file.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(length));
    if (!file) place.Fail("cannot read " + std::to_string(length) + " bytes from the file");
    return bytes;
  }
  // The record starting at `offset`, if its prefix and content end by `end`; nothing if the
  // prefix or the content runs past `end` (a file cut short, or a corrupt length).
  std::optional<RecordHead> Head(std::uint64_t offset, std::uint64_t end) const {
    if (offset > end || end - offset < records::kRecordPrefixBytes) return std::nullopt;
    const std::vector<std::uint8_t> prefix =
        ReadAt(offset, records::kRecordPrefixBytes, Place("record", offset));
    RecordHead head;
    head.opcode = prefix[0];
    head.offset = offset;
    for (int i = 0; i < 8; ++i) head.length |= std::uint64_t{prefix[1 + i]} << (8 * i);
    if (head.length > end - offset - records::kRecordPrefixBytes) return std::nullopt;
    return head;
  }
  // Like Head, but a record that does not end by `end` is an error.
  RecordHead RequireHead(std::uint64_t offset, std::uint64_t end, const std::string& where) const {
    const std::optional<RecordHead> head = Head(offset, end);
    if (!head) {
      std::string name = "record";
      if (offset < end && end - offset >= 1) {
        name = records::OpcodeName(ReadAt(offset, 1, Place("record", offset))[0]);
      }
      Place(name, offset)
          .Fail("the record runs past the end of " + where + " at byte " + std::to_string(end));
    }
    return *head;
  }
  std::vector<std::uint8_t> Content(const RecordHead& head) const {
    const RecordPlace place = Place(records::OpcodeName(head.opcode), head.offset);
    if (head.opcode == records::kChunk && head.length > kMaxChunkRecordBytes) {
      place.Fail("a chunk of " + std::to_string(head.length) + " bytes exceeds the limit of " +
                 std::to_string(kMaxChunkRecordBytes));
    }
    return ReadAt(head.offset + records::kRecordPrefixBytes, head.length, place);
  }

  void AddSchema(FieldReader& f);
  void AddChannel(FieldReader& f);
  void ReadSummary(std::uint64_t summary_start, std::uint64_t summary_end);
  void Scan(std::uint64_t end, bool cut_ok);
  // Decompresses the chunk at `head` and calls `record` with each of its records (opcode,
  // content, a FieldReader-ready place naming the record inside the chunk).
  template <typename F>
  void ForEachChunkRecord(const RecordHead& head, F&& record) const;
  Message ParseMessage(FieldReader& f, std::uint64_t chunk_offset) const;
};

void Reader::Impl::AddSchema(FieldReader& f) {
  Schema schema;
  schema.id = f.U16("id");
  schema.name = f.String("name");
  schema.encoding = f.String("encoding");
  schema.data = f.String("data");
  if (schema.id == 0) return;  // id 0 is reserved: readers ignore such a schema (spec)
  const auto [it, added] = schemas.emplace(schema.id, schema);
  if (!added && (it->second.name != schema.name || it->second.encoding != schema.encoding ||
                 it->second.data != schema.data)) {
    f.place().Fail("schema " + std::to_string(schema.id) + " is defined twice, differently");
  }
}

void Reader::Impl::AddChannel(FieldReader& f) {
  Channel channel;
  channel.id = f.U16("id");
  channel.schema_id = f.U16("schema_id");
  channel.topic = f.String("topic");
  channel.message_encoding = f.String("message_encoding");
  channel.metadata = f.StringMap("metadata");
  if (channel.schema_id != 0 && schemas.count(channel.schema_id) == 0) {
    f.place().Fail("channel '" + channel.topic + "' names schema " +
                   std::to_string(channel.schema_id) +
                   ", which no Schema record before it defines");
  }
  const auto [it, added] = channels.emplace(channel.id, channel);
  if (!added && (it->second.schema_id != channel.schema_id || it->second.topic != channel.topic ||
                 it->second.message_encoding != channel.message_encoding ||
                 it->second.metadata != channel.metadata)) {
    f.place().Fail("channel " + std::to_string(channel.id) + " is defined twice, differently");
  }
}

template <typename F>
void Reader::Impl::ForEachChunkRecord(const RecordHead& head, F&& record) const {
  const std::vector<std::uint8_t> content = Content(head);
  const RecordPlace place = Place("Chunk", head.offset);
  FieldReader f(content, place);
  f.U64("message_start_time");
  f.U64("message_end_time");
  const std::uint64_t uncompressed_size = f.U64("uncompressed_size");
  const std::uint32_t uncompressed_crc = f.U32("uncompressed_crc");
  const std::string compression = f.String("compression");
  const std::uint64_t records_size = f.U64("records");
  const std::span<const std::uint8_t> compressed = f.Bytes(records_size, "records");
  const records::ChunkBuffer chunk_records =
      records::Decompress(compression, compressed, uncompressed_size, place);
  if (uncompressed_crc != 0 && records::ComputeCrc32(chunk_records.bytes()) != uncompressed_crc) {
    place.Fail("the CRC of the uncompressed records does not match the chunk's uncompressed_crc");
  }
  const std::span<const std::uint8_t> all = chunk_records.bytes();
  std::size_t position = 0;
  while (position < all.size()) {
    RecordPlace inner = place;
    inner.context = "the record at byte " + std::to_string(position) + " of its records: ";
    if (all.size() - position < records::kRecordPrefixBytes) {
      inner.Fail("the chunk's records end inside a record's opcode and length");
    }
    FieldReader prefix(all.subspan(position, records::kRecordPrefixBytes), inner);
    const std::uint8_t opcode = prefix.U8("opcode");
    const std::uint64_t length = prefix.U64("length");
    position += records::kRecordPrefixBytes;
    inner.context = "the " + records::OpcodeName(opcode) + " at byte " +
                    std::to_string(position - records::kRecordPrefixBytes) + " of its records: ";
    if (length > all.size() - position) inner.Fail("the record runs past the chunk's records");
    FieldReader fields(all.subspan(position, static_cast<std::size_t>(length)), inner);
    position += static_cast<std::size_t>(length);
    if (!record(opcode, fields)) return;
  }
}

Message Reader::Impl::ParseMessage(FieldReader& f, std::uint64_t chunk_offset) const {
  Message message;
  message.channel_id = f.U16("channel_id");
  message.sequence = f.U32("sequence");
  message.log_time_ns = f.U64("log_time");
  message.publish_time_ns = f.U64("publish_time");
  message.data = f.Rest();
  message.chunk_offset = chunk_offset;
  if (channels.count(message.channel_id) == 0) {
    f.place().Fail("a message on channel " + std::to_string(message.channel_id) +
                   ", which no Channel record defines");
  }
  return message;
}

void Reader::Impl::ReadSummary(std::uint64_t summary_start, std::uint64_t summary_end) {
  std::uint64_t offset = summary_start;
  while (offset < summary_end) {
    const RecordHead head = RequireHead(offset, summary_end, "the summary section");
    const std::string name = records::OpcodeName(head.opcode);
    const RecordPlace place = Place(name, head.offset);
    offset = head.end();
    if (head.opcode != records::kSchema && head.opcode != records::kChannel &&
        head.opcode != records::kStatistics && head.opcode != records::kChunkIndex &&
        head.opcode != records::kAttachmentIndex && head.opcode != records::kMetadataIndex) {
      continue;  // other records (and unknown opcodes) are skipped
    }
    const std::vector<std::uint8_t> content = Content(head);
    FieldReader f(content, place);
    switch (head.opcode) {
      case records::kSchema:
        AddSchema(f);
        break;
      case records::kChannel:
        AddChannel(f);
        break;
      case records::kStatistics: {
        f.U64("message_count");
        f.U16("schema_count");
        f.U32("channel_count");
        f.U32("attachment_count");
        f.U32("metadata_count");
        f.U32("chunk_count");
        f.U64("message_start_time");
        f.U64("message_end_time");
        FieldReader entries(f.Bytes(f.U32("channel_message_counts"), "channel_message_counts"),
                            place);
        std::map<std::uint16_t, std::uint64_t> found;
        while (entries.remaining() > 0) {
          const std::uint16_t id = entries.U16("channel_message_counts");
          found[id] = entries.U64("channel_message_counts");
        }
        counts = std::move(found);
        break;
      }
      case records::kChunkIndex: {
        f.U64("message_start_time");
        f.U64("message_end_time");
        const std::uint64_t chunk_offset = f.U64("chunk_start_offset");
        f.U64("chunk_length");
        FieldReader entries(f.Bytes(f.U32("message_index_offsets"), "message_index_offsets"),
                            place);
        std::set<std::uint16_t>& ids = chunk_channels[chunk_offset];
        while (entries.remaining() > 0) {
          ids.insert(entries.U16("message_index_offsets"));
          entries.U64("message_index_offsets");
        }
        break;
      }
      case records::kAttachmentIndex: {
        const std::uint64_t attachment_offset = f.U64("offset");
        f.U64("length");
        f.U64("log_time");
        f.U64("create_time");
        f.U64("data_size");
        attachments.push_back(AttachmentPlace{attachment_offset, f.String("name")});
        break;
      }
      case records::kMetadataIndex: {
        const std::uint64_t metadata_offset = f.U64("offset");
        const RecordHead record = RequireHead(metadata_offset, data_end, "the data section");
        const RecordPlace metadata_place = Place("Metadata", metadata_offset);
        if (record.opcode != records::kMetadata) {
          metadata_place.Fail("the MetadataIndex at byte " + std::to_string(head.offset) +
                              " points at a " + records::OpcodeName(record.opcode));
        }
        const std::vector<std::uint8_t> metadata_content = Content(record);
        FieldReader m(metadata_content, metadata_place);
        std::string metadata_name = m.String("name");
        metadata.emplace_back(std::move(metadata_name), m.StringMap("metadata"));
        break;
      }
      default:
        break;
    }
  }
}

void Reader::Impl::Scan(std::uint64_t end, bool cut_ok) {
  std::map<std::uint16_t, std::uint64_t> found;
  std::uint64_t offset = data_start;
  data_end = end;
  while (offset < end) {
    const std::optional<RecordHead> head = Head(offset, end);
    if (!head) {
      if (!cut_ok) RequireHead(offset, end, "the data section");
      data_end = offset;  // the file was cut inside this record
      break;
    }
    offset = head->end();
    if (head->opcode == records::kDataEnd || head->opcode == records::kFooter) {
      data_end = head->offset;
      break;
    }
    const RecordPlace place = Place(records::OpcodeName(head->opcode), head->offset);
    switch (head->opcode) {
      case records::kSchema:
      case records::kChannel:
      case records::kMetadata:
      case records::kMessage: {
        const std::vector<std::uint8_t> content = Content(*head);
        FieldReader f(content, place);
        if (head->opcode == records::kSchema) AddSchema(f);
        if (head->opcode == records::kChannel) AddChannel(f);
        if (head->opcode == records::kMetadata) {
          std::string name = f.String("name");
          metadata.emplace_back(std::move(name), f.StringMap("metadata"));
        }
        if (head->opcode == records::kMessage) ++found[ParseMessage(f, 0).channel_id];
        break;
      }
      case records::kAttachment: {
        const std::vector<std::uint8_t> content = Content(*head);
        FieldReader f(content, place);
        f.U64("log_time");
        f.U64("create_time");
        attachments.push_back(AttachmentPlace{head->offset, f.String("name")});
        break;
      }
      case records::kChunk:
        // Channels may be defined inside chunks (other writers): register them, count messages.
        ForEachChunkRecord(*head, [&](std::uint8_t opcode, FieldReader& f) {
          if (opcode == records::kSchema) AddSchema(f);
          if (opcode == records::kChannel) AddChannel(f);
          if (opcode == records::kMessage) ++found[ParseMessage(f, head->offset).channel_id];
          return true;
        });
        break;
      default:
        break;  // MessageIndex records and unknown opcodes
    }
  }
  counts = std::move(found);
}

Reader::Reader(const std::filesystem::path& file) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.path = file;
  std::error_code error;
  m.size = std::filesystem::file_size(file, error);
  if (error) throw RecordingError(file, "file", 0, "cannot read: " + error.message());
  m.file.open(file, std::ios::binary);
  if (!m.file) throw RecordingError(file, "file", 0, "cannot open");
  const std::uint64_t magic_size = records::kMagic.size();
  if (m.size < magic_size ||
      !std::ranges::equal(m.ReadAt(0, magic_size, m.Place("Magic", 0)), records::kMagic)) {
    m.Place("Magic", 0).Fail("not an MCAP file (the first 8 bytes are not MCAP's magic)");
  }
  const std::optional<RecordHead> header = m.Head(magic_size, m.size);
  if (!header) m.Place("Header", magic_size).Fail("the file ends inside the Header record");
  if (header->opcode != records::kHeader) {
    m.Place(records::OpcodeName(header->opcode), magic_size)
        .Fail("the first record is not a Header");
  }
  {
    const std::vector<std::uint8_t> content = m.Content(*header);
    const RecordPlace place = m.Place("Header", magic_size);
    FieldReader f(content, place);
    m.profile = f.String("profile");
    m.library = f.String("library");
  }
  m.data_start = header->end();

  // The footer: the 29 bytes before the closing magic.
  const std::uint64_t footer_bytes = records::kRecordPrefixBytes + records::kFooterContentBytes;
  const std::uint64_t footer_offset = m.size - magic_size - footer_bytes;
  bool has_footer = false;
  std::uint64_t summary_start = 0;
  std::uint64_t summary_offset_start = 0;
  std::uint32_t summary_crc = 0;
  if (m.size >= m.data_start + footer_bytes + magic_size &&
      std::ranges::equal(m.ReadAt(m.size - magic_size, magic_size, m.Place("Magic", 0)),
                         records::kMagic)) {
    const std::optional<RecordHead> footer = m.Head(footer_offset, m.size - magic_size);
    if (footer && footer->opcode == records::kFooter &&
        footer->length == records::kFooterContentBytes) {
      has_footer = true;
      const std::vector<std::uint8_t> content = m.Content(*footer);
      const RecordPlace place = m.Place("Footer", footer_offset);
      FieldReader f(content, place);
      summary_start = f.U64("summary_start");
      summary_offset_start = f.U64("summary_offset_start");
      summary_crc = f.U32("summary_crc");
    }
  }
  if (!has_footer) {
    m.truncated = true;
    m.Scan(m.size, true);
    return;
  }
  const RecordPlace footer_place = m.Place("Footer", footer_offset);
  if (summary_start == 0) {  // a complete file without a summary
    if (summary_offset_start != 0) footer_place.Fail("a summary offset without a summary");
    m.Scan(footer_offset, false);
    return;
  }
  if (summary_start < m.data_start || summary_start > footer_offset) {
    footer_place.Fail("summary_start " + std::to_string(summary_start) +
                      " lies outside the file's records");
  }
  if (summary_offset_start != 0 &&
      (summary_offset_start < summary_start || summary_offset_start > footer_offset)) {
    footer_place.Fail("summary_offset_start " + std::to_string(summary_offset_start) +
                      " lies outside the summary");
  }
  if (summary_crc != 0) {
    // Over the summary, the summary offsets and the footer up to its CRC field.
    const std::vector<std::uint8_t> covered =
        m.ReadAt(summary_start, footer_offset + footer_bytes - 4 - summary_start, footer_place);
    if (records::ComputeCrc32(covered) != summary_crc) {
      footer_place.Fail("the summary's CRC does not match the footer's summary_crc");
    }
  }
  m.data_end = summary_start;
  m.ReadSummary(summary_start, summary_offset_start != 0 ? summary_offset_start : footer_offset);
}

Reader::~Reader() = default;

const std::string& Reader::profile() const { return impl_->profile; }
const std::string& Reader::library() const { return impl_->library; }
const std::map<std::uint16_t, Schema>& Reader::schemas() const { return impl_->schemas; }
const std::map<std::uint16_t, Channel>& Reader::channels() const { return impl_->channels; }
bool Reader::truncated() const { return impl_->truncated; }

const Channel* Reader::FindChannel(const std::string& topic) const {
  for (const auto& [id, channel] : impl_->channels) {
    if (channel.topic == topic) return &channel;
  }
  return nullptr;
}

const std::vector<std::pair<std::string, std::map<std::string, std::string>>>& Reader::metadata()
    const {
  return impl_->metadata;
}

std::optional<Attachment> Reader::ReadAttachment(const std::string& name) const {
  const Impl& m = *impl_;
  const auto place_it =
      std::find_if(m.attachments.begin(), m.attachments.end(),
                   [&](const Impl::AttachmentPlace& a) { return a.name == name; });
  if (place_it == m.attachments.end()) return std::nullopt;
  const RecordPlace place = m.Place("Attachment", place_it->offset);
  const RecordHead head = m.RequireHead(place_it->offset, m.data_end, "the data section");
  if (head.opcode != records::kAttachment) {
    place.Fail("the attachment index points at a " + records::OpcodeName(head.opcode));
  }
  const std::vector<std::uint8_t> content = m.Content(head);
  FieldReader f(content, place);
  Attachment attachment;
  attachment.log_time_ns = f.U64("log_time");
  attachment.create_time_ns = f.U64("create_time");
  attachment.name = f.String("name");
  attachment.media_type = f.String("media_type");
  const std::span<const std::uint8_t> data = f.Bytes(f.U64("data"), "data");
  const std::size_t crc_covers = f.position();
  const std::uint32_t crc = f.U32("crc");
  if (crc != 0 && records::ComputeCrc32(std::span(content).first(crc_covers)) != crc) {
    place.Fail("the attachment's CRC does not match its bytes");
  }
  attachment.data.assign(data.begin(), data.end());
  return attachment;
}

void Reader::ForEachMessage(const std::function<bool(const Message&)>& callback,
                            const std::vector<std::uint16_t>& channels) const {
  const Impl& m = *impl_;
  const std::set<std::uint16_t> wanted(channels.begin(), channels.end());
  std::uint64_t offset = m.data_start;
  while (offset < m.data_end) {
    const RecordHead head = m.RequireHead(offset, m.data_end, "the data section");
    offset = head.end();
    if (head.opcode == records::kDataEnd) return;
    if (head.opcode == records::kMessage) {
      const std::vector<std::uint8_t> content = m.Content(head);
      const RecordPlace place = m.Place("Message", head.offset);
      FieldReader f(content, place);
      const Message message = m.ParseMessage(f, 0);
      if (!wanted.empty() && wanted.count(message.channel_id) == 0) continue;
      if (!callback(message)) return;
      continue;
    }
    if (head.opcode != records::kChunk) continue;
    if (!wanted.empty()) {
      const auto indexed = m.chunk_channels.find(head.offset);
      if (indexed != m.chunk_channels.end() &&
          std::none_of(indexed->second.begin(), indexed->second.end(),
                       [&](std::uint16_t id) { return wanted.count(id) > 0; })) {
        continue;  // the summary says none of its messages are wanted
      }
    }
    bool go_on = true;
    m.ForEachChunkRecord(head, [&](std::uint8_t opcode, FieldReader& f) {
      if (opcode != records::kMessage) return true;
      const Message message = m.ParseMessage(f, head.offset);
      if (!wanted.empty() && wanted.count(message.channel_id) == 0) return true;
      go_on = callback(message);
      return go_on;
    });
    if (!go_on) return;
  }
}

std::map<std::uint16_t, std::uint64_t> Reader::MessageCounts() const {
  const Impl& m = *impl_;
  if (!m.counts) {
    std::map<std::uint16_t, std::uint64_t> counted;
    ForEachMessage([&](const Message& message) {
      ++counted[message.channel_id];
      return true;
    });
    m.counts = std::move(counted);
  }
  return *m.counts;
}

}  // namespace corridorsim::mcap

#include "common/io/cdr.h"

#include <bit>
#include <utility>

namespace corridorsim {

static_assert(std::endian::native == std::endian::little,
              "CdrWriter and CdrReader copy primitives as they lie in memory (CDR_LE)");

namespace {
constexpr std::uint8_t kHeader[4] = {0x00, 0x01, 0x00, 0x00};  // CDR_LE, options 0
// A string longer than this is corrupt data, not a message of ours (a frame id, an encoding).
constexpr std::size_t kMaxStringBytes = 1 << 20;
}  // namespace

CdrWriter::CdrWriter() { data_.assign(std::begin(kHeader), std::end(kHeader)); }

CdrWriter::CdrWriter(std::vector<std::uint8_t>&& buffer) : data_(std::move(buffer)) {
  data_.assign(std::begin(kHeader), std::end(kHeader));
}

void CdrWriter::Align(std::size_t size) {
  const std::size_t offset = data_.size() - 4;
  const std::size_t pad = (size - offset % size) % size;
  data_.insert(data_.end(), pad, 0);
}

void CdrWriter::Append(const void* bytes, std::size_t size) {
  const auto* p = static_cast<const std::uint8_t*>(bytes);
  data_.insert(data_.end(), p, p + size);
}

void CdrWriter::String(const std::string& value) {
  Primitive<std::uint32_t>(static_cast<std::uint32_t>(value.size() + 1));
  Append(value.data(), value.size());
  data_.push_back(0);
}

void CdrWriter::SequenceLength(std::size_t count) {
  Primitive<std::uint32_t>(static_cast<std::uint32_t>(count));
}

CdrReader::CdrReader(std::span<const std::uint8_t> data, std::string what)
    : data_(data), what_(std::move(what)) {
  if (data_.size() < 4) Fail("shorter than the 4-byte encapsulation header");
  if (data_[0] != 0x00 || data_[1] != 0x01) {
    Fail("not little-endian CDR (encapsulation " + std::to_string(data_[0]) + " " +
         std::to_string(data_[1]) + ", expected 0 1)");
  }
}

void CdrReader::Fail(const std::string& why) const {
  throw CdrError(what_ + ": " + why + " (at byte " + std::to_string(position_) + " of " +
                 std::to_string(data_.size()) + ")");
}

void CdrReader::Align(std::size_t size) {
  const std::size_t offset = position_ - 4;
  const std::size_t pad = (size - offset % size) % size;
  if (pad > remaining()) Fail("data ends inside padding");
  position_ += pad;
}

const std::uint8_t* CdrReader::Take(std::size_t size) {
  if (size > remaining()) Fail("data ends inside a field");
  const std::uint8_t* p = data_.data() + position_;
  position_ += size;
  return p;
}

bool CdrReader::Bool() {
  const std::uint8_t v = Primitive<std::uint8_t>();
  if (v > 1) Fail("a bool of value " + std::to_string(v));
  return v == 1;
}

std::string CdrReader::String() {
  const std::uint32_t length = Primitive<std::uint32_t>();
  if (length == 0) return {};  // some writers send an empty string as length 0
  if (length > kMaxStringBytes || length > remaining()) {
    Fail("a string of " + std::to_string(length) + " bytes");
  }
  const std::uint8_t* p = Take(length);
  if (p[length - 1] != 0) Fail("a string without its terminating NUL");
  return std::string(reinterpret_cast<const char*>(p), length - 1);
}

std::size_t CdrReader::SequenceLength(std::size_t element_bytes) {
  const std::uint32_t count = Primitive<std::uint32_t>();
  if (element_bytes == 0) element_bytes = 1;
  if (count > remaining() / element_bytes) {
    Fail("a sequence of " + std::to_string(count) + " elements in " + std::to_string(remaining()) +
         " bytes");
  }
  return count;
}

}  // namespace corridorsim

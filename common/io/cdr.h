#pragma once
// OMG CDR as ROS 2 serializes messages (rmw's "cdr" message encoding, XCDR1 little-endian): a
// 4-byte encapsulation header (0x00 0x01 0x00 0x00: CDR_LE), then each primitive aligned to its
// own size (at most 8) relative to the byte after the header, strings as a uint32 length that
// counts the terminating NUL, the bytes and the NUL, sequences as a uint32 count then the
// elements, fixed-size arrays as their elements alone.
//
// CdrReader checks every length against what is left of the data before it allocates, so a
// corrupt message is a CdrError, never a crash or a huge allocation.

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace corridorsim {

class CdrError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class CdrWriter {
 public:
  CdrWriter();  // writes the encapsulation header
  /// The same, reusing `buffer`'s memory (a writer of many large messages avoids allocating and
  /// touching fresh pages for each one).
  explicit CdrWriter(std::vector<std::uint8_t>&& buffer);

  template <class T>
  requires std::is_arithmetic_v<T>
  void Primitive(T value) {
    Align(sizeof(T));
    Append(&value, sizeof(T));
  }
  void Bool(bool value) { Primitive<std::uint8_t>(value ? 1 : 0); }
  void String(const std::string& value);
  /// The count of a sequence (its elements follow).
  void SequenceLength(std::size_t count);
  /// Primitives back to back (a fixed array's or a sequence's elements), aligned once.
  template <class T>
  requires std::is_arithmetic_v<T>
  void Elements(std::span<const T> values) {
    if (values.empty()) return;
    Align(sizeof(T));
    Append(values.data(), values.size_bytes());
  }

  const std::vector<std::uint8_t>& data() const { return data_; }
  std::vector<std::uint8_t> Take() { return std::move(data_); }

 private:
  void Align(std::size_t size);
  void Append(const void* bytes, std::size_t size);
  std::vector<std::uint8_t> data_;
};

class CdrReader {
 public:
  /// `what` names the message in errors ("/front/image_raw message 12").
  CdrReader(std::span<const std::uint8_t> data, std::string what);

  template <class T>
  requires std::is_arithmetic_v<T> T Primitive() {
    Align(sizeof(T));
    T value;
    std::memcpy(&value, Take(sizeof(T)), sizeof(T));
    return value;
  }
  bool Bool();
  std::string String();
  /// A sequence's count, checked: `element_bytes` (at least 1) times it fits in what is left.
  std::size_t SequenceLength(std::size_t element_bytes);
  template <class T>
  requires std::is_arithmetic_v<T>
  void Elements(std::span<T> values) {
    if (values.empty()) return;
    Align(sizeof(T));
    std::memcpy(values.data(), Take(values.size_bytes()), values.size_bytes());
  }
  /// The next `size` bytes as they lie in the data (no copy; valid as long as the data).
  std::span<const std::uint8_t> Bytes(std::size_t size) { return {Take(size), size}; }
  /// Bytes left after the read position.
  std::size_t remaining() const { return data_.size() - position_; }

 private:
  void Align(std::size_t size);
  const std::uint8_t* Take(std::size_t size);
  [[noreturn]] void Fail(const std::string& why) const;
  std::span<const std::uint8_t> data_;
  std::string what_;
  std::size_t position_ = 4;
};

}  // namespace corridorsim

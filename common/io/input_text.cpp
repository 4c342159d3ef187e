#include "common/io/input_text.h"

#include <algorithm>
#include <vector>

namespace corridorsim {

std::size_t Utf8Length(std::string_view text, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char b0 = byte(i);
  if (b0 < 0x80) return 1;
  std::size_t n = 0;
  unsigned char low = 0x80, high = 0xBF;  // the range of the second byte
  if (b0 >= 0xC2 && b0 <= 0xDF) {
    n = 2;
  } else if (b0 >= 0xE0 && b0 <= 0xEF) {
    n = 3;
    if (b0 == 0xE0) low = 0xA0;
    if (b0 == 0xED) high = 0x9F;
  } else if (b0 >= 0xF0 && b0 <= 0xF4) {
    n = 4;
    if (b0 == 0xF0) low = 0x90;
    if (b0 == 0xF4) high = 0x8F;
  } else {
    return 0;
  }
  if (i + n > text.size()) return 0;
  if (byte(i + 1) < low || byte(i + 1) > high) return 0;
  for (std::size_t k = 2; k < n; ++k) {
    if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) return 0;
  }
  return n;
}

std::string InputExcerpt(std::string_view text, std::size_t max_bytes) {
  // Control characters become \xNN; cuts fall between characters, never inside a UTF-8
  // sequence or an escape. Only a window at each end of a long text is looked at.
  const auto escape = [](std::string_view part) {
    std::vector<std::string> chars;  // one entry per character of `part`
    for (std::size_t i = 0; i < part.size();) {
      const auto c = static_cast<unsigned char>(part[i]);
      if (c < 0x20 || c == 0x7F) {
        chars.push_back("\\x" + ByteHex(c).substr(2));
        ++i;
        continue;
      }
      std::size_t n = 1;
      while (i + n < part.size() && (static_cast<unsigned char>(part[i + n]) & 0xC0) == 0x80) ++n;
      chars.emplace_back(part.substr(i, n));
      i += n;
    }
    return chars;
  };
  const std::size_t window = max_bytes + 4;
  if (text.size() <= window) {
    std::string whole;
    for (const std::string& ch : escape(text)) whole += ch;
    if (whole.size() <= max_bytes) return whole;
  }
  const std::size_t room = max_bytes > 3 ? max_bytes - 3 : 0;
  const std::size_t head_room = room * 2 / 3, tail_room = room - head_room;
  std::string head;
  for (const std::string& ch : escape(text.substr(0, std::min(text.size(), window)))) {
    if (head.size() + ch.size() > head_room) break;
    head += ch;
  }
  std::string tail;
  const std::vector<std::string> tail_chars =
      escape(text.substr(text.size() > window ? text.size() - window : 0));
  for (auto it = tail_chars.rbegin(); it != tail_chars.rend(); ++it) {
    if (tail.size() + it->size() > tail_room) break;
    tail.insert(0, *it);
  }
  return head + "..." + tail;
}

std::string PathExcerpt(std::string_view path) { return InputExcerpt(path, kMaxPathInMessage); }

std::string KeyExcerpt(std::string_view key) { return InputExcerpt(key, kMaxKeyInMessage); }

std::string ByteHex(unsigned char byte) {
  static const char* digits = "0123456789abcdef";
  return std::string("0x") + digits[byte >> 4] + digits[byte & 15];
}

bool HasControlCharacter(std::string_view text) {
  return std::any_of(text.begin(), text.end(),
                     [](char ch) { return static_cast<unsigned char>(ch) < 0x20 || ch == 0x7F; });
}

}  // namespace corridorsim

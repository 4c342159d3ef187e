#pragma once
// User text (a path, a key, a value of an input file or the command line) checked and quoted in
// messages: never split inside a UTF-8 character, control characters escaped, long text cut to
// its head and tail. The YAML reader (yaml_reader.h), the include chains and the plugin loader
// (harness/scenario/plugins.cpp) put paths and keys into their messages through it.

#include <cstddef>
#include <string>
#include <string_view>

namespace corridorsim {

/// A path in a message: as typed, unless it is absurdly long (longer: head...tail) or holds
/// control characters.
inline constexpr std::size_t kMaxPathInMessage = 240;
/// A dotted key in a message (it may hold user text: map keys, camera names).
inline constexpr std::size_t kMaxKeyInMessage = 120;

/// The length of the UTF-8 character starting at text[i], or 0 if it is not well formed
/// (overlong forms, surrogates, code points above U+10FFFF and a sequence cut by the end of
/// `text` included). `i` must be less than text.size().
std::size_t Utf8Length(std::string_view text, std::size_t i);

/// User text made safe to put into a message: control characters as `\xNN`, at most `max_bytes`
/// (a longer text keeps its head and tail around "..."), never split inside a UTF-8 character.
std::string InputExcerpt(std::string_view text, std::size_t max_bytes = 80);

/// InputExcerpt(path, kMaxPathInMessage).
std::string PathExcerpt(std::string_view path);
/// InputExcerpt(key, kMaxKeyInMessage).
std::string KeyExcerpt(std::string_view key);

/// A byte as a message names it: "0x1f".
std::string ByteHex(unsigned char byte);

/// Whether `text` holds a control character (a byte below 0x20, or 0x7F): a path with one is
/// refused by name, before any file is looked for.
bool HasControlCharacter(std::string_view text);

}  // namespace corridorsim

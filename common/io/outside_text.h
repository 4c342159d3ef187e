#pragma once
// Text from outside the program (a plugin's label, an exception message, a file name) on its way
// into a text file that is not JSON (JSON goes through stable_json.h's JsonText, which does the
// same): a byte that is not part of a well-formed UTF-8 character becomes U+FFFD, so that the
// file stays UTF-8 text that every reader (the Python package, the pages) accepts.

#include <string>
#include <string_view>

namespace corridorsim {

/// `text` with every byte that is not part of a well-formed UTF-8 character (Utf8Length's rules:
/// no overlong forms, surrogates or code points above U+10FFFF) replaced by U+FFFD (EF BF BD);
/// well-formed text is returned unchanged.
std::string ValidUtf8(std::string_view text);

}  // namespace corridorsim

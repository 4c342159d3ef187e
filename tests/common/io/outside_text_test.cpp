// Tests common/io/outside_text.cpp: bytes that are not UTF-8 become U+FFFD, text stays as it is.
#include "common/io/outside_text.h"

#include <string>

#include <catch2/catch.hpp>

namespace corridorsim {
namespace {

TEST_CASE("each byte that is not UTF-8 becomes U+FFFD; UTF-8 text is unchanged", "[outside_text]") {
  const std::string fffd = "\xEF\xBF\xBD";
  CHECK(ValidUtf8("room 214") == "room 214");
  CHECK(ValidUtf8("\xE5\xA4\xB1\xE6\x95\x97 caf\xC3\xA9 <!--<script>") ==
        "\xE5\xA4\xB1\xE6\x95\x97 caf\xC3\xA9 <!--<script>");
  // Latin-1, an overlong '/', a surrogate, a code point above U+10FFFF, a cut character.
  CHECK(ValidUtf8("caf\xE9") == "caf" + fffd);
  CHECK(ValidUtf8("\xC0\xAF") == fffd + fffd);
  CHECK(ValidUtf8("\xED\xA0\x80") == fffd + fffd + fffd);
  CHECK(ValidUtf8("\xF4\x90\x80\x80") == fffd + fffd + fffd + fffd);
  CHECK(ValidUtf8("ok \xE6\x96") == "ok " + fffd + fffd);
  CHECK(ValidUtf8("") == "");
}

}  // namespace
}  // namespace corridorsim

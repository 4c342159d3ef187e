// Tests common/io/sha256.cpp against the FIPS 180-2 test vectors (Appendix B) and `sha256sum`.
#include "common/io/sha256.h"

#include <string>

#include <catch2/catch.hpp>

namespace corridorsim {
namespace {

TEST_CASE("SHA-256 gives the FIPS 180-2 digests", "[sha256]") {
  // B.1: one block.
  CHECK(Sha256Hex("abc") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  // B.2: two blocks (the padding does not fit the first).
  CHECK(Sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq") ==
        "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  // B.3: one million 'a', 15,625 blocks.
  CHECK(Sha256Hex(std::string(1'000'000, 'a')) ==
        "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST_CASE("SHA-256 pads every length around a block edge as sha256sum does", "[sha256]") {
  // Empty input, and lengths whose padding lands on each side of the 56-byte limit.
  CHECK(Sha256Hex("") == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  CHECK(Sha256Hex(std::string(55, 'a')) ==
        "9f4390f8d30c2dd92ec9f095b65e2b9ae9b0a925a5258e241c9f1e910f734318");
  CHECK(Sha256Hex(std::string(56, 'a')) ==
        "b35439a4ac6f0948b6d6f9e3c6af0f5f590ce20f1bde7090ef7970686ec6738a");
  CHECK(Sha256Hex(std::string(64, 'a')) ==
        "ffe054fe7ae0cb6dc65c3af9b61d5209f439851db43d0ba5997337df154668eb");
  // Bytes above 0x7f are unsigned in the message schedule.
  CHECK(Sha256(std::string(1, '\xff'))[0] == 0xa8);
}

}  // namespace
}  // namespace corridorsim

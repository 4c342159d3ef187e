#pragma once
// SHA-256 (FIPS 180-4, the algorithm of FIPS 180-2) of a byte string, for provenance.json's hash
// of the resolved scenario. Not for security: no crypto library is a dependency, and a run only
// needs a fingerprint that any `sha256sum` reproduces.

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace corridorsim {

/// The 32-byte digest of `bytes`.
std::array<std::uint8_t, 32> Sha256(std::string_view bytes);

/// The digest as 64 lowercase hex digits (what `sha256sum` prints).
std::string Sha256Hex(std::string_view bytes);

}  // namespace corridorsim

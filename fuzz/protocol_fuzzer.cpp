// Fuzzes what corridorsim reads from an external pipeline's program (harness/external/protocol.h):
// the input's first 12 bytes are a message header (DecodeHeader), the rest its JSON, parsed
// (ParseMessage) and read as each reply (ParseReady, ParseEstimate, ParseProcessed,
// ParseFinished, the latter with the input itself as the blob its maps point into).
// ProtocolError (the program's bug: its pipeline fails) is the documented outcome; any other
// exception, a crash or a sanitizer report is a bug of corridorsim.
//
//   scripts/bootstrap.sh fuzz 60   (docs/fuzzing.md; builds build-fuzz/bin/protocol_fuzzer)

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <string_view>
#include <typeinfo>

#include "harness/external/protocol.h"

namespace {

template <class F>
void Expect(const char* what, F&& call) {
  try {
    call();
  } catch (const corridorsim::external::ProtocolError&) {
    // the documented outcome
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s threw %s: %s\n", what, typeid(e).name(), e.what());
    std::abort();
  } catch (...) {
    std::fprintf(stderr, "%s threw a non-standard exception\n", what);
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace ext = corridorsim::external;
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  if (size >= ext::kHeaderBytes) {
    char header[ext::kHeaderBytes];
    std::memcpy(header, data, ext::kHeaderBytes);
    Expect("DecodeHeader", [&] { ext::DecodeHeader(header); });
  }
  const std::string_view json = size >= ext::kHeaderBytes ? input.substr(ext::kHeaderBytes) : input;
  nlohmann::json message;
  bool parsed = false;
  Expect("ParseMessage", [&] {
    message = ext::ParseMessage(json);
    parsed = true;
  });
  if (!parsed) return 0;
  const std::vector<std::string> cameras = {"front", "upward"};
  Expect("ParseReady", [&] { ext::ParseReady(message); });
  Expect("ParseEstimate", [&] {
    ext::ReplyExtras extras;
    ext::ParseEstimate(message, 20000000, &extras);
  });
  Expect("ParseProcessed", [&] {
    ext::ReplyExtras extras;
    ext::ParseProcessed(message, 20000000, cameras, &extras);
  });
  Expect("ParseFinished", [&] { ext::ParseFinished(message, input, 20000000, cameras); });
  return 0;
}

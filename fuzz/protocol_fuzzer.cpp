// Fuzzes what corridorsim reads from an external pipeline's program (harness/external/protocol.h):
// the input's first 12 bytes are a message header (DecodeHeader), the rest its JSON, parsed
// (ParseMessage) and read as each reply (ParseReady, ParseEstimate, ParseProcessed,
// ParseFinished, the latter with the input itself as the blob its maps point into). Then the
// input is read as the connection reads a message off the socket (ProgramConnection::Receive):
// a header whose lengths frame the JSON and the blob that follow (a stream shorter than they say
// is a message the connection never completes), the JSON parsed and read as the reply its
// "type" names, a finish reply's maps pointing into that blob.
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
#include <vector>

#include "harness/external/protocol.h"

namespace {

// Runs `call`: true when it returned, false when it threw ProtocolError (the documented
// outcome); anything else thrown aborts.
template <class F>
bool Expect(const char* what, F&& call) {
  try {
    call();
    return true;
  } catch (const corridorsim::external::ProtocolError&) {
    return false;  // the documented outcome
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s threw %s: %s\n", what, typeid(e).name(), e.what());
    std::abort();
  } catch (...) {
    std::fprintf(stderr, "%s threw a non-standard exception\n", what);
    std::abort();
  }
}

// The message as Receive frames it: header, then json_bytes of JSON, then blob_bytes of blob.
void ReadFramed(std::string_view input) {
  namespace ext = corridorsim::external;
  if (input.size() < ext::kHeaderBytes) return;  // the connection waits for the rest
  char bytes[ext::kHeaderBytes];
  std::memcpy(bytes, input.data(), ext::kHeaderBytes);
  ext::Header header;
  if (!Expect("DecodeHeader (framed)", [&] { header = ext::DecodeHeader(bytes); })) return;
  if (header.json_bytes > ext::kMaxJsonBytes || header.blob_bytes > ext::kMaxBlobBytes) {
    std::fprintf(stderr, "DecodeHeader accepted lengths over their bounds\n");
    std::abort();
  }
  const std::string_view rest = input.substr(ext::kHeaderBytes);
  if (rest.size() < std::size_t{header.json_bytes} + header.blob_bytes) return;  // incomplete
  const std::string_view json = rest.substr(0, header.json_bytes);
  const std::string_view blob = rest.substr(header.json_bytes, header.blob_bytes);
  nlohmann::json message;
  if (!Expect("ParseMessage (framed)", [&] { message = ext::ParseMessage(json); })) return;
  if (!message.is_object() || !message.contains("type") || !message["type"].is_string()) {
    std::fprintf(stderr, "ParseMessage accepted a message without a string \"type\"\n");
    std::abort();
  }
  const std::string type = message["type"].get<std::string>();
  const std::vector<std::string> cameras = {"front", "upward"};
  ext::ReplyExtras extras;
  if (type == "ready") Expect("ParseReady (framed)", [&] { ext::ParseReady(message); });
  if (type == "estimate") {
    Expect("ParseEstimate (framed)", [&] { ext::ParseEstimate(message, 20000000, &extras); });
  }
  if (type == "processed") {
    Expect("ParseProcessed (framed)",
           [&] { ext::ParseProcessed(message, 20000000, cameras, &extras); });
  }
  if (type == "finished") {
    Expect("ParseFinished (framed)", [&] {
      const ext::Finished finished = ext::ParseFinished(message, blob, 20000000, cameras);
      for (const auto& map : finished.maps) {
        if (map.bytes.size() > blob.size()) {
          std::fprintf(stderr, "a map larger than the blob it lies in\n");
          std::abort();
        }
      }
    });
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
  if (!Expect("ParseMessage", [&] { message = ext::ParseMessage(json); })) return 0;
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
  ReadFramed(input);
  return 0;
}

// Fuzzes the MCAP reader (common/io/mcap.h, docs/fuzzing.md): the input is written to a file in
// a private temporary folder and read as a recording is read: the header, the footer and summary
// (or, without them, the scan of the data section), every message of every chunk, the message
// counts, the metadata and an attachment. What the reader accepts must keep its promises: every
// channel names a schema it lists (or none), every message a channel it lists, and a recording
// read without a summary counts exactly the messages it gives.
//
// RecordingError is the documented outcome for a malformed file; any other exception, a crash, a
// sanitizer report (a huge allocation included) or a broken promise is a bug: the target aborts
// and libFuzzer saves the input.
//
//   scripts/bootstrap.sh fuzz 60   (docs/fuzzing.md; builds build-fuzz/bin/mcap_reader_fuzzer)

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <system_error>

#include "common/io/mcap.h"
#include "fuzz/fuzz_checks.h"

namespace {

namespace mcap = corridorsim::mcap;
using corridorsim::fuzz::Bug;

const std::filesystem::path& InputFile() {
  static const std::filesystem::path file = [] {
    char pattern[] = "/tmp/corridorsim_fuzz_mcap_XXXXXX";
    const char* made = ::mkdtemp(pattern);
    if (!made) Bug("mkdtemp failed");
    static std::filesystem::path dir;
    dir = made;
    std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(dir, ignored);
    });
    return dir / "input.mcap";
  }();
  return file;
}

void ReadRecording(const std::filesystem::path& file) {
  const mcap::Reader reader(file);
  for (const auto& [id, channel] : reader.channels()) {
    if (id != channel.id) Bug("channel map key");
    if (channel.schema_id != 0 && reader.schemas().count(channel.schema_id) == 0) {
      Bug("a channel names a schema the reader does not list");
    }
  }
  std::map<std::uint16_t, std::uint64_t> seen;
  reader.ForEachMessage([&](const mcap::Message& message) {
    if (reader.channels().count(message.channel_id) == 0) Bug("a message on an unlisted channel");
    ++seen[message.channel_id];
    return true;
  });
  const std::map<std::uint16_t, std::uint64_t> counts = reader.MessageCounts();
  if (reader.truncated() && counts != seen) Bug("a scanned file's counts differ from its messages");
  if (const std::optional<mcap::Attachment> attachment = reader.ReadAttachment("scenario.yaml")) {
    if (attachment->name != "scenario.yaml") Bug("ReadAttachment returned another attachment");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path& file = InputFile();
  {
    std::filesystem::remove(file);  // a new file each time (no flush of a rewritten one)
    std::ofstream out(file, std::ios::binary);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    if (!out) Bug("cannot write " + file.string());
  }
  try {
    ReadRecording(file);
  } catch (const mcap::RecordingError&) {
    // the documented outcome
  } catch (const std::exception& e) {
    Bug(std::string("an exception other than RecordingError: ") + e.what());
  }
  return 0;
}

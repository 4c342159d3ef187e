// Prints what corridorsim's MCAP reader (common/io/mcap.h) reads from a file, for
// tests/recordings/read_mcap_test.mjs, which compares it with files @mcap/core's McapWriter wrote
// (schemas and channels inside the chunks, with and without a summary, cut short).
//
//   dump_mcap FILE.mcap
//
// One JSON line per message in file order: {"topic", "sequence", "log_time", "publish_time"
// (decimal strings), "length", "sha256"}, then {"summary": {"truncated", "profile", "library",
// "schemas": {id: name}, "channels": {id: topic}, "counts": {topic: n}, "metadata": [[name,
// {k: v}]], "attachment": {name, media_type, length, sha256} or null}}, the attachment being the
// one named by the second argument, if given. Exit 0; 2 with one message for a RecordingError.
#include <iostream>
#include <map>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "common/io/mcap.h"
#include "common/io/sha256.h"

namespace {

namespace mcap = corridorsim::mcap;
using Json = nlohmann::ordered_json;

std::string_view Chars(std::span<const std::uint8_t> bytes) {
  return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2 && argc != 3) {
    std::cerr << "usage: dump_mcap FILE.mcap [ATTACHMENT]\n";
    return 2;
  }
  try {
    const mcap::Reader reader(argv[1]);
    reader.ForEachMessage([&](const mcap::Message& m) {
      Json line;
      line["topic"] = reader.channels().at(m.channel_id).topic;
      line["sequence"] = m.sequence;
      line["log_time"] = std::to_string(m.log_time_ns);
      line["publish_time"] = std::to_string(m.publish_time_ns);
      line["length"] = m.data.size();
      line["sha256"] = corridorsim::Sha256Hex(Chars(m.data));
      std::cout << line.dump() << "\n";
      return true;
    });
    Json summary;
    summary["truncated"] = reader.truncated();
    summary["profile"] = reader.profile();
    summary["library"] = reader.library();
    summary["schemas"] = Json::object();
    for (const auto& [id, schema] : reader.schemas())
      summary["schemas"][std::to_string(id)] = schema.name;
    summary["channels"] = Json::object();
    for (const auto& [id, channel] : reader.channels()) {
      summary["channels"][std::to_string(id)] = channel.topic;
    }
    summary["counts"] = Json::object();
    for (const auto& [id, count] : reader.MessageCounts()) {
      summary["counts"][reader.channels().at(id).topic] = count;
    }
    summary["metadata"] = Json::array();
    for (const auto& [name, map] : reader.metadata()) summary["metadata"].push_back({name, map});
    summary["attachment"] = nullptr;
    if (argc == 3) {
      if (const std::optional<mcap::Attachment> a = reader.ReadAttachment(argv[2])) {
        summary["attachment"] = {{"name", a->name},
                                 {"media_type", a->media_type},
                                 {"length", a->data.size()},
                                 {"sha256", corridorsim::Sha256Hex(Chars(a->data))}};
      }
    }
    std::cout << Json{{"summary", summary}}.dump() << "\n";
  } catch (const mcap::RecordingError& e) {
    std::cerr << "dump_mcap: " << e.what() << "\n";
    return 2;
  }
  return 0;
}

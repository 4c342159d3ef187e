#include "common/io/line_reader.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <vector>

#include "common/error.h"

namespace corridorsim {
namespace {

constexpr std::size_t kChunkBytes = std::size_t{1} << 20;

// Closes the descriptor however the reading ends (a callback may throw).
struct Descriptor {
  int fd = -1;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

void ReadRegularFileLines(const std::filesystem::path& path, std::uint64_t max_bytes,
                          std::size_t max_line_bytes,
                          const std::function<void(std::string_view, std::int64_t)>& line) {
  const auto fail = [&](std::int64_t number, const std::string& message) {
    throw InputError(SourceLocation{path.string(), static_cast<int>(number), 0}, "", message);
  };
  Descriptor file;
  file.fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (file.fd < 0) fail(0, std::string("cannot be opened: ") + std::strerror(errno));
  struct stat info {};
  if (::fstat(file.fd, &info) != 0 || !S_ISREG(info.st_mode)) fail(0, "not a regular file");
  const std::string too_large = "larger than " + std::to_string(max_bytes) + " bytes";
  if (static_cast<std::uint64_t>(info.st_size) > max_bytes) fail(0, too_large);
  const std::string too_long =
      "a line longer than " + std::to_string(max_line_bytes) + " bytes (is this a text file?)";
  std::vector<char> chunk(kChunkBytes);
  std::string carry;  // the start of a line that continues in the next chunk
  std::uint64_t total = 0;
  std::int64_t number = 0;
  for (;;) {
    const ssize_t n = ::read(file.fd, chunk.data(), chunk.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail(0, std::string("cannot be read: ") + std::strerror(errno));
    if (n == 0) break;
    total += static_cast<std::uint64_t>(n);
    if (total > max_bytes) fail(0, too_large);  // grew while read
    const std::string_view data(chunk.data(), static_cast<std::size_t>(n));
    std::size_t begin = 0;
    while (begin < data.size()) {
      const std::size_t end = data.find('\n', begin);
      const std::string_view part =
          data.substr(begin, (end == std::string_view::npos ? data.size() : end) - begin);
      if (carry.size() + part.size() > max_line_bytes) fail(number + 1, too_long);
      if (end == std::string_view::npos) {
        carry.append(part);
        break;
      }
      ++number;
      if (carry.empty()) {
        line(part, number);
      } else {
        carry.append(part);
        line(carry, number);
        carry.clear();
      }
      begin = end + 1;
    }
  }
  if (!carry.empty()) line(carry, number + 1);
}

}  // namespace corridorsim

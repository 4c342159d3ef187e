#include "common/io/supervisor_channel.h"

#include <unistd.h>

#include <cerrno>
#include <mutex>
#include <string>

namespace corridorsim {
namespace {

int g_channel = -1;
std::mutex g_channel_mutex;  // one record at a time, whatever thread writes it

// Writes "<tag><text>\0" whole (a path holds no NUL; it may hold a newline). A write that fails
// (the supervisor gone) is dropped: the supervisor's end is then closed and nobody reads.
void WriteLine(char tag, const std::string& text) {
  if (g_channel < 0) return;
  std::string line;
  line.reserve(text.size() + 2);
  line += tag;
  line += text;
  line += '\0';
  const std::lock_guard<std::mutex> lock(g_channel_mutex);
  std::size_t done = 0;
  while (done < line.size()) {
    const ssize_t n = ::write(g_channel, line.data() + done, line.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    done += static_cast<std::size_t>(n);
  }
}

}  // namespace

void SetSupervisorChannel(int fd) { g_channel = fd; }

void ReportStagingFolder(const std::filesystem::path& path) { WriteLine('+', path.string()); }

void ReportStagingFolderGone(const std::filesystem::path& path) { WriteLine('-', path.string()); }

void ReportJobFinished(int exit_code) { WriteLine('=', std::to_string(exit_code)); }

}  // namespace corridorsim

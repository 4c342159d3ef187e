#include "harness/external/connection.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <thread>

#include "common/io/stable_json.h"
#include "common/io/yaml_reader.h"
#include "harness/external/protocol.h"

namespace corridorsim::external {
namespace {

using Clock = std::chrono::steady_clock;

Clock::time_point DeadlineAfter(std::chrono::duration<double> timeout) {
  return Clock::now() + std::chrono::duration_cast<Clock::duration>(timeout);
}

int MillisecondsUntil(Clock::time_point deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
  if (left.count() <= 0) return 0;
  return static_cast<int>(std::min<long long>(left.count() + 1, 60'000));
}

std::string SecondsText(std::chrono::duration<double> d) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", d.count());
  return text;
}

}  // namespace

ProgramConnection::ProgramConnection(
    const std::vector<std::string>& argv, const std::string& working_dir,
    const std::vector<std::pair<std::string, std::string>>& environment) {
  if (argv.empty()) throw StartError("no command");
  program_ = argv[0];
  int sockets[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sockets) != 0) {
    throw StartError(std::string("socketpair: ") + std::strerror(errno));
  }
  int log_pipe[2];
  if (::pipe2(log_pipe, O_CLOEXEC) != 0) {
    const int e = errno;
    ::close(sockets[0]);
    ::close(sockets[1]);
    throw StartError(std::string("pipe: ") + std::strerror(e));
  }
  ChildOptions options;
  options.output_fd = log_pipe[1];
  options.pass_fds = {sockets[1]};
  options.close_other_fds = true;
  options.working_dir = working_dir;
  options.environment = environment;
  options.own_process_group = true;
  child_ = std::make_unique<ChildProcess>(argv, options);
  ::close(sockets[1]);
  ::close(log_pipe[1]);
  socket_ = sockets[0];
  log_fd_ = log_pipe[0];
  ::fcntl(socket_, F_SETFL, ::fcntl(socket_, F_GETFL) | O_NONBLOCK);
  ::fcntl(log_fd_, F_SETFL, ::fcntl(log_fd_, F_GETFL) | O_NONBLOCK);
  if (const std::optional<ChildStatus> status = child_->Poll(); status && !status->started) {
    ::close(socket_);
    ::close(log_fd_);
    socket_ = log_fd_ = -1;
    throw StartError("cannot start '" + InputExcerpt(program_, 200) + "': " + status->error);
  }
}

ProgramConnection::~ProgramConnection() {
  if (child_) {
    child_->KillGroup();
    child_->Wait();
  }
  if (socket_ >= 0) ::close(socket_);
  if (log_fd_ >= 0) ::close(log_fd_);
}

void ProgramConnection::AppendLog(const char* data, std::size_t n) {
  log_.append(data, n);
  if (log_.size() > 2 * kLogKeepBytes) {
    const std::size_t cut = log_.size() - kLogKeepBytes;
    log_dropped_ += cut;
    log_.erase(0, cut);
  }
}

void ProgramConnection::DrainLog() {
  if (log_fd_ < 0) return;
  char buffer[65536];
  for (;;) {
    const ssize_t got = ::read(log_fd_, buffer, sizeof buffer);
    if (got > 0) {
      AppendLog(buffer, static_cast<std::size_t>(got));
      continue;
    }
    if (got < 0 && errno == EINTR) continue;
    if (got == 0) {  // every writer closed it
      ::close(log_fd_);
      log_fd_ = -1;
    }
    return;  // EAGAIN: nothing more now
  }
}

bool ProgramConnection::WaitFor(short events, Clock::time_point deadline) {
  for (;;) {
    pollfd fds[2] = {{socket_, events, 0}, {log_fd_, POLLIN, 0}};
    const int n = log_fd_ >= 0 ? 2 : 1;
    const int ready = ::poll(fds, static_cast<nfds_t>(n), MillisecondsUntil(deadline));
    if (ready < 0 && errno != EINTR) {
      throw ConnectionError(std::string("poll: ") + std::strerror(errno));
    }
    if (n == 2 && (fds[1].revents & (POLLIN | POLLHUP))) DrainLog();
    if (ready > 0 && fds[0].revents != 0) return true;
    if (Clock::now() >= deadline) return false;
  }
}

std::string ProgramConnection::WhyGone(const std::string& what) {
  // Give it a moment to end (it closed the socket on its way out), then say how it ended.
  const Clock::time_point until = Clock::now() + std::chrono::milliseconds(500);
  std::optional<ChildStatus> status;
  while (!(status = child_->Poll()) && Clock::now() < until) {
    DrainLog();
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  if (!status) return what + " (the program is still running)";
  return what + ": the program " + DescribeChildStatus(*status);
}

void ProgramConnection::Send(const nlohmann::ordered_json& json, std::string_view blob, int fd,
                             std::chrono::duration<double> timeout) {
  const std::string text = JsonText(json);
  const std::string header = EncodeHeader(text.size(), blob.size());
  const std::string_view parts[3] = {header, text, blob};
  const Clock::time_point deadline = DeadlineAfter(timeout);
  bool fd_sent = fd < 0;
  for (const std::string_view part : parts) {
    std::size_t done = 0;
    while (done < part.size()) {
      ssize_t sent = 0;
      if (!fd_sent) {
        // The descriptor rides on the first byte (SCM_RIGHTS).
        iovec io{const_cast<char*>(part.data()), part.size()};
        alignas(cmsghdr) char control[CMSG_SPACE(sizeof(int))] = {};
        msghdr message{};
        message.msg_iov = &io;
        message.msg_iovlen = 1;
        message.msg_control = control;
        message.msg_controllen = sizeof control;
        cmsghdr* c = CMSG_FIRSTHDR(&message);
        c->cmsg_level = SOL_SOCKET;
        c->cmsg_type = SCM_RIGHTS;
        c->cmsg_len = CMSG_LEN(sizeof(int));
        std::memcpy(CMSG_DATA(c), &fd, sizeof fd);
        sent = ::sendmsg(socket_, &message, MSG_NOSIGNAL);
        if (sent > 0) fd_sent = true;
      } else {
        sent = ::send(socket_, part.data() + done, part.size() - done, MSG_NOSIGNAL);
      }
      if (sent > 0) {
        done += static_cast<std::size_t>(sent);
        continue;
      }
      if (sent < 0 && errno == EINTR) continue;
      if (sent < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
        if (!WaitFor(POLLOUT, deadline)) {
          throw ConnectionError("timeout: the program read no '" + MessageType(json) +
                                "' message for " + SecondsText(timeout) + " s");
        }
        continue;
      }
      throw ConnectionError(
          WhyGone("the connection closed while sending '" + MessageType(json) + "'"));
    }
  }
}

Received ProgramConnection::Receive(std::chrono::duration<double> timeout) {
  const Clock::time_point deadline = DeadlineAfter(timeout);
  const auto read_exactly = [&](char* data, std::size_t size, const char* what) {
    std::size_t done = 0;
    while (done < size) {
      const ssize_t got = ::recv(socket_, data + done, size - done, 0);
      if (got > 0) {
        done += static_cast<std::size_t>(got);
        continue;
      }
      if (got == 0) {
        throw ConnectionError(WhyGone(done == 0 && std::strcmp(what, "header") == 0
                                          ? "no reply"
                                          : std::string("the connection closed inside a "
                                                        "message's ") +
                                                what));
      }
      if (errno == EINTR) continue;
      if (errno == EAGAIN || errno == EWOULDBLOCK) {
        if (!WaitFor(POLLIN, deadline)) {
          throw ConnectionError("timeout: no reply within timeout_s = " + SecondsText(timeout) +
                                " s");
        }
        continue;
      }
      throw ConnectionError(WhyGone(std::string("recv: ") + std::strerror(errno)));
    }
  };
  char header_bytes[kHeaderBytes];
  read_exactly(header_bytes, kHeaderBytes, "header");
  Header header;
  try {
    header = DecodeHeader(header_bytes);
  } catch (const ProtocolError& e) {
    throw ConnectionError(e.what());
  }
  std::string text(header.json_bytes, '\0');
  read_exactly(text.data(), text.size(), "JSON");
  Received received;
  received.blob.assign(header.blob_bytes, '\0');
  read_exactly(received.blob.data(), received.blob.size(), "blob");
  try {
    received.json = ParseMessage(text);
  } catch (const ProtocolError& e) {
    throw ConnectionError(e.what());
  }
  return received;
}

std::optional<ChildStatus> ProgramConnection::Close(std::chrono::duration<double> grace) {
  if (socket_ >= 0) {
    ::close(socket_);
    socket_ = -1;
  }
  const Clock::time_point deadline = DeadlineAfter(grace);
  std::optional<ChildStatus> status;
  while (!(status = child_->Poll())) {
    if (Clock::now() >= deadline) break;
    if (log_fd_ >= 0) {
      pollfd p{log_fd_, POLLIN, 0};
      ::poll(&p, 1, std::min(MillisecondsUntil(deadline), 20));
      DrainLog();
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }
  Kill();
  return status;
}

void ProgramConnection::Kill() {
  child_->KillGroup();
  child_->Wait();
  // What the group wrote before it died: the pipe ends once every writer is gone; a writer that
  // escaped the group (setsid) cannot hold this up for more than a moment.
  const Clock::time_point until = Clock::now() + std::chrono::milliseconds(200);
  while (log_fd_ >= 0 && Clock::now() < until) {
    pollfd p{log_fd_, POLLIN, 0};
    ::poll(&p, 1, 20);
    DrainLog();
  }
}

std::string ProgramConnection::Log() const {
  // The last kLogKeepBytes, from the start of a line where one begins in the first KiB of them.
  std::size_t cut = log_.size() > kLogKeepBytes ? log_.size() - kLogKeepBytes : 0;
  if (cut > 0) {
    const std::size_t newline = log_.find('\n', cut);
    if (newline != std::string::npos && newline - cut < 1024) cut = newline + 1;
  }
  const std::size_t dropped = log_dropped_ + cut;
  if (dropped == 0) return log_;
  return "[corridorsim: the first " + std::to_string(dropped) +
         " bytes of the program's output are left out]\n" + log_.substr(cut);
}

std::string ProgramConnection::LogTail(std::size_t lines, std::size_t max_bytes) const {
  std::size_t start = log_.size();
  // Trailing newlines do not count as lines.
  while (start > 0 && log_[start - 1] == '\n') --start;
  const std::size_t end = start;
  std::size_t found = 0;
  while (start > 0 && found < lines) {
    --start;
    if (log_[start] == '\n') ++found;
  }
  if (found == lines) ++start;  // past that newline
  std::string tail = log_.substr(start, end - start);
  if (tail.size() > max_bytes) tail = tail.substr(tail.size() - max_bytes);
  // One line for a reason: the program's lines joined by " | ".
  std::string joined;
  for (const char c : tail) joined += c == '\n' ? std::string(" | ") : std::string(1, c);
  return InputExcerpt(joined, max_bytes + 256);
}

}  // namespace corridorsim::external

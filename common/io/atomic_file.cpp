#include "common/io/atomic_file.h"

#include <sys/stat.h>

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

#include "common/error.h"
#include "common/io/supervisor_channel.h"

namespace corridorsim {
namespace {

// A name no other writer (process or thread) uses at the same time: `.<stem>.<what>.<pid>.<n>`.
std::filesystem::path UniqueSibling(const std::filesystem::path& path, std::string_view what) {
  static std::atomic<unsigned long> counter{0};
  const std::string name = "." + path.filename().string() + "." + std::string(what) + "." +
                           std::to_string(::getpid()) + "." + std::to_string(counter++);
  return path.parent_path() / name;
}

std::string Quoted(const std::filesystem::path& path) { return "'" + path.string() + "'"; }

void RemoveQuietly(const std::filesystem::path& path) {
  std::error_code ignored;
  std::filesystem::remove(path, ignored);
}

}  // namespace

void WriteFileAtomic(const std::filesystem::path& path, std::string_view bytes) {
  if (path.filename().empty()) {
    throw std::runtime_error("cannot write " + Quoted(path) + ": not a file name");
  }
  const std::filesystem::path tmp = UniqueSibling(path, "tmp");
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) {
      const std::string reason = std::strerror(errno);
      throw std::runtime_error("cannot write " + Quoted(path) + ": cannot create " + Quoted(tmp) +
                               ": " + reason);
    }
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.flush();
    if (!out) {
      RemoveQuietly(tmp);
      throw std::runtime_error("cannot write " + Quoted(path) + ": writing " + Quoted(tmp) +
                               " failed (disk full?)");
    }
  }
  std::error_code error;
  std::filesystem::rename(tmp, path, error);
  if (error) {
    RemoveQuietly(tmp);
    throw std::runtime_error("cannot write " + Quoted(path) + ": rename from " + Quoted(tmp) +
                             " failed: " + error.message());
  }
}

void EnsureWritableDirectory(const std::filesystem::path& dir) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) {
    throw std::runtime_error("cannot create output folder " + Quoted(dir) + ": " + error.message());
  }
  if (!std::filesystem::is_directory(dir, error)) {
    throw std::runtime_error("output folder " + Quoted(dir) + " is not a directory");
  }
  const std::filesystem::path probe = UniqueSibling(dir / "write_probe", "probe");
  {
    std::ofstream out(probe, std::ios::binary | std::ios::trunc);
    if (!out) {
      const std::string reason = std::strerror(errno);
      throw std::runtime_error("output folder " + Quoted(dir) + " is not writable: " + reason);
    }
  }
  std::filesystem::remove(probe, error);
  if (error) {
    throw std::runtime_error("output folder " + Quoted(dir) + ": cannot remove probe file " +
                             Quoted(probe) + ": " + error.message());
  }
}

namespace {

bool IsEmptyDirectory(const std::filesystem::path& dir) {
  return std::filesystem::directory_iterator(dir) == std::filesystem::directory_iterator();
}

// `parent` is `child` or one of its ancestors (both absolute and normal).
bool IsSameOrAncestor(const std::filesystem::path& parent, const std::filesystem::path& child) {
  auto p = parent.begin();
  auto c = child.begin();
  for (; p != parent.end(); ++p, ++c) {
    if (c == child.end() || *p != *c) return false;
  }
  return true;
}

// Whether process `pid` still runs: it exists and is not a zombie. A job killed with its whole
// tree (a CI timeout, CMake's execute_process TIMEOUT) is reparented to init when its supervisor
// dies with it and stays a zombie until init reaps it: its staging folder is stale already.
bool ProcessRuns(pid_t pid) {
  if (::kill(pid, 0) != 0 && errno == ESRCH) return false;
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text;
  if (!stat || !std::getline(stat, text)) return true;  // no /proc: assume it runs
  const std::size_t close = text.rfind(')');            // the name may hold spaces and ')'
  if (close == std::string::npos || close + 2 >= text.size()) return true;
  const char state = text[close + 2];
  return state != 'Z' && state != 'X';
}

// Removes `.<name>.partial-<pid>[.old]` folders beside the target whose process no longer runs (a
// killed job's staging folder, or the previous folder a killed Commit did not get to remove).
void RemoveStaleStaging(const std::filesystem::path& parent, const std::string& name) {
  const std::string prefix = "." + name + ".partial-";
  std::error_code error;
  std::filesystem::directory_iterator it(parent, error);
  if (error) return;
  for (const std::filesystem::directory_entry& entry : it) {
    const std::string entry_name = entry.path().filename().string();
    if (entry_name.compare(0, prefix.size(), prefix) != 0) continue;
    std::string digits = entry_name.substr(prefix.size());
    if (digits.size() > 4 && digits.compare(digits.size() - 4, 4, ".old") == 0) {
      digits.resize(digits.size() - 4);
    }
    if (digits.empty() || digits.size() > 9 ||
        digits.find_first_not_of("0123456789") != std::string::npos) {
      continue;
    }
    const pid_t pid = static_cast<pid_t>(std::stol(digits));
    const bool ours = pid == ::getpid();  // left by an earlier process with this pid
    if (ours || !ProcessRuns(pid)) {
      std::error_code ignored;
      std::filesystem::remove_all(entry.path(), ignored);
    }
  }
}

}  // namespace

std::filesystem::path NormalOutputFolder(const std::filesystem::path& dir) {
  if (dir.empty()) throw std::runtime_error("the output folder is an empty path");
  std::error_code error;
  std::filesystem::path normal = std::filesystem::absolute(dir, error).lexically_normal();
  if (error) {
    throw std::runtime_error("output folder " + Quoted(dir) + ": " + error.message());
  }
  if (normal.filename().empty()) normal = normal.parent_path();  // "out/run/"
  if (normal.filename().empty() || normal == normal.root_path()) {
    throw std::runtime_error("output folder " + Quoted(dir) + " names no folder of its own");
  }
  return normal;
}

StagedDirectory::StagedDirectory(const std::filesystem::path& target, bool replace_existing)
    : target_(NormalOutputFolder(target)), replace_existing_(replace_existing) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::path cwd = fs::current_path(error).lexically_normal();
  const fs::path resolved = fs::weakly_canonical(target_, error);
  if (!error && IsSameOrAncestor(resolved, cwd)) {
    throw std::runtime_error("output folder " + Quoted(target) +
                             " is the current folder or contains it; choose a folder below it");
  }
  const fs::file_status status = fs::status(target_, error);
  if (fs::exists(status)) {
    if (!fs::is_directory(status)) {
      throw std::runtime_error("output folder " + Quoted(target) + " is not a directory");
    }
    if (!replace_existing_ && !IsEmptyDirectory(target_)) {
      throw FolderNotEmptyError("output folder " + Quoted(target) + " is not empty");
    }
    // Replacing deletes the previous folder: only one that a job of ours wrote whole.
    if (replace_existing_ && !IsEmptyDirectory(target_) &&
        !fs::is_regular_file(fs::symlink_status(target_ / kOutputFolderMarker, error))) {
      throw std::runtime_error("output folder " + Quoted(target) +
                               " holds files that no corridorsim job wrote (it has no " +
                               std::string(kOutputFolderMarker) +
                               "); --force replaces only corridorsim's own output folders: "
                               "choose another folder");
    }
  }
  fs::create_directories(target_.parent_path(), error);
  if (error) {
    throw std::runtime_error("cannot create output folder " + Quoted(target) + ": " +
                             error.message());
  }
  const std::string name = target_.filename().string();
  RemoveStaleStaging(target_.parent_path(), name);
  staging_ = target_.parent_path() / ("." + name + ".partial-" + std::to_string(::getpid()));
  ReportStagingFolder(staging_);  // before it exists: removed whatever ends this process
  if (!fs::create_directory(staging_, error) || error) {
    const std::string reason = error ? error.message() : "it exists";
    ReportStagingFolderGone(staging_);
    staging_.clear();
    throw std::runtime_error("output folder " + Quoted(target) + ": cannot create " +
                             "the staging folder beside it: " + reason);
  }
  try {
    EnsureWritableDirectory(staging_);
    WriteFileAtomic(staging_ / kOutputFolderMarker,
                    "This folder was written whole by one corridorsim job; `--force` may replace "
                    "it whole.\n");
  } catch (...) {
    fs::remove_all(staging_, error);
    ReportStagingFolderGone(staging_);
    staging_.clear();
    throw;
  }
}

StagedDirectory::~StagedDirectory() {
  if (committed_ || staging_.empty()) return;
  std::error_code ignored;
  std::filesystem::remove_all(staging_, ignored);
  ReportStagingFolderGone(staging_);
}

void StagedDirectory::Commit() {
  namespace fs = std::filesystem;
  if (committed_) throw std::logic_error("StagedDirectory::Commit twice");
  std::error_code error;
  const bool target_exists = fs::exists(fs::symlink_status(target_, error));
  if (target_exists && !replace_existing_ && fs::is_directory(target_, error) &&
      !IsEmptyDirectory(target_)) {
    throw FolderNotEmptyError("output folder " + Quoted(target_) + " got files while the job ran");
  }
  const auto fail = [&](const std::string& what, int err) {
    throw std::runtime_error("cannot move " + Quoted(staging_) + " to " + Quoted(target_) + ": " +
                             what + ": " + std::strerror(err));
  };
  fs::path previous;  // where the previous folder ends up
  if (target_exists) {
    // One atomic swap: the target is the new folder, the staging name the previous one.
    previous = staging_;
    if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) != 0) {
      if (errno != EINVAL && errno != ENOSYS) fail("exchange", errno);
      // A file system without RENAME_EXCHANGE: move the previous folder aside first.
      previous = staging_.string() + ".old";
      if (::rename(target_.c_str(), previous.c_str()) != 0)
        fail("moving the previous aside", errno);
      if (::rename(staging_.c_str(), target_.c_str()) != 0) {
        const int err = errno;
        ::rename(previous.c_str(), target_.c_str());
        fail("rename", err);
      }
    }
  } else if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, target_.c_str(), RENAME_NOREPLACE) !=
             0) {
    if (errno != EINVAL && errno != ENOSYS) fail("rename", errno);
    if (::rename(staging_.c_str(), target_.c_str()) != 0) fail("rename", errno);
  }
  committed_ = true;
  // A previous folder left here by a killed process is removed by the next job.
  if (!previous.empty()) fs::remove_all(previous, error);
  ReportStagingFolderGone(staging_);
}

std::string ReadRegularFile(const std::filesystem::path& path, std::uint64_t max_bytes) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  const auto fail = [&](const std::string& message) {
    throw InputError(SourceLocation{path.string(), 0, 0}, "", message);
  };
  if (fd < 0) fail(std::string("cannot be opened: ") + std::strerror(errno));
  struct stat info {};
  std::string text, problem;
  if (::fstat(fd, &info) != 0 || !S_ISREG(info.st_mode)) {
    problem = "not a regular file";
  } else if (static_cast<std::uint64_t>(info.st_size) > max_bytes) {
    problem = "larger than " + std::to_string(max_bytes) + " bytes";
  } else {
    text.reserve(static_cast<std::size_t>(info.st_size));
    char buffer[65536];
    for (;;) {
      const ssize_t n = ::read(fd, buffer, sizeof(buffer));
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) {
        problem = std::string("cannot be read: ") + std::strerror(errno);
        break;
      }
      if (n == 0) break;
      text.append(buffer, static_cast<std::size_t>(n));
      if (text.size() > max_bytes) {
        problem = "larger than " + std::to_string(max_bytes) + " bytes";
        break;
      }
    }
  }
  ::close(fd);
  if (!problem.empty()) fail(problem);
  return text;
}

}  // namespace corridorsim

#include "common/io/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

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

}  // namespace corridorsim

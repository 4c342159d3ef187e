#include "common/io/yaml_reader.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <set>

#include "common/io/input_text.h"

// A scenario file and its include chain (yaml_reader.h: YamlDocument::Load, LoadWithIncludes):
// the file read once, safely (a regular file of at most kMaxYamlFileBytes, opened without
// blocking), and the `include:` keys followed base-first, cycles and over-long chains refused at
// the `include:` line.

namespace corridorsim {
namespace {

// ---- Files --------------------------------------------------------------------------------------

// The identity of an opened file, for include cycles: a link or another spelling of the same
// path is the same file.
struct FileId {
  dev_t device = 0;
  ino_t inode = 0;
  bool operator<(const FileId& o) const {
    return device != o.device ? device < o.device : inode < o.inode;
  }
};

constexpr const char* kDoesNotExist = "does not exist";

std::string KindOf(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

// Why open(2) failed, as the rest of "included file 'x' ..." (never the file's content).
std::string OpenProblem(const std::string& path, int error) {
  switch (error) {
    case ENOENT: {
      struct stat link {};
      if (::lstat(path.c_str(), &link) == 0 && S_ISLNK(link.st_mode)) {
        return "is a symbolic link to nothing (dangling)";
      }
      return kDoesNotExist;
    }
    case ELOOP:
      return "cannot be opened: too many levels of symbolic links (a link loop?)";
    case ENAMETOOLONG:
      return "cannot be opened: its name is longer than the system allows";
    case ENOTDIR:
      return "cannot be opened: a part of its path is not a folder";
    case EACCES:
    case EPERM:
      return "cannot be opened: permission denied";
    case EISDIR:
      return "is a folder, not a regular file";
    default:
      return std::string("cannot be opened: ") + std::strerror(error);
  }
}

// Reads a regular file of at most kMaxYamlFileBytes into `text`, once. Opening never blocks
// (O_NONBLOCK: a FIFO without a writer would otherwise wait forever in open()), and the opened
// descriptor is what is checked, so the file cannot be swapped between the check and the read.
// On failure returns false with `why` set.
bool ReadRegularFile(const std::string& path, std::string& text, FileId& id, std::string& why) {
  if (path.find('\0') != std::string::npos) {
    why = "cannot be opened: its name contains a NUL character";
    return false;
  }
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    why = OpenProblem(path, errno);
    return false;
  }
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    why = std::string("cannot be read: ") + std::strerror(errno);
    return false;
  }
  if (!S_ISREG(st.st_mode)) {
    why = "is " + KindOf(st.st_mode) + ", not a regular file";
    return false;
  }
  const std::string too_large =
      "is larger than the limit of " + std::to_string(kMaxYamlFileBytes) + " bytes (1 MiB)";
  if (st.st_size < 0 || static_cast<std::uint64_t>(st.st_size) > kMaxYamlFileBytes) {
    why = too_large;
    return false;
  }
  id = FileId{st.st_dev, st.st_ino};
  // The size fstat reports is a hint (it may grow, /proc files say 0): read until the end, but
  // never more than the limit plus one byte.
  text.clear();
  text.reserve(static_cast<std::size_t>(st.st_size));
  char buffer[1 << 16];
  while (true) {
    const ssize_t n = ::read(fd, buffer, sizeof(buffer));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      why = std::string("cannot be read: ") + std::strerror(errno);
      return false;
    }
    if (n == 0) break;
    text.append(buffer, static_cast<std::size_t>(n));
    if (text.size() > kMaxYamlFileBytes) {
      why = too_large;
      return false;
    }
  }
  return true;
}

// Reads and parses `path`; a file problem is an error at `include_at` (the `include:` line of the
// including file) when given, else at the file itself.
YamlDocument LoadFile(const std::string& path, const SourceLocation* include_at, FileId& id) {
  std::string text, why;
  if (!ReadRegularFile(path, text, id, why)) {
    if (include_at) {
      throw InputError(*include_at, "include", "included file '" + PathExcerpt(path) + "' " + why);
    }
    throw InputError(
        SourceLocation{PathExcerpt(path), 0, 0}, "",
        why == kDoesNotExist ? "cannot open the file" : "cannot open the file: it " + why);
  }
  return YamlDocument::FromString(text, path);
}

}  // namespace

YamlDocument YamlDocument::Load(const std::string& path) {
  FileId id;
  return LoadFile(path, nullptr, id);
}

std::vector<YamlDocument> LoadWithIncludes(const std::string& path) {
  std::vector<YamlDocument> chain;
  FileId id;
  chain.push_back(LoadFile(path, nullptr, id));
  std::set<FileId> visited{id};
  while (true) {
    const YamlDocument& current = chain.back();
    const YAML::Node include = current.root["include"];
    if (!include) break;
    SourceLocation where = current.LocationOf(include);
    if (!include.IsScalar() || include.Scalar().empty()) {
      throw InputError(where, "include", "expected the path of a scenario file");
    }
    const std::string& name = include.Scalar();
    if (HasControlCharacter(name)) {
      throw InputError(where, "include",
                       "the path '" + PathExcerpt(name) + "' contains a control character");
    }
    if (static_cast<int>(chain.size()) >= kMaxIncludeChain) {
      throw InputError(where, "include",
                       "the include chain is longer than " + std::to_string(kMaxIncludeChain) +
                           " files, the limit");
    }
    std::filesystem::path target(name);
    if (target.is_relative()) target = std::filesystem::path(current.file).parent_path() / target;
    YamlDocument next = LoadFile(target.string(), &where, id);
    if (!visited.insert(id).second) {
      throw InputError(where, "include",
                       "include cycle through '" + PathExcerpt(target.string()) + "'");
    }
    chain.push_back(std::move(next));
  }
  return {std::make_move_iterator(chain.rbegin()), std::make_move_iterator(chain.rend())};
}

}  // namespace corridorsim

#pragma once
// Writing output files so that a killed run never leaves one that looks complete: the bytes go to
// a temporary file in the same folder, which is then renamed over the target (rename is atomic
// within one file system). Whole output folders go the same way (StagedDirectory).

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace corridorsim {

/// Reads a regular file of at most `max_bytes` (input a user names: a detections file, a map),
/// once. Opening never blocks (O_NONBLOCK: a FIFO would wait for a writer) and the opened
/// descriptor is what is checked. Throws InputError naming the path: cannot be opened, not a
/// regular file, larger than max_bytes, cannot be read.
std::string ReadRegularFile(const std::filesystem::path& path, std::uint64_t max_bytes);

/// Writes `bytes` to `path` through `.<name>.tmp.<pid>.<n>` in the same folder and a rename. The
/// folder must exist. Throws std::runtime_error naming `path` on failure (the temporary file is
/// removed).
void WriteFileAtomic(const std::filesystem::path& path, std::string_view bytes);

/// Creates `dir` (and its parents) if needed and proves it is writable by creating and removing a
/// probe file. Throws std::runtime_error naming `dir` otherwise.
void EnsureWritableDirectory(const std::filesystem::path& dir);

/// A target folder that holds files and may not be replaced (StagedDirectory without
/// `replace_existing`).
class FolderNotEmptyError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// An output folder written whole: the files go into a staging folder beside the target
/// (`.<name>.partial-<pid>` in the same parent), and Commit() puts it in the target's place in one
/// rename (Linux RENAME_EXCHANGE when a folder is there; the previous folder is then removed). A
/// folder never holds files of two jobs, and a job that fails or is killed before Commit leaves
/// the previous folder untouched. Staging folders of processes that no longer run are removed
/// when the next job stages the same target.
class StagedDirectory {
 public:
  /// The file every staged folder holds from its creation: `replace_existing` replaces only a
  /// folder that has it (a folder some corridorsim job wrote), never one a user filled.
  static constexpr const char* kOutputFolderMarker = ".corridorsim-output";

  /// Checks the target and creates the staging folder (and the target's parents). The target
  /// may be missing or an empty folder; a folder with files is replaced only when
  /// `replace_existing` (else FolderNotEmptyError) and only when it holds kOutputFolderMarker.
  /// Throws std::runtime_error naming the folder when it is not a folder, is the current folder or
  /// contains it, or cannot be written.
  StagedDirectory(const std::filesystem::path& target, bool replace_existing);
  ~StagedDirectory();  // not committed: removes the staging folder
  StagedDirectory(const StagedDirectory&) = delete;
  StagedDirectory& operator=(const StagedDirectory&) = delete;

  /// Where the job writes: the staging folder, and the target once committed.
  const std::filesystem::path& path() const { return committed_ ? target_ : staging_; }
  /// The target as an absolute, normalised path.
  const std::filesystem::path& target() const { return target_; }
  bool committed() const { return committed_; }

  /// Moves the staging folder into the target's place. Throws std::runtime_error naming both
  /// folders on failure (the previous folder is then untouched). Once only.
  void Commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path staging_;
  bool replace_existing_;
  bool committed_ = false;
};

/// The absolute, lexically normal form of an output folder's path ("out/run/" and
/// "./out/run" are one folder). Throws std::runtime_error for a path that names no folder of its
/// own (empty, "/").
std::filesystem::path NormalOutputFolder(const std::filesystem::path& dir);

}  // namespace corridorsim

#pragma once
// Writing output files so that a killed run never leaves one that looks complete: the bytes go to
// a temporary file in the same folder, which is then renamed over the target (rename is atomic
// within one file system).

#include <filesystem>
#include <string_view>

namespace corridorsim {

/// Writes `bytes` to `path` through `.<name>.tmp.<pid>.<n>` in the same folder and a rename. The
/// folder must exist. Throws std::runtime_error naming `path` on failure (the temporary file is
/// removed).
void WriteFileAtomic(const std::filesystem::path& path, std::string_view bytes);

/// Creates `dir` (and its parents) if needed and proves it is writable by creating and removing a
/// probe file. Throws std::runtime_error naming `dir` otherwise.
void EnsureWritableDirectory(const std::filesystem::path& dir);

}  // namespace corridorsim

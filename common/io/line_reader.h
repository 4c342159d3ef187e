#pragma once
// Large text files read line by line: a trajectory of ten million poses is never held whole
// (harness/evaluate/trajectory_file.h). The file is opened as ReadRegularFile opens one (never
// blocking, a regular file only, bounded) and read in fixed chunks.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string_view>

namespace corridorsim {

/// Calls `line(text, number)` for every line of the regular file `path` in order: `text` without
/// its LF (a CR before it is kept: the caller decides), `number` 1-based; a last line without LF
/// counts. Memory is one chunk and one line, whatever the file's size. Throws InputError naming
/// the path (cannot be opened, not a regular file, larger than `max_bytes`, cannot be read) or
/// path:number (a line longer than `max_line_bytes`); whatever `line` throws passes through.
void ReadRegularFileLines(const std::filesystem::path& path, std::uint64_t max_bytes,
                          std::size_t max_line_bytes,
                          const std::function<void(std::string_view, std::int64_t)>& line);

}  // namespace corridorsim

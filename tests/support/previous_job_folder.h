// An output folder as a previous corridorsim job left it, for tests of what a new job may do
// with it (StagedDirectory, StageOutputFolder).
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "common/io/atomic_file.h"

namespace corridorsim::test {

/// Makes `folder` a previous job's output: StagedDirectory's marker and `files` (a path under
/// `folder`, its bytes; the folders on the way are made).
inline void WritePreviousJobFolder(const std::filesystem::path& folder,
                                   const std::vector<std::pair<std::string, std::string>>& files) {
  std::filesystem::create_directories(folder);
  WriteFileAtomic(folder / StagedDirectory::kOutputFolderMarker, "");
  for (const auto& [name, bytes] : files) {
    std::filesystem::create_directories((folder / name).parent_path());
    WriteFileAtomic(folder / name, bytes);
  }
}

}  // namespace corridorsim::test

#include "common/installation.h"

#include <dlfcn.h>

#include <cstdlib>
#include <system_error>

namespace corridorsim {

std::filesystem::path SdkLibraryFile() {
  Dl_info info{};
  // The address of a function of this library: dladdr names the object that holds it.
  if (dladdr(reinterpret_cast<const void*>(&SdkLibraryFile), &info) == 0 || !info.dli_fname) {
    return {};
  }
  std::error_code error;
  std::filesystem::path file = std::filesystem::weakly_canonical(info.dli_fname, error);
  if (error) file = std::filesystem::absolute(info.dli_fname, error);
  return error ? std::filesystem::path() : file;
}

std::filesystem::path DataDir() {
  if (const char* dir = std::getenv(kDataDirVariable); dir && *dir) {
    return std::filesystem::path(dir);
  }
  const std::filesystem::path library = SdkLibraryFile();
  // CORRIDORSIM_LIB_TO_DATA: the relative path from the library folder to the data folder,
  // computed by CMake from GNUInstallDirs (common/CMakeLists.txt), e.g. "../share/corridorsim".
  const std::filesystem::path relative(CORRIDORSIM_LIB_TO_DATA);
  if (library.empty()) return relative;  // the loader cannot say: as good a guess as any
  return (library.parent_path() / relative).lexically_normal();
}

std::filesystem::path PythonPackageDir() {
  const std::filesystem::path library = SdkLibraryFile();
  if (library.empty()) return {};
  return (library.parent_path() / CORRIDORSIM_LIB_TO_PYTHON).lexically_normal();
}

std::string PythonPathWithPackage() {
  const std::filesystem::path package = PythonPackageDir();
  const char* old = std::getenv("PYTHONPATH");
  const std::string inherited = old != nullptr ? old : "";
  if (package.empty()) return inherited;
  return package.string() + (inherited.empty() ? "" : ":" + inherited);
}

}  // namespace corridorsim

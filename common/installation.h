#pragma once
// Where corridorsim's data lies at run time: the shipped scenarios and studies, the trained
// detector models and the plot scripts. One rule for the build tree and an installed tree:
// `<the folder of libcorridorsim_common.so>/<libdir -> datadir>/corridorsim`, which is
// `<prefix>/share/corridorsim` once installed (`cmake --install`, the Debian package) and
// `<build>/share/corridorsim` in a build tree (links to the checkout's folders, made at
// configure time). CORRIDORSIM_DATA_DIR, when set, names the folder instead. No path of the
// source or build tree is compiled in (docs/install.md).

#include <filesystem>
#include <string>

namespace corridorsim {

/// The environment variable that overrides the data folder.
inline constexpr const char* kDataDirVariable = "CORRIDORSIM_DATA_DIR";

/// The data folder (see above). It may lack a file: callers name the file they miss and this
/// folder in their message.
std::filesystem::path DataDir();

/// The folder that holds the Python package `corridorsim` (docs/protocol.md):
/// `<prefix>/lib/python3/dist-packages` of the prefix the library is installed in (in a build
/// tree, build/lib/python3/dist-packages, a link to python/); empty if the loader cannot say where
/// the library is.
std::filesystem::path PythonPackageDir();

/// PYTHONPATH for the Python programs corridorsim starts (plot scripts, the viewer, external
/// pipelines): PythonPackageDir() first, then this process's PYTHONPATH; this process's
/// PYTHONPATH alone when the package's folder is unknown (empty when neither is set).
std::string PythonPathWithPackage();

/// The file of the shared library this function lives in (the SDK's libcorridorsim_common),
/// absolute; empty if the loader cannot say.
std::filesystem::path SdkLibraryFile();

}  // namespace corridorsim

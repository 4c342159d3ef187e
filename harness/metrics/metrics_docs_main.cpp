// metrics_docs: regenerates the metric tables of docs/metrics.md from the registry
// (harness/metrics/registry.h). The prose around the generated blocks stays as written.
//
//   metrics_docs --write docs/metrics.md   rewrite the blocks in place
//   metrics_docs --check docs/metrics.md   exit 1 when the blocks differ from the registry
#include <cstdio>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include "common/io/atomic_file.h"
#include "harness/metrics/registry.h"

int main(int argc, char** argv) {
  const std::string mode = argc == 3 ? argv[1] : "";
  if (mode != "--write" && mode != "--check") {
    std::fprintf(stderr, "usage: metrics_docs --write|--check docs/metrics.md\n");
    return 2;
  }
  const std::string path = argv[2];
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::fprintf(stderr, "metrics_docs: cannot read %s\n", path.c_str());
    return 2;
  }
  const std::string docs((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  try {
    const std::string updated = corridorsim::metrics::UpdateMetricsDocs(docs);
    if (updated == docs) {
      std::printf("metrics_docs: %s matches the registry\n", path.c_str());
      return 0;
    }
    if (mode == "--check") {
      std::printf("metrics_docs: %s differs from the registry (run with --write)\n", path.c_str());
      return 1;
    }
    corridorsim::WriteFileAtomic(path, updated);
    std::printf("metrics_docs: updated %s\n", path.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "metrics_docs: %s\n", e.what());
    return 2;
  }
}

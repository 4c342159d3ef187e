// corridorsim_docs: keeps the docs' generated tables equal to their one declaration in the code:
// docs/scenarios.md's key tables come from the options tables (common/options_table.h),
// docs/metrics.md's metric tables from the metric registry (harness/metrics/registry.def). The
// prose around the generated blocks stays as written.
//
//   corridorsim_docs --check DOCS_DIR   lists what disagrees and exits 1 (CTest
//   docs.generated_tables) corridorsim_docs --write DOCS_DIR   rewrites the generated blocks in
//   place

#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

#include "common/io/atomic_file.h"
#include "harness/metrics/registry.h"
#include "harness/scenario/scenario.h"

namespace {

// One generated document: its file name in DOCS_DIR and how its blocks are regenerated (the
// problems found in the blocks go to `problems`).
struct GeneratedDoc {
  const char* file;
  std::function<std::string(const std::string&, std::vector<std::string>*)> update;
};

}  // namespace

int main(int argc, char** argv) {
  const std::string usage = "usage: corridorsim_docs --check|--write DOCS_DIR\n";
  const std::string mode = argc == 3 ? argv[1] : "";
  if (mode != "--check" && mode != "--write") {
    std::cerr << usage;
    return 2;
  }
  const std::filesystem::path dir = argv[2];
  const std::vector<GeneratedDoc> docs = {
      {"scenarios.md",
       [](const std::string& text, std::vector<std::string>* problems) {
         return corridorsim::ReplaceOptionsDocBlocks(text, corridorsim::ScenarioDocBlocks(),
                                                     problems);
       }},
      {"protocol.md",
       [](const std::string& text, std::vector<std::string>* problems) {
         std::vector<corridorsim::OptionsDocBlock> external;
         for (const corridorsim::OptionsDocBlock& b : corridorsim::ScenarioDocBlocks()) {
           if (b.name == "pipelines.external") external.push_back(b);
         }
         return corridorsim::ReplaceOptionsDocBlocks(text, external, problems);
       }},
      {"metrics.md", [](const std::string& text, std::vector<std::string>*) {
         return corridorsim::metrics::UpdateMetricsDocs(text);
       }}};
  int rc = 0;
  for (const GeneratedDoc& doc : docs) {
    const std::filesystem::path file = dir / doc.file;
    std::ifstream in(file, std::ios::binary);
    if (!in) {
      std::cerr << "corridorsim_docs: cannot read " << file.string() << "\n";
      return 2;
    }
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<std::string> problems;
    std::string updated;
    try {
      updated = doc.update(text, &problems);
    } catch (const std::exception& e) {
      std::cerr << "corridorsim_docs: " << file.string() << ": " << e.what() << "\n";
      return 2;
    }
    if (mode == "--write") {
      if (updated != text) corridorsim::WriteFileAtomic(file, updated);
      continue;
    }
    if (updated != text && problems.empty()) problems.push_back("a generated table differs");
    for (const std::string& p : problems) std::cerr << file.string() << ": " << p << "\n";
    if (!problems.empty()) rc = 1;
  }
  if (rc != 0) std::cerr << "regenerate with: corridorsim_docs --write " << dir.string() << "\n";
  return rc;
}

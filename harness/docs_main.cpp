// corridorsim_docs: keeps docs/scenarios.md's key tables equal to the options tables
// (common/options_table.h). `--check FILE` lists what disagrees and exits 1 (CTest
// docs.options_tables); `--write FILE` rewrites the generated blocks in place.

#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "common/io/atomic_file.h"
#include "harness/scenario.h"

int main(int argc, char** argv) {
  const std::string usage = "usage: corridorsim_docs --check|--write docs/scenarios.md\n";
  if (argc != 3) {
    std::cerr << usage;
    return 2;
  }
  const std::string mode = argv[1], file = argv[2];
  if (mode != "--check" && mode != "--write") {
    std::cerr << usage;
    return 2;
  }
  std::ifstream in(file);
  if (!in) {
    std::cerr << "corridorsim_docs: cannot read " << file << "\n";
    return 2;
  }
  std::stringstream text;
  text << in.rdbuf();
  std::vector<std::string> problems;
  const std::string updated =
      corridorsim::ReplaceOptionsDocBlocks(text.str(), corridorsim::ScenarioDocBlocks(), &problems);
  if (mode == "--write") {
    corridorsim::WriteFileAtomic(file, updated);
    return 0;
  }
  for (const std::string& p : problems) std::cerr << file << ": " << p << "\n";
  if (!problems.empty()) {
    std::cerr << "regenerate with: corridorsim_docs --write " << file << "\n";
    return 1;
  }
  return 0;
}

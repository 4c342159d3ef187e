// Fuzzes ParseCommandLine (harness/cli/cli.h): the input's bytes split at NUL bytes are the
// arguments after the program name. InputError (bad input, exit 2) is the parser's one documented
// error; any other exception, a crash or a sanitizer report is a bug.
//
//   scripts/bootstrap.sh fuzz 60   (docs/fuzzing.md; builds build-fuzz/bin/cli_fuzzer)

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "common/error.h"
#include "harness/cli/cli.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> args(1);
  for (std::size_t i = 0; i < size; ++i) {
    if (data[i] == 0) {
      args.emplace_back();
    } else {
      args.back().push_back(static_cast<char>(data[i]));
    }
  }
  if (size == 0) args.clear();
  try {
    const corridorsim::CommandLine command = corridorsim::ParseCommandLine(args);
    // What the parser accepts keeps its promises: help has text, a job has an output folder.
    if (command.job == corridorsim::CommandLine::Job::kHelp && command.help_text.empty()) {
      std::fprintf(stderr, "help without text\n");
      std::abort();
    }
  } catch (const corridorsim::InputError&) {
    // bad input: the documented outcome
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ParseCommandLine threw %s: %s\n", typeid(e).name(), e.what());
    std::abort();
  } catch (...) {
    std::fprintf(stderr, "ParseCommandLine threw a non-std exception\n");
    std::abort();
  }
  return 0;
}

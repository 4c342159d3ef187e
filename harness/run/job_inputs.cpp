#include "harness/run/job_inputs.h"

#include <system_error>

#include "common/error.h"
#include "common/io/yaml_reader.h"  // InputExcerpt

namespace corridorsim {
namespace {

namespace fs = std::filesystem;

// `path` absolute, normalised, its existing part's links resolved (weakly_canonical); only
// made absolute and normalised when that fails (a component that cannot be read). No trailing
// separator: "run/" is "run".
fs::path Resolved(const fs::path& path) {
  std::error_code error;
  const fs::path absolute = fs::absolute(path, error).lexically_normal();
  fs::path out = fs::weakly_canonical(absolute, error);
  if (error) out = absolute;
  out = out.lexically_normal();
  if (!out.has_filename() && out.has_relative_path()) out = out.parent_path();
  return out;
}

// `inner` is `outer` or lies below it (both resolved, compared component by component).
bool IsWithin(const fs::path& inner, const fs::path& outer) {
  auto i = inner.begin();
  for (auto o = outer.begin(); o != outer.end(); ++o, ++i) {
    if (i == inner.end() || *i != *o) return false;
  }
  return true;
}

}  // namespace

std::vector<JobInput> JobInputsOf(const std::vector<std::filesystem::path>& files,
                                  const std::string& what) {
  std::vector<JobInput> out;
  for (const fs::path& f : files) out.push_back({f, what});
  return out;
}

bool PathWithin(const std::filesystem::path& inner, const std::filesystem::path& outer) {
  return IsWithin(Resolved(inner), Resolved(outer));
}

std::vector<JobInput> ScenarioInputs(const Scenario& scenario) {
  std::vector<JobInput> out = JobInputsOf(scenario.chain_files, "a scenario file");
  for (const fs::path& p : scenario.plugins) out.push_back({p, "a plugin library"});
  return out;
}

void RefuseOutputOverInputs(const std::filesystem::path& output, const std::string& option,
                            const std::vector<JobInput>& inputs) {
  const fs::path out = Resolved(output);
  for (const JobInput& input : inputs) {
    if (input.path.empty()) continue;
    const fs::path in = Resolved(input.path);
    const char* relation = nullptr;
    if (out == in) {
      relation = "is";
    } else if (IsWithin(in, out)) {
      relation = "contains";
    } else if (IsWithin(out, in)) {
      relation = "lies inside";
    }
    if (relation == nullptr) continue;
    throw InputError(SourceLocation{"command line", 0, 0}, option,
                     "'" + InputExcerpt(output.string(), 200) + "' " + relation + " '" +
                         InputExcerpt(input.path.string(), 200) + "', " + input.what +
                         ", which this job reads: an output must be none of its inputs, contain "
                         "none and lie inside none; choose another path");
  }
}

}  // namespace corridorsim

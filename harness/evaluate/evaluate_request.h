#pragma once
// What `corridorsim evaluate` is asked for (harness/evaluate/evaluate.h runs it): plain data, so
// that the command-line parser (harness/cli/cli.h) needs nothing else of the job.

#include <filesystem>
#include <string>
#include <vector>

#include "harness/evaluate/alignment.h"

namespace corridorsim {

/// Bounds of the command line: estimates and maps per evaluation, and --max-dt (s).
inline constexpr std::size_t kMaxEvaluatedFiles = 64;
inline constexpr double kMaxAssociationSeconds = 1.0;

struct EvaluateRequest {
  struct NamedFile {
    std::string name;  // the estimate's name in evaluation.json (a pipeline name's characters)
    std::filesystem::path file;
  };
  std::filesystem::path run_dir;     // RUN_DIR: ground_truth.tum, world.json
  std::vector<NamedFile> estimates;  // --estimate NAME=FILE (TUM, ov_eval)
  std::vector<NamedFile> landmarks;  // --landmarks NAME=FILE
  // --frame NAME=CAMERA: the estimate's poses are world_from_<camera> (the optical frame, as the
  // TUM RGB-D export's groundtruth.txt), brought to world_from_robot with the run's mount.
  struct Frame {
    std::string name;
    std::string camera;
  };
  std::vector<Frame> frames;
  evaluate::Alignment alignment = evaluate::Alignment::kNone;  // --align
  double max_dt_s = 0.01;                                      // --max-dt
  std::filesystem::path out_dir;                               // --out; empty: RUN_DIR/evaluation
  bool force = false;                                          // --force
  bool plots = true;                                           // --no-plots
  std::vector<std::string> expectations;  // --expect NAME.METRIC<op>VALUE, parsed by the job
};

}  // namespace corridorsim

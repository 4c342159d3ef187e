// The corridorsim command. Subcommands: run (the main job), world, snapshot, drive, where, detect,
// train-detectors, dataset, score, study (and study merge), test, plugin, evaluate; --version.
// The command line is parsed by ParseCommandLine (harness/cli/cli.h); this file only dispatches.
// Exit codes: 0 success, 2 bad input (one message naming file, line and key, or the command-line
// flag), 3 an expectation failed (run, score, evaluate), 4 results are written but an extra
// failed, 5 a pipeline failed (run: the others' results are written), 1 any other failure; a job
// that ends without reaching the end of main() (a plugin calling exit()) is never 0
// (harness/cli/supervisor.h).

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "common/error.h"
#include "common/installation.h"
#include "common/io/atomic_file.h"
#include "harness/cli/cli.h"
#include "harness/cli/supervisor.h"
#include "harness/evaluate/evaluate.h"
#include "harness/external/external_pipeline.h"
#include "harness/run/drive.h"
#include "harness/run/provenance.h"
#include "harness/run/run.h"
#include "harness/run/run_folder.h"
#include "harness/run/snapshot.h"
#include "harness/run/where.h"
#include "harness/scenario/job.h"
#include "harness/scenario/plugins.h"
#include "harness/scenario/scenario.h"
#include "harness/study/study.h"
#include "harness/study/suite.h"
#include "harness/workbench/dataset.h"
#include "harness/workbench/detect.h"
#include "harness/workbench/score.h"
#include "harness/workbench/train_detectors.h"
#include "render/software_rasterizer.h"
#include "slam/features/door_plates.h"
#include "slam/sdk_version.h"
#include "worlds/world_io.h"

namespace corridorsim {
namespace {

// No scenario given: ./scenarios/default.yaml when the current folder has one (a checkout), else
// the shipped one. Says which file it is, since the two may differ.
void ResolveDefaultScenario(JobRequest* request) {
  if (!request->scenario_file.empty()) return;
  std::error_code error;
  std::filesystem::path path = "scenarios/default.yaml";
  if (!std::filesystem::is_regular_file(path, error)) {
    path = DataDir() / "scenarios" / "default.yaml";
  }
  std::filesystem::path shown = std::filesystem::weakly_canonical(path, error);
  if (error) shown = std::filesystem::absolute(path, error);
  std::fprintf(stderr, "corridorsim: no scenario given; using %s\n", shown.string().c_str());
  request->scenario_file = path.string();
}

void PrintWorldSummary(const worlds::World& world, const std::filesystem::path& out, double ms) {
  std::map<std::string, int> door_states;
  for (const auto& d : world.doors) ++door_states[worlds::DoorStateName(d.state)];
  int circular = 0, off = 0, room_lamps = 0;
  for (const auto& l : world.lamps) {
    circular += l.shape == worlds::LampShape::kCircular;
    off += !l.on;
    room_lamps += l.room_door_id >= 0;
  }
  const Eigen::Vector3d size = world.bounds.sizes();
  std::printf("world: %s, seed %llu, %.1f x %.1f x %.1f m, generated in %.0f ms\n",
              worlds::LayoutName(world.options.layout).c_str(),
              static_cast<unsigned long long>(world.seed), size.x(), size.y(), size.z(), ms);
  std::printf("  corridor segments %zu, walls %zu\n", world.segments.size(), world.walls.size());
  std::printf("  doors %zu (closed %d, open %d, empty %d)\n", world.doors.size(),
              door_states["closed"], door_states["open"], door_states["empty"]);
  std::printf("  door plates %zu\n", world.plates.size());
  std::printf("  lamps %zu (circular %d, panel %zu, in rooms %d, off %d), reflectors %zu\n",
              world.lamps.size(), circular, world.lamps.size() - circular, room_lamps, off,
              world.reflectors.size());
  std::printf("  ceiling corner points %zu, distractors %zu\n", world.corner_points.size(),
              world.distractors.size());
  std::printf("  meshes %zu, triangles %zu, textures %zu, collision boxes %zu\n",
              world.meshes.size(), world.triangle_count(), world.textures.size(),
              world.collision_boxes.size());
  std::printf("wrote %s/{world.obj, world.mtl, textures/, ground_truth.json, map.png}\n",
              out.string().c_str());
}

int RunWorld(const JobRequest& request) {
  const Scenario scenario = LoadScenario(request.scenario_file, request.settings);
  // Written into a staging folder that replaces --out whole at the end (harness/run/run_folder.h).
  const std::unique_ptr<StagedDirectory> folder =
      StageOutputFolder(request.out_dir, "--out", request.force, ScenarioInputs(scenario));
  const std::uint64_t world_seed = request.seed.value_or(scenario.seed);
  const auto t0 = std::chrono::steady_clock::now();
  const worlds::World world = GenerateWorld(scenario, world_seed);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  worlds::WriteWorldFiles(world, folder->path());
  folder->Commit();
  PrintWorldSummary(world, folder->path(), ms);
  return kExitSuccess;
}

// The request of a job that reads a scenario (whose default Dispatch resolves first), else null.
JobRequest* ScenarioRequest(CommandLine& command) {
  switch (command.job) {
    case CommandLine::Job::kWorld:
      return &command.world;
    case CommandLine::Job::kSnapshot:
      return &command.snapshot;
    case CommandLine::Job::kRun:
      return &command.run;
    case CommandLine::Job::kDrive:
      return &command.drive;
    case CommandLine::Job::kDataset:
      return &command.dataset;
    case CommandLine::Job::kStudy:
      return &command.study;
    default:
      return nullptr;
  }
}

int Dispatch(CommandLine& command) {
  if (JobRequest* request = ScenarioRequest(command)) ResolveDefaultScenario(request);
  switch (command.job) {
    case CommandLine::Job::kHelp:
      std::fputs(command.help_text.c_str(), stdout);
      return kExitSuccess;
    case CommandLine::Job::kVersion:
      std::printf("corridorsim %s (%s)\nSDK ABI version %d\ndata %s\n", CORRIDORSIM_VERSION,
                  ProjectVersion().c_str(), CORRIDORSIM_SDK_ABI_VERSION, DataDir().c_str());
      return kExitSuccess;
    case CommandLine::Job::kPlugin: {
      const LoadedPlugin plugin =
          LoadPlugin(command.plugin_file, {"command line", 0, 0}, "library");
      std::fputs(DescribePlugin(plugin).c_str(), stdout);
      return kExitSuccess;
    }
    case CommandLine::Job::kWorld:
      return RunWorld(command.world);
    case CommandLine::Job::kSnapshot:
      RunSnapshot(command.snapshot);
      return kExitSuccess;
    case CommandLine::Job::kRun:
    case CommandLine::Job::kReplay:
      return RunScenario(command.run);
    case CommandLine::Job::kDrive:
      RunDrive(command.drive);
      return kExitSuccess;
    case CommandLine::Job::kWhere:
      std::fputs(LocateRoom(command.where).c_str(), stdout);
      return kExitSuccess;
    case CommandLine::Job::kDetect:
      RunDetectJob(command.detect);
      return kExitSuccess;
    case CommandLine::Job::kTrainDetectors:
      return RunTrainDetectors(command.train_detectors);
    case CommandLine::Job::kDataset:
      return RunDataset(command.dataset);
    case CommandLine::Job::kScore:
      return RunScore(command.score);
    case CommandLine::Job::kEvaluate:
      return evaluate::RunEvaluate(command.evaluate);
    case CommandLine::Job::kStudy:
      return RunStudy(command.study);
    case CommandLine::Job::kStudyMerge:
      return MergeStudies(command.study);
    case CommandLine::Job::kTest:
      if (command.test.files.empty()) {
        JobRequest request;
        ResolveDefaultScenario(&request);
        command.test.files.push_back(request.scenario_file);
      }
      return RunTestSuite(command.test);
  }
  return kExitFailure;
}

}  // namespace
}  // namespace corridorsim

int main(int argc, char** argv) {
  using namespace corridorsim;
  // Mesa's environment, set before any thread or fork (render/software_rasterizer.h).
  render::PinSoftwareRasterizer();
  SuperviseThisJob();  // from here on: the job (harness/cli/supervisor.h)
  try {
    external::RegisterExternalPipelineType();  // `type: external` (docs/protocol.md)
    const std::vector<std::string> args =
        argc > 1 ? std::vector<std::string>(argv + 1, argv + argc) : std::vector<std::string>();
    CommandLine command = ParseCommandLine(args);
    return FinishJob(Dispatch(command));
  } catch (const InputError& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "corridorsim: error: %s\n", e.what());
    return FinishJob(kExitBadInput);
  } catch (const slam::ModelFileError& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "corridorsim: error: %s\n", e.what());
    return FinishJob(kExitBadInput);
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "corridorsim: error: %s\n", e.what());
    return FinishJob(kExitFailure);
  }
}

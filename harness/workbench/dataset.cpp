#include "harness/workbench/dataset.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <set>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "common/io/json_input.h"
#include "common/io/sha256.h"
#include "common/io/stable_json.h"
#include "harness/run/frame_io.h"
#include "harness/run/job_inputs.h"
#include "harness/run/simulation_setup.h"
#include "harness/workbench/dataset_internal.h"
#include "render/backend.h"
#include "render/software_rasterizer.h"
#include "worlds/image_io.h"
#include "worlds/world_io.h"

// The `dataset` job (dataset.h: RunDataset): the cameras selected, the folder claimed, resumed or
// replaced through its manifest, each world's frames written file by file, the progress line; and
// the manifest read back by the folder's readers (ReadDatasetManifest). The poses, the frames and
// the COCO annotations: dataset_poses.cpp, dataset_world.cpp, dataset_coco.cpp.

namespace corridorsim {
namespace {

namespace fs = std::filesystem;
using dataset_internal::kCommandLine;
using Json = nlohmann::ordered_json;

constexpr int kFormatVersion = 1;

// The manifest says what the folder's bytes depend on; a rerun resumes only into a folder whose
// manifest is the same bytes.
std::string ManifestJson(const Scenario& scenario, std::uint64_t seed,
                         const DatasetRequest& request, const std::vector<std::string>& cameras,
                         const render::Backend& backend) {
  Json j;
  j["format"] = "corridorsim dataset";
  j["format_version"] = kFormatVersion;
  j["scenario"] = {{"name", scenario.name},
                   {"sha256", Sha256Hex(ResolvedScenarioYaml(scenario, seed))},
                   {"sha256_of", "the resolved scenario with the seed (a run's scenario.yaml)"}};
  j["seed"] = seed;
  j["world_seeds"] = "seed + world index (modulo 2^64)";
  j["worlds"] = request.worlds;
  j["frames_per_world"] = request.frames_per_world;
  j["cameras"] = cameras;
  j["poses"] = DatasetPoseModeName(request.poses);
  const render::BackendInfo info = backend.info();
  const std::optional<std::string> gallivm_perf = render::GallivmPerfInEffect(&backend);
  j["render"] = {{"backend", render::BackendName(backend.kind())},
                 {"device", info.device},
                 {"gl_renderer", info.renderer},
                 {"gl_version", info.version},
                 {"GALLIVM_PERF", gallivm_perf ? Json(*gallivm_perf) : Json(nullptr)}};
  j["categories"] = DatasetCategoriesJson();
  return JsonFileText(j);
}

// The first top-level key whose value differs between two manifests, for the refusal message.
std::string FirstDifference(const std::string& existing, const std::string& wanted) {
  try {
    const Json a = Json::parse(existing), b = Json::parse(wanted);
    for (const auto& [key, value] : b.items()) {
      if (!a.contains(key) || a[key] != value) return key;
    }
  } catch (const nlohmann::json::exception&) {
    return "(not JSON)";
  }
  return "(formatting)";
}

// A folder with files is this job's only when it holds StagedDirectory::kOutputFolderMarker
// (a regular file, not a link), which `dataset` writes before anything else: an empty or missing
// folder is filled; one of ours holding this dataset's manifest is resumed; one of ours with
// another manifest (or another corridorsim job's folder) is cleared with --force, else refused;
// one without the marker is never touched, whatever it holds (a dataset.json of the user's).
void WriteManifestAndCheck(const fs::path& dir, const std::string& manifest, bool force) {
  std::error_code error;
  const fs::path manifest_path = dir / "dataset.json";
  const fs::path marker = dir / StagedDirectory::kOutputFolderMarker;
  if (fs::exists(dir, error) && !fs::is_directory(dir, error)) {
    throw InputError(kCommandLine, "--out", dir.string() + " exists and is not a folder");
  }
  const bool has_files = fs::is_directory(dir, error) && !fs::is_empty(dir, error);
  if (has_files) {
    if (!fs::is_regular_file(fs::symlink_status(marker, error))) {
      throw InputError(kCommandLine, "--out",
                       dir.string() + " holds files that corridorsim did not write (it has no " +
                           StagedDirectory::kOutputFolderMarker +
                           "): dataset resumes or replaces only its own folders; choose another "
                           "--out");
    }
    const bool has_manifest = fs::exists(fs::symlink_status(manifest_path, error));
    const std::optional<std::string> existing =
        has_manifest
            ? std::optional<std::string>(ReadRegularFile(manifest_path, kMaxDatasetManifestBytes))
            : std::nullopt;
    if (existing == manifest) return;  // resume
    if (!force) {
      throw InputError(
          kCommandLine, "--out",
          existing
              ? manifest_path.string() + " was written with other arguments (first difference: `" +
                    FirstDifference(*existing, manifest) +
                    "`); use --force to replace the dataset, or another --out"
              : dir.string() +
                    " holds another corridorsim job's output (no dataset.json); use --force "
                    "to replace it, or another --out");
    }
    for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
      fs::remove_all(entry.path());
    }
  }
  EnsureWritableDirectory(dir);
  WriteFileAtomic(marker,
                  "This folder was written by corridorsim dataset: it resumes into it, and "
                  "`--force` may replace it whole.\n");
  WriteFileAtomic(manifest_path, manifest);
}

// The selected cameras in the rig's order: --cameras must name enabled cameras.
std::vector<std::string> SelectCameras(const Scenario& scenario,
                                       const std::vector<std::string>& requested) {
  std::vector<std::string> enabled;
  for (const render::CameraOptions& c : scenario.rig.cameras) {
    if (c.enabled) enabled.push_back(c.id);
  }
  std::string enabled_list;
  for (const std::string& id : enabled) enabled_list += (enabled_list.empty() ? "" : ", ") + id;
  if (requested.empty()) {
    if (enabled.empty()) {
      throw InputError(kCommandLine, "--cameras",
                       "the scenario enables no camera (sensors.<camera>.enabled)");
    }
    return enabled;
  }
  std::set<std::string> wanted;
  for (const std::string& id : requested) {
    if (std::find(enabled.begin(), enabled.end(), id) == enabled.end()) {
      throw InputError(kCommandLine, "--cameras",
                       "'" + id + "' is not a camera the scenario enables (enabled: " +
                           (enabled_list.empty() ? "none" : enabled_list) + ")");
    }
    if (!wanted.insert(id).second) {
      throw InputError(kCommandLine, "--cameras", "'" + id + "' is named twice");
    }
  }
  std::vector<std::string> selected;
  for (const std::string& id : enabled) {
    if (wanted.count(id)) selected.push_back(id);
  }
  return selected;
}

// `dataset: world 2/5 frame 10/20`: in place on a terminal, else a line per tenth of the job and
// at the end of each world (no clock: the same lines every time).
class DatasetProgress {
 public:
  DatasetProgress(int worlds, int frames) : worlds_(worlds), frames_(frames) {
    tty_ = ::isatty(STDERR_FILENO) != 0;
  }
  void Update(int world, int frame) {
    const std::int64_t done = std::int64_t(world) * frames_ + frame + 1;
    const std::int64_t total = std::int64_t(worlds_) * frames_;
    const int decile = static_cast<int>(10 * done / total);
    char line[128];
    std::snprintf(line, sizeof(line), "dataset: world %d/%d frame %d/%d", world + 1, worlds_,
                  frame + 1, frames_);
    if (tty_) {
      std::fprintf(stderr, "\r%s", line);
      if (done == total) std::fputc('\n', stderr);
    } else if (decile != last_decile_ || frame + 1 == frames_) {
      std::fprintf(stderr, "%s\n", line);
    }
    last_decile_ = decile;
  }

 private:
  int worlds_, frames_;
  bool tty_ = false;
  int last_decile_ = 0;
};

}  // namespace

DatasetManifest ReadDatasetManifest(const fs::path& dir) {
  DatasetManifest m;
  m.file = (dir / "dataset.json").string();
  m.json = ParseJsonInput(ReadRegularFile(dir / "dataset.json", kMaxDatasetManifestBytes), m.file);
  const JsonField top{m.file, "", m.json};
  if (!m.json.is_object()) top.Fail("expected an object");
  if (top.At("format").String() != "corridorsim dataset") {
    top.At("format").Fail("expected \"corridorsim dataset\"");
  }
  const JsonField cameras = top.At("cameras");
  for (std::size_t i = 0; i < cameras.ArraySize(); ++i) {
    // A camera names a folder of DIR: a plain name, never a path out of it.
    const std::string id = cameras.At(i).String();
    if (id.empty() || id.size() > 64 || !std::all_of(id.begin(), id.end(), [](char c) {
          return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
        })) {
      cameras.At(i).Fail("expected a camera name: 1 to 64 letters, digits, '_' or '-'");
    }
    m.cameras.push_back(id);
  }
  return m;
}

int RunDataset(const DatasetRequest& request) {
  const Scenario scenario = LoadScenario(request.scenario_file, request.settings);
  const std::vector<std::string> cameras = SelectCameras(scenario, request.cameras);
  const render::BackendKind backend_kind = ChooseBackend(scenario.rig.backend);
  const std::uint64_t seed = request.seed.value_or(scenario.seed);
  const int n_worlds = request.worlds, n_frames = request.frames_per_world;
  CheckOrDie(n_worlds >= 1 && n_worlds <= kMaxDatasetWorlds && n_frames >= 1 &&
                 n_frames <= kMaxDatasetFramesPerWorld,
             "RunDataset", "counts out of bounds (ParseCommandLine checks them)");
  render::RigOptions rig_options = scenario.rig;
  for (render::CameraOptions& c : rig_options.cameras) {
    c.enabled = std::find(cameras.begin(), cameras.end(), c.id) != cameras.end();
  }
  const fs::path dir = request.out_dir;
  RefuseOutputOverInputs(dir, "--out", ScenarioInputs(scenario));

  // World 0 and its poses before anything is written: a scenario whose worlds cannot be built,
  // or poses that cannot be placed, are mostly found here.
  std::optional<DatasetWorld> world(std::in_place, scenario, rig_options, backend_kind, seed, 0,
                                    n_worlds, request.poses, n_frames);

  // The manifest names the renderer, so a GL context comes first.
  const std::string manifest = [&] {
    const std::unique_ptr<render::Backend> backend = render::CreateBackend(backend_kind);
    return ManifestJson(scenario, seed, request, cameras, *backend);
  }();
  WriteManifestAndCheck(dir, manifest, request.force);
  for (const render::CameraOptions& c : rig_options.cameras) {
    if (!c.enabled) continue;
    for (const char* sub : {"images", "labels", "truth"}) fs::create_directories(dir / c.id / sub);
    if (c.depth) fs::create_directories(dir / c.id / "depth");
    WriteFileAtomic(dir / c.id / "intrinsics.json", JsonFileText(IntrinsicsJson(c)));
  }

  DatasetProgress progress(n_worlds, n_frames);
  std::int64_t rendered = 0;
  for (int w = 0; w < n_worlds; ++w) {
    // Every pose is drawn even when its frame is done: a resumed world gets the same poses.
    if (w > 0) {
      world.emplace(scenario, rig_options, backend_kind, seed + static_cast<std::uint64_t>(w), w,
                    n_worlds, request.poses, n_frames);
    }
    const fs::path world_dir = dir / "worlds" / DatasetWorldStem(w, n_worlds);
    if (!fs::exists(world_dir / "ground_truth.json")) {
      fs::create_directories(world_dir);
      WriteFileAtomic(world_dir / "ground_truth.json",
                      JsonFileText(worlds::GroundTruthJson(world->world())));
    }
    for (int f = 0; f < n_frames; ++f) {
      const std::string stem = DatasetFrameStem(w, f, n_worlds, n_frames);
      const bool done = std::all_of(cameras.begin(), cameras.end(), [&](const std::string& id) {
        return fs::exists(dir / id / "truth" / (stem + ".json"));
      });
      if (!done) {
        for (const DatasetFrame& frame : world->Render(f)) {
          const render::CameraFrame& image = frame.frame;
          const fs::path camera_dir = dir / image.camera_id;
          const int width = image.rgb.width, height = image.rgb.height;
          WriteFileAtomic(camera_dir / "images" / (stem + ".png"),
                          EncodePng(image.rgb, image.camera_id + " " + stem));
          WriteFileAtomic(camera_dir / "labels" / (stem + ".png"),
                          EncodeLabels(image, width, height));
          if (frame.depth) {
            WriteFileAtomic(camera_dir / "depth" / (stem + ".png"),
                            EncodeDepth(image.noisy_depth_m, image.camera_id + " depth " + stem));
          }
          // Written last: its presence marks the frame done.
          WriteFileAtomic(camera_dir / "truth" / (stem + ".json"), JsonFileText(frame.truth, 1));
        }
        ++rendered;
      }
      progress.Update(w, f);
    }
  }
  for (const std::string& id : cameras) WriteDatasetAnnotations(dir, id, n_worlds, n_frames);
  std::string camera_list;
  for (const std::string& id : cameras) camera_list += (camera_list.empty() ? "" : ",") + id;
  std::printf("dataset: %d worlds x %d frames, cameras %s: rendered %lld frames, wrote %s\n",
              n_worlds, n_frames, camera_list.c_str(), static_cast<long long>(rendered),
              dir.string().c_str());
  return 0;
}

}  // namespace corridorsim

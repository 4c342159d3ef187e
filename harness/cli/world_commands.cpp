// The subcommands about a world and the robot in it: world, snapshot, drive, where.
#include <memory>
#include <string>

#include "harness/cli/options.h"
#include "harness/cli/subcommands.h"

namespace corridorsim::cli {
namespace {

class WorldCommand final : public Subcommand {
 public:
  explicit WorldCommand(CLI::App* app)
      : Subcommand(
            app, "world",
            "Generate a corridor world and write its geometry, textures, ground truth and plan"),
        options_(job_, "out/world",
                 "Scenario YAML whose `world:` section and `seed` are used "
                 "(default: ./scenarios/default.yaml if it exists, else the shipped "
                 "one; the file used is printed)",
                 "Seed of the world's random streams (default: the scenario's `seed`)",
                 "Output folder for world.obj, world.mtl, textures/, ground_truth.json, "
                 "map.png") {
    SetFooter(job_,
              "Writes world.obj + world.mtl + textures/*.png (open in MeshLab or Blender), "
              "ground_truth.json (door plates, lamps, doors, corridor segments, corner "
              "points, distractors; metres, world frame) and map.png (top-down plan).\n",
              FolderFooter::kStaged,
              "0 success, 2 bad input (file:line:column: key: message, or command line: "
              "--flag: message; nothing is written), 1 other failures.");
  }

  void Resolve(CommandLine* parsed) const override {
    parsed->job = CommandLine::Job::kWorld;
    options_.Resolve(&parsed->world);
  }

 private:
  JobOptions options_;
};

class SnapshotCommand final : public Subcommand {
 public:
  explicit SnapshotCommand(CLI::App* app)
      : Subcommand(app, "snapshot",
                   "Place the robot at one pose and render every camera of the rig"),
        options_(job_, "out/snapshot",
                 std::string("Scenario YAML (world, sensors, render) ") + kDefaultScenarioHelp,
                 "Seed of the world and the sensor noise", "Output folder") {
    AddOption(job_, "--pose", pose_,
              "Robot pose x,y,yaw: metres in the world frame (|x|, |y| <= 100000) and "
              "degrees (0 = along +x, |yaw| <= 360)")
        ->required()
        ->type_name("X,Y,YAW");
    SetFooter(job_,
              "Writes per camera <camera>_rgb.png, <camera>_labels.png (16-bit RGB: R = semantic "
              "class, G = instance id >> 16, B = instance id & 0xffff), <camera>_overlay.png "
              "(ground truth drawn on the image), front_depth.png (16-bit, 5000 per metre, 0 = "
              "invalid), plus frame_ground_truth.json and intrinsics.json.\n"
              "Environment: CORRIDORSIM_RENDER_BACKEND=osmesa|egl overrides the scenario's "
              "render.backend.\n",
              FolderFooter::kStaged,
              "0 success, 2 bad input (nothing is written), 1 other failures (e.g. no GL "
              "context).");
  }

  void Resolve(CommandLine* parsed) const override {
    parsed->job = CommandLine::Job::kSnapshot;
    options_.Resolve(&parsed->snapshot);
    const PoseArgument pose = ParsePoseArgument(pose_, "--pose");
    parsed->snapshot.x_m = pose.x_m;
    parsed->snapshot.y_m = pose.y_m;
    parsed->snapshot.yaw_deg = pose.yaw_deg;
  }

 private:
  JobOptions options_;
  std::string pose_;
};

class DriveCommand final : public Subcommand {
 public:
  DriveCommand(CLI::App* app, CommandLine* parsed)
      : Subcommand(
            app, "drive",
            "Drive the scenario's path closed loop and write trajectories, odometry and events"),
        options_(job_, "out/drive",
                 std::string("Scenario YAML (world, robot, path, sensors) ") + kDefaultScenarioHelp,
                 "Seed of the world, the odometry errors and the sensor noise", "Output folder") {
    AddSwitch(job_, "--save-frames", parsed->drive.save_frames,
              "Render the cameras at their rates and write every frame");
    SetFooter(job_,
              "Writes ground_truth.tum (the planar truth world_from_robot: x, y, yaw with z = 0, "
              "at 100 Hz and every odometry stamp; the same file a run writes), "
              "ground_truth_3d.tum (the physics' full 3D pose at the same stamps) and "
              "odometry.tum (wheel odometry dead reckoning from the true start pose), all TUM "
              "format: t x y z qx qy qz qw, seconds; odometry.csv (the raw messages: per-wheel "
              "distances and ticks); events.json (collisions, slips, path done or timeout); "
              "provenance.json. With --save-frames: frames/<camera>/{rgb,labels,depth}/<t>.png, "
              "frames/<camera>/frames.json (pose and visible landmarks per frame) and "
              "frames/intrinsics.json.\n",
              FolderFooter::kStaged,
              "0 success, 2 bad input (nothing is written), 1 other failures.");
  }

  void Resolve(CommandLine* parsed) const override {
    parsed->job = CommandLine::Job::kDrive;
    options_.Resolve(&parsed->drive);
  }

 private:
  JobOptions options_;
};

class WhereCommand final : public Subcommand {
 public:
  explicit WhereCommand(CLI::App* app)
      : Subcommand(app, "where",
                   "Say where a room is, as each pipeline of a finished run mapped it") {
    AddOption(job_, "room", room_, "Room number, as on its door plate (e.g. 101)", "ROOM")
        ->required();
    AddOption(job_, "--run", run_, "Run folder (corridorsim run --out)", "DIR")->required();
    AddOption(job_, "--pipeline", pipeline_,
              "Only this pipeline's map (default: every DIR/maps/<pipeline>_semantic.json)");
    SetFooter(job_,
              "Reads DIR/maps/<pipeline>_semantic.json (the semantic map: room number -> door "
              "plate position with covariance) and prints per pipeline x and y in metres, world "
              "frame, with their 1-sigma.\n",
              FolderFooter::kNone,
              "0 success, 2 bad input (the folder or a map missing or malformed, or no map "
              "knows the room: the message lists the known rooms), 1 other failures.");
  }

  void Resolve(CommandLine* parsed) const override {
    parsed->job = CommandLine::Job::kWhere;
    parsed->where.room = ParseRoomArgument(room_, "ROOM");
    parsed->where.run_dir = FolderName(run_, "--run");
    if (pipeline_.given()) {
      parsed->where.pipeline = ParsePipelineArgument(pipeline_.text, "--pipeline");
    }
  }

 private:
  std::string room_, run_;
  OptionalArgument pipeline_;
};

}  // namespace

std::unique_ptr<Subcommand> AddWorldCommand(CLI::App* app) {
  return std::make_unique<WorldCommand>(app);
}
std::unique_ptr<Subcommand> AddSnapshotCommand(CLI::App* app) {
  return std::make_unique<SnapshotCommand>(app);
}
std::unique_ptr<Subcommand> AddDriveCommand(CLI::App* app, CommandLine* parsed) {
  return std::make_unique<DriveCommand>(app, parsed);
}
std::unique_ptr<Subcommand> AddWhereCommand(CLI::App* app) {
  return std::make_unique<WhereCommand>(app);
}

}  // namespace corridorsim::cli

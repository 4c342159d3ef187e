// A render::Rig ready to draw a world: the scene built from the world with the rig's scene
// options and uploaded to a backend of the rig's kind (tests and benchmarks of the closed loop).
#pragma once

#include <memory>
#include <utility>

#include "render/backend.h"
#include "render/camera_rig.h"
#include "render/scene.h"
#include "worlds/world.h"

namespace corridorsim::test {

class UploadedRig {
 public:
  UploadedRig(const worlds::World& world, const render::RigOptions& options)
      : scene_(render::BuildScene(world, options.scene)),
        backend_(Uploaded(render::CreateBackend(options.backend), scene_)),
        rig_(options, scene_, *backend_) {}
  UploadedRig(const UploadedRig&) = delete;
  UploadedRig& operator=(const UploadedRig&) = delete;

  render::Rig& rig() { return rig_; }

 private:
  static std::unique_ptr<render::Backend> Uploaded(std::unique_ptr<render::Backend> backend,
                                                   const render::Scene& scene) {
    backend->Upload(scene);
    return backend;
  }

  render::Scene scene_;
  std::unique_ptr<render::Backend> backend_;
  render::Rig rig_;  // draws scene_ with backend_
};

}  // namespace corridorsim::test

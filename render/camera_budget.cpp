#include "render/camera_budget.h"

#include <algorithm>
#include <cmath>

namespace corridorsim::render {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

// One parameter struct at n times the resolution (ScaledModel).
template <class Model>
Model Scaled(Model m, int n) {
  m.width *= n;
  m.height *= n;
  m.fx *= n;
  m.fy *= n;
  m.cx = n * m.cx + (n - 1) / 2.0;
  m.cy = n * m.cy + (n - 1) / 2.0;
  return m;
}

}  // namespace

CameraModel ScaledModel(const CameraModel& model, int n) {
  if (n == 1) return model;
  if (const auto* p = model.pinhole()) return CameraModel(Scaled(*p, n));
  return CameraModel(Scaled(*model.kannala_brandt(), n));
}

int SamplesPerSide(int samples) { return samples >= 25 ? 5 : samples >= 9 ? 3 : 1; }

bool IsUndistortedPinhole(const CameraModel& model) {
  const PinholeRadTan* p = model.pinhole();
  return p && p->k1 == 0 && p->k2 == 0 && p->p1 == 0 && p->p2 == 0 && p->k3 == 0;
}

CameraBudget CameraBudgetOf(const CameraOptions& camera, int samples) {
  if (SamplesPerSide(samples) > 1) {
    // Supersampled: the camera drawn at n times its resolution.
    CameraOptions drawn = camera;
    drawn.model = ScaledModel(camera.model, SamplesPerSide(samples));
    drawn.cube_face_px *= SamplesPerSide(samples);
    return CameraBudgetOf(drawn, 1);
  }
  const CameraModel& model = camera.model;
  const CameraIntrinsics p = model.intrinsics();
  const std::uint64_t pixels = std::uint64_t(std::max(p.width, 0)) * std::max(p.height, 0);
  CameraBudget b;
  if (IsUndistortedPinhole(model)) {
    b.pass_width_px = p.width, b.pass_height_px = p.height, b.passes = 1;
  } else if (model.kannala_brandt()) {
    // A face spans 90 degrees at face_px (PlanRemapPasses); its crop keeps a 2 px border, and
    // rounding the window's ends outwards adds up to 1 px each (a ray on a face's edge may lie
    // a rounding error beyond it).
    const double auto_face = 2 * std::ceil(std::max(p.fx, p.fy));
    const double face = camera.cube_face_px > 0 ? camera.cube_face_px : auto_face;
    b.pass_width_px = b.pass_height_px = int(std::min(face + 7, 1e9));
    b.passes = 6;
  } else {
    // A distorted pinhole passing its Check() is invertible up to its image corners, so every
    // pixel is valid and the undistorted window's extremes lie on the image border.
    double u0 = 1e30, u1 = -1e30, v0 = 1e30, v1 = -1e30;
    auto extend = [&](int u, int v) {
      const Vector3d q = model.Unproject(Vector2d(u, v));
      if (!q.allFinite() || q.norm() < 0.5 || !(q.z() > 1e-6)) return;
      const double x = p.fx * q.x() / q.z(), y = p.fy * q.y() / q.z();
      u0 = std::min(u0, x), u1 = std::max(u1, x), v0 = std::min(v0, y), v1 = std::max(v1, y);
    };
    for (int u = 0; u < p.width; ++u) extend(u, 0), extend(u, p.height - 1);
    for (int v = 0; v < p.height; ++v) extend(0, v), extend(p.width - 1, v);
    if (u0 <= u1 && v0 <= v1) {
      // The crop of PlanRemapPasses: the used window plus 2 px, both ends included.
      b.pass_width_px = int(std::min(std::ceil(u1) - std::floor(u0) + 5, 1e9));
      b.pass_height_px = int(std::min(std::ceil(v1) - std::floor(v0) + 5, 1e9));
    }
    b.passes = 1;
  }
  // Bytes per pass pixel: the GL targets (RGBA8, R32UI, R8UI, R32F, depth 32F) and the
  // read-back (RGB, instance, class, depth). Per output pixel: the frame (RGB, instance, class,
  // exact and noisy depth) and, for a remapped camera, its tables (lookup 12, remap 8, depth
  // scale 4) and the planning's bearings and faces (28).
  const std::uint64_t pass_pixels =
      std::uint64_t(b.pass_width_px) * std::uint64_t(b.pass_height_px) * std::uint64_t(b.passes);
  const bool depth = camera.ReadsDepth();
  const std::uint64_t per_pass_px = 17 + 8 + (depth ? 4 : 0);
  const std::uint64_t per_px =
      8 + (depth ? 8 : 0) + (IsUndistortedPinhole(model) ? 0 : 12 + 8 + (depth ? 4 : 0) + 28);
  b.bytes = pass_pixels * per_pass_px + pixels * per_px;
  return b;
}

}  // namespace corridorsim::render

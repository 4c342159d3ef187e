#include "render/camera_renderer.h"

#include "render/camera_budget.h"
#include "render/lighting.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace corridorsim::render {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector2d;
using Eigen::Vector3d;

// Rotation from a pass (cube face) frame to the camera frame whose optical axis is `axis`.
Matrix3d FaceRotation(int face) {
  // Columns: the face's x, y, z axes in the camera frame (x right, y down, z forward).
  Matrix3d r;
  switch (face) {
    case 0:
      r << 1, 0, 0, 0, 1, 0, 0, 0, 1;
      break;  // +z
    case 1:
      r << 0, 0, 1, 0, 1, 0, -1, 0, 0;
      break;  // +x: face z = cam x, face x = -cam z
    case 2:
      r << 0, 0, -1, 0, 1, 0, 1, 0, 0;
      break;  // -x
    case 3:
      r << 1, 0, 0, 0, 0, 1, 0, -1, 0;
      break;  // +y: face z = cam y, face y = -cam z
    case 4:
      r << 1, 0, 0, 0, 0, -1, 0, 1, 0;
      break;  // -y
    default:
      r << -1, 0, 0, 0, 1, 0, 0, 0, -1;
      break;  // -z
  }
  return r;
}

// `frame`'s images sized to width x height (the colour image made anew only when its size
// changed; depth only for a camera that reads it), their pixels left to the caller to write.
void SizeFrame(int width, int height, bool reads_depth, CameraFrame* frame) {
  if (frame->rgb.width != width || frame->rgb.height != height || frame->rgb.channels != 3) {
    frame->rgb = Image8(width, height, 3);
  }
  const std::size_t pixels = static_cast<std::size_t>(width) * height;
  frame->instance.resize(pixels);
  frame->semantic.resize(pixels);
  if (reads_depth) {
    frame->depth_m.width = width;
    frame->depth_m.height = height;
    frame->depth_m.data.resize(pixels);
  }
}

}  // namespace

CameraRenderer::CameraRenderer(const CameraOptions& options, int samples_per_side)
    : options_(options),
      n_(samples_per_side),
      draw_model_(ScaledModel(options.model, samples_per_side)) {
  if (n_ < 1 || n_ % 2 == 0 || n_ > 5) {
    throw std::invalid_argument("render: samples per pixel side must be 1, 3 or 5");
  }
  if (IsUndistortedPinhole(draw_model_)) {
    PlanPinholePass();
  } else {
    PlanRemapPasses();
  }
  rendered_.resize(passes_.size());
}

void CameraRenderer::PlanPinholePass() {
  const PinholeRadTan& p = *draw_model_.pinhole();
  Pass pass;
  pass.view.width = p.width;
  pass.view.height = p.height;
  pass.view.fx = p.fx;
  pass.view.fy = p.fy;
  pass.view.cx = p.cx;
  pass.view.cy = p.cy;
  passes_.push_back(pass);
}

void CameraRenderer::PlanRemapPasses() {
  const CameraIntrinsics p = draw_model_.intrinsics();
  const bool fisheye = draw_model_.kannala_brandt() != nullptr;
  const int w = p.width, h = p.height;
  // Unit bearings of every output pixel, and which face (or the single pass) each one uses.
  std::vector<Vector3d> bearings(static_cast<std::size_t>(w) * h);
  std::vector<int> face_of(bearings.size(), -1);
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const Vector3d b = draw_model_.Unproject(Vector2d(u, v));
      const std::size_t i = static_cast<std::size_t>(v) * w + u;
      bearings[i] = b;
      if (!b.allFinite() || b.norm() < 0.5) continue;
      if (!fisheye) {
        if (b.z() > 1e-6) face_of[i] = 0;
        continue;
      }
      int best = 0;
      double best_dot = -2;
      for (int f = 0; f < 6; ++f) {
        const double d = FaceRotation(f).col(2).dot(b);
        if (d > best_dot + 1e-12) best_dot = d, best = f;
      }
      face_of[i] = best;
    }
  }
  // Pass intrinsics: a fisheye face spans 90 degrees at `face_px`; a distorted pinhole's single
  // pass keeps the camera's focal length.
  int face_px = options_.cube_face_px * n_;
  if (face_px == 0) face_px = 2 * static_cast<int>(std::ceil(std::max(p.fx, p.fy)));
  const double f_face = face_px / 2.0;
  struct Extent {
    double u0 = 1e30, v0 = 1e30, u1 = -1e30, v1 = -1e30;
  };
  const int n_faces = fisheye ? 6 : 1;
  std::vector<Extent> extents(static_cast<std::size_t>(n_faces));
  auto project_in = [&](int f, const Vector3d& b) {
    const Vector3d q = FaceRotation(f).transpose() * b;
    const double fx = fisheye ? f_face : p.fx, fy = fisheye ? f_face : p.fy;
    return Vector2d(fx * q.x() / q.z(), fy * q.y() / q.z());  // relative to the principal point
  };
  for (std::size_t i = 0; i < bearings.size(); ++i) {
    if (face_of[i] < 0) continue;
    const Vector2d uv = project_in(face_of[i], bearings[i]);
    Extent& e = extents[static_cast<std::size_t>(face_of[i])];
    e.u0 = std::min(e.u0, uv.x()), e.u1 = std::max(e.u1, uv.x());
    e.v0 = std::min(e.v0, uv.y()), e.v1 = std::max(e.v1, uv.y());
  }
  std::vector<int> pass_of_face(static_cast<std::size_t>(n_faces), -1);
  std::vector<Vector2d> origin_of_face(static_cast<std::size_t>(n_faces));
  for (int f = 0; f < n_faces; ++f) {
    const Extent& e = extents[static_cast<std::size_t>(f)];
    if (e.u0 > e.u1) continue;
    // Crop to the used window plus a border of 2 px for bilinear sampling.
    const double u0 = std::floor(e.u0) - 2, v0 = std::floor(e.v0) - 2;
    const double u1 = std::ceil(e.u1) + 2, v1 = std::ceil(e.v1) + 2;
    Pass pass;
    pass.camera_from_pass = SE3(FaceRotation(f), Vector3d::Zero());
    pass.view.width = static_cast<int>(u1 - u0) + 1;
    pass.view.height = static_cast<int>(v1 - v0) + 1;
    pass.view.fx = fisheye ? f_face : p.fx;
    pass.view.fy = fisheye ? f_face : p.fy;
    pass.view.cx = -u0;  // pixel (0,0) of the crop is at offset (u0, v0) from the principal point
    pass.view.cy = -v0;
    pass_of_face[static_cast<std::size_t>(f)] = static_cast<int>(passes_.size());
    origin_of_face[static_cast<std::size_t>(f)] = Vector2d(u0, v0);
    passes_.push_back(pass);
  }
  lut_.resize(bearings.size());
  remap_.resize(bearings.size());
  if (options_.ReadsDepth()) depth_scale_.assign(bearings.size(), 0.0f);
  for (std::size_t i = 0; i < bearings.size(); ++i) {
    if (face_of[i] < 0) continue;
    const int f = face_of[i];
    const Vector3d q = FaceRotation(f).transpose() * bearings[i];
    const Vector2d uv = project_in(f, bearings[i]) - origin_of_face[static_cast<std::size_t>(f)];
    LutEntry& e = lut_[i];
    e.x = static_cast<float>(uv.x());
    e.y = static_cast<float>(uv.y());
    e.pass = static_cast<std::uint8_t>(pass_of_face[static_cast<std::size_t>(f)]);
    e.valid = true;
    const View& pv = passes_[e.pass].view;
    // The crop keeps a 2 px border, so the bilinear block and the nearest pixel stay inside.
    int x0 = std::clamp(static_cast<int>(std::floor(uv.x())), 0, pv.width - 2);
    int y0 = std::clamp(static_cast<int>(std::floor(uv.y())), 0, pv.height - 2);
    long wx = std::clamp(std::lround((uv.x() - x0) * 256.0), 0L, 256L);
    long wy = std::clamp(std::lround((uv.y() - y0) * 256.0), 0L, 256L);
    // A full weight on the right column (bottom row) is the next block's left column (top row)
    // with weight 0: the same sum, and the weights fit in 8 bits.
    if (wx == 256 && x0 + 2 < pv.width) ++x0, wx = 0;
    if (wy == 256 && y0 + 2 < pv.height) ++y0, wy = 0;
    const int nx = std::clamp(static_cast<int>(std::lround(uv.x())), 0, pv.width - 1);
    const int ny = std::clamp(static_cast<int>(std::lround(uv.y())), 0, pv.height - 1);
    if (wx > 255 || wy > 255 || nx < x0 || nx > x0 + 1 || ny < y0 || ny > y0 + 1) {
      std::abort();  // cannot happen with the 2 px border (the sample lies inside the crop)
    }
    RemapEntry& r = remap_[i];
    r.top_left = static_cast<std::uint32_t>(y0 * pv.width + x0);
    r.wx = static_cast<std::uint8_t>(wx);
    r.wy = static_cast<std::uint8_t>(wy);
    r.pass = e.pass;
    r.nearest = static_cast<std::uint8_t>((nx - x0) | (ny - y0) << 1);
    // Camera z of the point at pass depth 1 along this ray: camera z = pass z * b.z / q.z.
    if (options_.ReadsDepth()) depth_scale_[i] = static_cast<float>(bearings[i].z() / q.z());
  }
  PlanUnusedPixels();
}

void CameraRenderer::PlanUnusedPixels() {
  // The pass pixels Compose reads: each output pixel's bilinear block (its nearest pixel is one
  // of the four).
  std::vector<std::vector<bool>> used(passes_.size());
  for (std::size_t k = 0; k < passes_.size(); ++k) {
    used[k].assign(std::size_t(passes_[k].view.width) * passes_[k].view.height, false);
  }
  for (const RemapEntry& r : remap_) {
    if (r.nearest == RemapEntry::kInvalid) continue;
    std::vector<bool>& u = used[r.pass];
    const std::size_t w = std::size_t(passes_[r.pass].view.width);
    u[r.top_left] = u[r.top_left + 1] = u[r.top_left + w] = u[r.top_left + w + 1] = true;
  }
  // Unused blocks of kBlock x kBlock pixels (llvmpipe shades 4x4 blocks; a coarser grid keeps
  // the rectangles few), as runs along block rows merged with identical runs of the rows below.
  constexpr int kBlock = 8;
  unused_.assign(passes_.size(), {});
  for (std::size_t k = 0; k < passes_.size(); ++k) {
    const int w = passes_[k].view.width, h = passes_[k].view.height;
    auto block_unused = [&](int bx, int by) {
      for (int y = by * kBlock; y < std::min(h, (by + 1) * kBlock); ++y) {
        for (int x = bx * kBlock; x < std::min(w, (bx + 1) * kBlock); ++x) {
          if (used[k][std::size_t(y) * w + x]) return false;
        }
      }
      return true;
    };
    std::vector<PixelRect> open;  // runs of the previous block row, still growing downwards
    for (int by = 0; by * kBlock < h; ++by) {
      const int y0 = by * kBlock, y1 = std::min(h, y0 + kBlock);
      std::vector<PixelRect> runs;
      for (int bx = 0; bx * kBlock < w; ++bx) {
        if (!block_unused(bx, by)) continue;
        const int x0 = bx * kBlock, x1 = std::min(w, x0 + kBlock);
        if (!runs.empty() && runs.back().x1 == x0) {
          runs.back().x1 = x1;
        } else {
          runs.push_back({x0, y0, x1, y1});
        }
      }
      std::vector<PixelRect> next;
      for (PixelRect run : runs) {
        const auto same = std::find_if(open.begin(), open.end(), [&](const PixelRect& o) {
          return o.x0 == run.x0 && o.x1 == run.x1;
        });
        if (same != open.end()) {
          run.y0 = same->y0;
          open.erase(same);
        }
        next.push_back(run);
      }
      unused_[k].insert(unused_[k].end(), open.begin(), open.end());  // ended above this row
      open = std::move(next);
    }
    unused_[k].insert(unused_[k].end(), open.begin(), open.end());
  }
}

std::vector<View> CameraRenderer::Passes(const SE3& world_from_camera) const {
  std::vector<View> views;
  for (const Pass& pass : passes_) {
    View v = pass.view;
    v.world_from_camera = world_from_camera * pass.camera_from_pass;
    views.push_back(v);
  }
  return views;
}

std::size_t CameraRenderer::pass_pixel_count() const {
  std::size_t n = 0;
  for (const Pass& p : passes_) n += static_cast<std::size_t>(p.view.width) * p.view.height;
  return n;
}

std::optional<std::pair<int, Eigen::Vector2d>> CameraRenderer::Lookup(int u, int v) const {
  if (u < 0 || v < 0 || u >= options_.model.width() || v >= options_.model.height()) {
    return std::nullopt;
  }
  // The centre sample (supersampling).
  u = n_ * u + (n_ - 1) / 2;
  v = n_ * v + (n_ - 1) / 2;
  const int width = draw_model_.width();
  if (lut_.empty()) return std::make_pair(0, Vector2d(u, v));
  const LutEntry& e = lut_[static_cast<std::size_t>(v) * width + u];
  if (!e.valid) return std::nullopt;
  return std::make_pair(static_cast<int>(e.pass), Vector2d(e.x, e.y));
}

void CameraRenderer::Render(const Scene& scene, Backend& backend, const SE3& world_from_camera,
                            CameraFrame* frame) {
  Draw(scene, backend, world_from_camera);
  Finish(frame);
}

void CameraRenderer::Draw(const Scene& scene, Backend& backend, const SE3& world_from_camera) {
  world_from_camera_ = world_from_camera;
  std::vector<View> views = Passes(world_from_camera);
  // Baked lighting needs no per-pixel lights; otherwise the nearest few light each pass.
  const std::vector<int> lights =
      scene.options.bake_lighting
          ? std::vector<int>{}
          : NearestLights(scene, world_from_camera.translation(), scene.options.max_lights);
  // All passes in one batch: the backend submits the next pass while the last one rasterises.
  std::vector<std::vector<int>> visible(views.size());
  std::vector<DrawRequest> requests(views.size());
  for (std::size_t k = 0; k < views.size(); ++k) {
    views[k].read_depth = options_.ReadsDepth();
    visible[k] = VisibleDrawables(scene, views[k]);
  }
  const auto gain = static_cast<float>(ExposureGain(scene, world_from_camera, visible));
  for (std::size_t k = 0; k < views.size(); ++k) {
    requests[k] = DrawRequest{views[k], visible[k], lights, &rendered_[k], unused_pixels(k), gain};
  }
  backend.DrawPasses(requests);
}

double CameraRenderer::ExposureGain(const Scene& scene, const SE3& world_from_camera,
                                    std::span<const std::vector<int>> visible) const {
  const ExposureOptions& e = options_.exposure;
  if (e.mode == ExposureMode::kFixed) return e.gain;
  const double mean = MeteredLuminance(scene, world_from_camera.translation(), visible);
  if (!(mean > 0)) return e.max_gain;
  return std::clamp(e.target / mean, e.min_gain, e.max_gain);
}

void CameraRenderer::Finish(CameraFrame* frame) {
  frame->camera_id = options_.id;
  frame->world_from_camera = world_from_camera_;
  if (n_ > 1) {
    if (lut_.empty()) {
      std::swap(hires_.rgb, rendered_[0].rgb);
      std::swap(hires_.instance, rendered_[0].instance);
      std::swap(hires_.semantic, rendered_[0].semantic);
      if (options_.ReadsDepth()) std::swap(hires_.depth_m, rendered_[0].depth_m);
    } else {
      Compose(&hires_);
    }
    Downsample(hires_, frame);
  } else if (lut_.empty()) {
    // One exact pass: hand its buffers over (the frame's old buffers come back for reuse).
    RenderedView& r = rendered_[0];
    std::swap(frame->rgb, r.rgb);
    std::swap(frame->instance, r.instance);
    std::swap(frame->semantic, r.semantic);
    if (options_.ReadsDepth()) std::swap(frame->depth_m, r.depth_m);
  } else {
    Compose(frame);
  }
}

void CameraRenderer::Downsample(const CameraFrame& hires, CameraFrame* frame) const {
  const int width = options_.model.width(), height = options_.model.height(), n = n_;
  const std::size_t hw = static_cast<std::size_t>(width) * n;
  SizeFrame(width, height, options_.ReadsDepth(), frame);
  const unsigned count = static_cast<unsigned>(n * n);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      const std::size_t out = static_cast<std::size_t>(v) * width + u;
      unsigned sum[3] = {0, 0, 0};
      for (int dy = 0; dy < n; ++dy) {
        const std::size_t row = (static_cast<std::size_t>(v) * n + dy) * hw;
        for (int dx = 0; dx < n; ++dx) {
          const std::uint8_t* px =
              &hires.rgb.data[(row + static_cast<std::size_t>(u) * n + dx) * 3];
          for (int c = 0; c < 3; ++c) sum[c] += px[c];
        }
      }
      for (int c = 0; c < 3; ++c) {
        frame->rgb.data[out * 3 + c] = static_cast<std::uint8_t>((sum[c] + count / 2) / count);
      }
      const std::size_t centre = (static_cast<std::size_t>(v) * n + (n - 1) / 2) * hw +
                                 static_cast<std::size_t>(u) * n + (n - 1) / 2;
      frame->instance[out] = hires.instance[centre];
      frame->semantic[out] = hires.semantic[centre];
      if (options_.ReadsDepth()) frame->depth_m.data[out] = hires.depth_m.data[centre];
    }
  }
}

void CameraRenderer::Compose(CameraFrame* frame) const {
  const int width = draw_model_.width(), height = draw_model_.height();
  SizeFrame(width, height, options_.ReadsDepth(), frame);
  // Per pass: where its images start (up to 6 cube faces).
  std::array<detail::PassImages, 6> images{};
  for (std::size_t k = 0; k < rendered_.size() && k < images.size(); ++k) {
    const RenderedView& r = rendered_[k];
    images[k] = {r.rgb.data.data(), r.instance.data(), r.semantic.data(),
                 options_.ReadsDepth() ? r.depth_m.data.data() : nullptr, std::size_t(r.rgb.width)};
  }
  detail::NearestLabels(remap_, images, options_.ReadsDepth() ? depth_scale_.data() : nullptr,
                        frame->instance.data(), frame->semantic.data(),
                        options_.ReadsDepth() ? frame->depth_m.data.data() : nullptr);
  detail::BilinearRgb(remap_, images, frame->rgb.data.data());
}

}  // namespace corridorsim::render

#include "harness/workbench/detect.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "common/enum_names.h"
#include "common/error.h"
#include "common/io/atomic_file.h"
#include "common/io/camera_json.h"
#include "common/io/json_input.h"
#include "common/io/stable_json.h"
#include "harness/run/frame_io.h"
#include "render/camera_rig.h"
#include "slam/features/ceiling_lamps.h"
#include "slam/features/door_plates.h"
#include "slam/features/harris_corners.h"
#include "slam/features/image_conversion.h"
#include "slam/features/upward_doors.h"
#include "slam/features/vanishing_point.h"
#include "worlds/image_io.h"

namespace corridorsim {
namespace {

[[noreturn]] void Bad(const std::filesystem::path& file, const std::string& message) {
  throw InputError(SourceLocation{file.string(), 0, 0}, "", message);
}

// The bytes of a regular file of at most kMaxDetectFileBytes, read once. Opening never blocks (a
// FIFO without a writer), and the opened descriptor is what is checked.
std::vector<std::uint8_t> ReadInputFile(const std::filesystem::path& path) {
  const std::string name = path.string();
  if (name.find('\0') != std::string::npos) Bad(path, "cannot be opened: a NUL in its name");
  const int fd = ::open(name.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) Bad(path, std::string("cannot be opened: ") + std::strerror(errno));
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) Bad(path, std::string("cannot be read: ") + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) Bad(path, "is not a regular file");
  const std::string too_large =
      "is larger than the limit of " + std::to_string(kMaxDetectFileBytes >> 20) + " MiB";
  if (st.st_size < 0 || static_cast<std::uint64_t>(st.st_size) > kMaxDetectFileBytes) {
    Bad(path, too_large);
  }
  std::vector<std::uint8_t> bytes;
  bytes.reserve(static_cast<std::size_t>(st.st_size));
  std::uint8_t buffer[1 << 16];
  while (true) {
    const ssize_t n = ::read(fd, buffer, sizeof(buffer));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) Bad(path, std::string("cannot be read: ") + std::strerror(errno));
    if (n == 0) break;
    bytes.insert(bytes.end(), buffer, buffer + n);
    if (bytes.size() > kMaxDetectFileBytes) Bad(path, too_large);
  }
  return bytes;
}

// Decodes a PNG after checking its signature and its header's size against the bounds (so that a
// huge image is refused before any pixel is decoded).
DecodedPng ReadPngFile(const std::filesystem::path& path, const std::string& what) {
  const std::vector<std::uint8_t> bytes = ReadInputFile(path);
  static const std::uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (bytes.size() < 33 || std::memcmp(bytes.data(), kSignature, 8) != 0 ||
      std::memcmp(bytes.data() + 12, "IHDR", 4) != 0) {
    Bad(path, "is not a PNG image (" + what + ")");
  }
  const auto be32 = [&](std::size_t at) {
    return (std::uint32_t{bytes[at]} << 24) | (std::uint32_t{bytes[at + 1]} << 16) |
           (std::uint32_t{bytes[at + 2]} << 8) | std::uint32_t{bytes[at + 3]};
  };
  const std::uint32_t width = be32(16), height = be32(20);
  if (width == 0 || height == 0 || width > kMaxDetectImageSide || height > kMaxDetectImageSide) {
    Bad(path, "is " + std::to_string(width) + "x" + std::to_string(height) +
                  " px: each side must lie in [1, " + std::to_string(kMaxDetectImageSide) + "]");
  }
  try {
    return DecodePng(bytes, static_cast<int>(kMaxDetectImageSide), what);
  } catch (const std::invalid_argument&) {
    Bad(path, "is not a readable PNG image (" + what + ")");
  }
}

cv::Mat View(Image8* image) {
  return cv::Mat(image->height, image->width, CV_8UC3, image->data.data());
}
cv::Point At(const Eigen::Vector2d& p) {  // 1/16 px for the drawing functions' shift of 4
  return cv::Point(static_cast<int>(std::lround(p.x() * 16)),
                   static_cast<int>(std::lround(p.y() * 16)));
}
nlohmann::ordered_json Px(const Eigen::Vector2d& p) { return RoundedJson(p, json_steps::kPx); }
nlohmann::ordered_json LineJson(const slam::ImageLineSegment& line) {
  return nlohmann::ordered_json::array(
      {RoundToStep(line.a_px.x(), json_steps::kPx), RoundToStep(line.a_px.y(), json_steps::kPx),
       RoundToStep(line.b_px.x(), json_steps::kPx), RoundToStep(line.b_px.y(), json_steps::kPx)});
}
// A section of `count` items with one tally of them (`tally_key`: how many have depth, how many
// were accepted), in that order.
nlohmann::ordered_json ItemsSection(std::size_t count, const char* tally_key, int tally,
                                    nlohmann::ordered_json items) {
  nlohmann::ordered_json j;
  j["count"] = count;
  j[tally_key] = tally;
  j["items"] = std::move(items);
  return j;
}
// Six significant digits (a Harris response has no fixed scale).
double Significant6(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.6g", value);
  return std::strtod(text, nullptr);
}

}  // namespace

Image8 ReadRgbPng(const std::filesystem::path& path, const std::string& what) {
  return DecodedPngAsRgb(ReadPngFile(path, what));
}

constexpr EnumName<DetectCamera> kDetectCameraNames[] = {{DetectCamera::kFront, "front"},
                                                         {DetectCamera::kLateral, "lateral"},
                                                         {DetectCamera::kUpward, "upward"}};

std::string DetectCameraName(DetectCamera camera) { return NameOf(kDetectCameraNames, camera); }

DetectInput LoadDetectInput(const DetectRequest& request) {
  DetectInput input;
  input.image_name = request.image_file.string();
  input.camera = request.camera;
  input.rgb = ReadRgbPng(request.image_file, "the image");
  if (request.depth_file) {
    const std::filesystem::path& path = *request.depth_file;
    const DecodedPng raw = ReadPngFile(path, "the --depth image");
    if (raw.bit_depth != 16 || raw.channels != 1) {
      Bad(path, "--depth: expected a 16-bit one-channel PNG at " +
                    std::to_string(static_cast<int>(kDepthScale)) +
                    " per metre (TUM RGB-D, as snapshot writes front_depth.png)");
    }
    if (raw.width != input.rgb.width || raw.height != input.rgb.height) {
      Bad(path, "--depth: the depth image is " + std::to_string(raw.width) + "x" +
                    std::to_string(raw.height) + " px, the image " +
                    std::to_string(input.rgb.width) + "x" + std::to_string(input.rgb.height) +
                    " (it must be registered to it)");
    }
    ImageF depth(raw.width, raw.height);
    for (int y = 0; y < raw.height; ++y) {
      const std::uint16_t* row = raw.samples16.data() + std::size_t(y) * raw.width;
      for (int x = 0; x < raw.width; ++x) {
        depth.at(x, y) = static_cast<float>(row[x] / kDepthScale);  // 0 stays 0 (invalid)
      }
    }
    input.depth_m = std::move(depth);
  }
  if (request.camera == DetectCamera::kUpward) {
    if (request.intrinsics_file) {
      const std::filesystem::path& path = *request.intrinsics_file;
      const std::string file = path.string();
      const nlohmann::ordered_json json = ParseJsonInput(ReadRegularFile(path, 1 << 20), file);
      if (!json.is_object()) {
        throw InputError(SourceLocation{file, 0, 0}, "", "expected a JSON object (a camera model)");
      }
      // dataset's intrinsics.json holds the upward camera's entry, snapshot's and drive's every
      // camera's by name.
      try {
        input.model = CameraModelFromIntrinsicsJson(json, "upward");
      } catch (const OptionsError& e) {
        throw InputError(SourceLocation{file, 0, 0}, e.problem().key, e.problem().message);
      }
      if (input.model->width() != input.rgb.width || input.model->height() != input.rgb.height) {
        throw InputError(SourceLocation{file, 0, 0}, "width",
                         "the model is " + std::to_string(input.model->width()) + "x" +
                             std::to_string(input.model->height()) + " px, the image " +
                             std::to_string(input.rgb.width) + "x" +
                             std::to_string(input.rgb.height));
      }
    } else {
      const render::RigOptions rig = render::RigOptions::Default();
      const render::CameraOptions* upward = rig.Find("upward");
      CheckOrDie(upward != nullptr, "LoadDetectInput", "the default rig has no upward camera");
      if (upward->model.width() != input.rgb.width || upward->model.height() != input.rgb.height) {
        Bad(request.image_file,
            "--camera upward: the image is " + std::to_string(input.rgb.width) + "x" +
                std::to_string(input.rgb.height) + " px, not the default upward camera's " +
                std::to_string(upward->model.width()) + "x" +
                std::to_string(upward->model.height()) + "; give its model with --intrinsics FILE");
      }
      input.model = upward->model;
    }
  }
  return input;
}

nlohmann::ordered_json VanishingPointSection(const DetectInput& input, Image8* overlay) {
  const slam::VanishingPointOptions options;
  slam::VanishingPointReport report;
  const std::optional<slam::VanishingPoint> vp =
      slam::DetectVanishingPoint(input.rgb, options, &report);
  nlohmann::ordered_json j;
  j["found"] = vp.has_value();
  j["status"] = slam::VanishingPointStatusName(report.status);
  j["pixel"] = vp ? Px(vp->pixel_px) : nlohmann::ordered_json();
  const slam::VanishingPointQuality& q = report.quality;
  j["quality"] = {{"rms_residual_px", RoundToStep(q.rms_residual_px, json_steps::kPx)},
                  {"line_count", q.line_count},
                  {"direction_count", q.direction_count},
                  {"candidate_count", q.candidate_count},
                  {"rejected_axis_count", q.rejected_axis_count},
                  {"merged_count", q.merged_count},
                  {"rejected_outlier_count", q.rejected_outlier_count}};
  j["lines"] = nlohmann::ordered_json::array();
  if (vp) {
    for (const slam::ImageLineSegment& line : vp->lines) j["lines"].push_back(LineJson(line));
  }
  j["candidate_lines"] = nlohmann::ordered_json::array();
  for (const slam::ImageLineSegment& line : report.candidate_lines) {
    j["candidate_lines"].push_back(LineJson(line));
  }
  if (overlay) {
    cv::Mat view = View(overlay);  // RGB: colours below are (r, g, b)
    for (const slam::ImageLineSegment& line : report.candidate_lines) {
      cv::line(view, At(line.a_px), At(line.b_px), cv::Scalar(255, 60, 60), 1, cv::LINE_AA, 4);
    }
    if (vp) {
      for (const slam::ImageLineSegment& line : vp->lines) {
        cv::line(view, At(line.a_px), At(line.b_px), cv::Scalar(40, 255, 40), 2, cv::LINE_AA, 4);
      }
      cv::circle(view, At(vp->pixel_px), 8 * 16, cv::Scalar(255, 0, 255), 2, cv::LINE_AA, 4);
      cv::drawMarker(view,
                     cv::Point(static_cast<int>(std::lround(vp->pixel_px.x())),
                               static_cast<int>(std::lround(vp->pixel_px.y()))),
                     cv::Scalar(255, 0, 255), cv::MARKER_TILTED_CROSS, 14, 2);
    }
  }
  return j;
}

nlohmann::ordered_json CornersSection(const DetectInput& input, Image8* overlay) {
  const slam::HarrisCornerOptions options;
  const std::vector<slam::HarrisCorner> corners =
      slam::DetectHarrisCorners(input.rgb, input.depth_m ? &*input.depth_m : nullptr, options);
  int with_depth = 0;
  nlohmann::ordered_json items = nlohmann::ordered_json::array();
  for (const slam::HarrisCorner& c : corners) {
    with_depth += c.depth_m.has_value();
    items.push_back({{"pixel", Px(c.pixel_px)},
                     {"depth_m", c.depth_m ? nlohmann::ordered_json(
                                                 RoundToStep(*c.depth_m, json_steps::kMetres))
                                           : nlohmann::ordered_json()},
                     {"response", Significant6(c.response)}});
  }
  nlohmann::ordered_json j =
      ItemsSection(corners.size(), "with_depth", with_depth, std::move(items));
  if (overlay) {
    cv::Mat view = View(overlay);
    for (const slam::HarrisCorner& c : corners) {
      const cv::Scalar colour = c.depth_m ? cv::Scalar(255, 220, 0) : cv::Scalar(0, 220, 255);
      cv::circle(view, At(c.pixel_px), 3 * 16, colour, 1, cv::LINE_AA, 4);
    }
  }
  return j;
}

nlohmann::ordered_json PlatesSection(const DetectInput& input, Image8* overlay) {
  // The shipped models (models/, docs/detectors.md); a missing or corrupt file is bad input.
  const slam::DoorPlateModels models = slam::DoorPlateModels::Load();
  const slam::DoorPlateOptions options;
  slam::CheckModelsFit(models, options);
  const std::vector<slam::DoorPlateDetection> plates =
      slam::DetectDoorPlates(input.rgb, models, options);
  const auto box = [](const slam::BoxPx& b) {
    return nlohmann::ordered_json::array(
        {RoundToStep(b.min_x, json_steps::kPx), RoundToStep(b.min_y, json_steps::kPx),
         RoundToStep(b.max_x, json_steps::kPx), RoundToStep(b.max_y, json_steps::kPx)});
  };
  nlohmann::ordered_json items = nlohmann::ordered_json::array();
  int accepted = 0;
  for (const slam::DoorPlateDetection& p : plates) {
    accepted += p.reading.accepted;
    nlohmann::ordered_json digits = nlohmann::ordered_json::array();
    for (const slam::DigitReading& d : p.reading.digits) {
      digits.push_back({{"digit", std::string(1, d.digit)},
                        {"score", RoundToStep(d.score, json_steps::kRatio)},
                        {"box_px", box(d.box_px)}});
    }
    items.push_back({{"box_px", box(p.box_px)},
                     {"svm_score", Significant6(p.svm_score)},
                     {"number", p.reading.number},
                     {"accepted", p.reading.accepted},
                     {"min_digit_score", RoundToStep(p.reading.min_score, json_steps::kRatio)},
                     {"digits", std::move(digits)}});
  }
  nlohmann::ordered_json j = ItemsSection(plates.size(), "accepted", accepted, std::move(items));
  if (overlay) {
    cv::Mat view = View(overlay);
    for (const slam::DoorPlateDetection& p : plates) {
      // Accepted readings green with their number, the others red.
      const cv::Scalar colour = p.reading.accepted ? cv::Scalar(0, 230, 0) : cv::Scalar(230, 0, 0);
      cv::rectangle(view, At({p.box_px.min_x, p.box_px.min_y}),
                    At({p.box_px.max_x, p.box_px.max_y}), colour, 1, cv::LINE_AA, 4);
      if (p.reading.accepted) {
        cv::putText(view, p.reading.number,
                    cv::Point(static_cast<int>(p.box_px.min_x),
                              std::max(10, static_cast<int>(p.box_px.min_y) - 3)),
                    cv::FONT_HERSHEY_SIMPLEX, 0.5, colour, 1, cv::LINE_AA);
      }
    }
  }
  return j;
}

nlohmann::ordered_json LampsSection(const DetectInput& input, Image8* overlay) {
  const slam::CeilingLampOptions options;
  const slam::CeilingLampDetection found =
      slam::DetectCeilingLamps(input.rgb, input.model ? &*input.model : nullptr, options);
  const auto region = [](const slam::CeilingLampRegion& r) {
    nlohmann::ordered_json j;
    j["center_px"] = Px(r.center_px);
    j["radius_px"] = RoundToStep(r.radius_px, json_steps::kPx);
    j["sigma1_px"] = std::isfinite(r.sigma1_px)
                         ? nlohmann::ordered_json(RoundToStep(r.sigma1_px, json_steps::kPx))
                         : nlohmann::ordered_json();
    j["sigma2_px"] = std::isfinite(r.sigma2_px)
                         ? nlohmann::ordered_json(RoundToStep(r.sigma2_px, json_steps::kPx))
                         : nlohmann::ordered_json();
    j["area_px"] = r.area_px;
    j["edge_points"] = r.edge_points;
    j["edge_contrast"] = RoundToStep(r.edge_contrast, 100);
    j["cut_by_border"] = r.cut_by_border;
    if (!r.circular) j["rejection"] = r.rejection;
    return j;
  };
  nlohmann::ordered_json j;
  j["k_conv_px"] = options.k_conv_px;
  j["regions"] = found.regions;
  j["regions_skipped"] = found.regions_skipped;
  j["lamps"] = nlohmann::ordered_json::array();
  for (const slam::CeilingLampRegion& r : found.lamps) j["lamps"].push_back(region(r));
  j["rejected"] = nlohmann::ordered_json::array();
  for (const slam::CeilingLampRegion& r : found.rejected) j["rejected"].push_back(region(r));
  if (overlay) {
    cv::Mat view = slam::MatView(*overlay);
    const auto draw = [&](const slam::CeilingLampRegion& r, const cv::Scalar& colour) {
      const double radius = r.radius_px > 0 ? r.radius_px : 6.0;
      cv::circle(view, At(r.center_px), static_cast<int>(std::lround(radius * 16)), colour, 1,
                 cv::LINE_AA, 4);
      cv::drawMarker(
          view, cv::Point(int(std::lround(r.center_px.x())), int(std::lround(r.center_px.y()))),
          colour, cv::MARKER_CROSS, 7, 1);
    };
    for (const slam::CeilingLampRegion& r : found.rejected) draw(r, cv::Scalar(230, 0, 0));
    for (const slam::CeilingLampRegion& r : found.lamps) draw(r, cv::Scalar(0, 230, 0));
  }
  return j;
}

nlohmann::ordered_json UpwardDoorsSection(const DetectInput& input, Image8* overlay) {
  const slam::UpwardDoorOptions options;
  const Eigen::Vector2d principal_point =
      input.model ? input.model->principal_point()
                  : Eigen::Vector2d(0.5 * (input.rgb.width - 1), 0.5 * (input.rgb.height - 1));
  const cv::Mat grey = slam::GreyMat(input.rgb);
  const slam::UpwardDoorDetection found =
      slam::DetectUpwardDoorCandidates(grey, principal_point, options);
  nlohmann::ordered_json j;
  std::size_t vertical = 0;
  for (const slam::UpwardLine& l : found.lines) vertical += l.vertical ? 1 : 0;
  j["lines"] = found.lines.size();
  j["vertical_lines"] = vertical;
  j["columns"] = nlohmann::ordered_json::array();
  for (const slam::DoorColumn& c : found.columns) {
    j["columns"].push_back({{"angle_rad", RoundToStep(c.angle_rad, json_steps::kRad)},
                            {"top_px", Px(c.top_px)},
                            {"top_radius_px", RoundToStep(c.top_radius_px, json_steps::kPx)},
                            {"bottom_radius_px", RoundToStep(c.bottom_radius_px, json_steps::kPx)},
                            {"lines", c.lines}});
  }
  j["candidates"] = nlohmann::ordered_json::array();
  for (const slam::UpwardDoorCandidate& c : found.candidates) {
    j["candidates"].push_back({{"column_a", c.column_a},
                               {"column_b", c.column_b},
                               {"angle_a_rad", RoundToStep(c.angle_a_rad, json_steps::kRad)},
                               {"angle_b_rad", RoundToStep(c.angle_b_rad, json_steps::kRad)},
                               {"top_a_px", Px(c.top_a_px)},
                               {"top_b_px", Px(c.top_b_px)},
                               {"bar_coverage", RoundToStep(c.bar_coverage, 1000)}});
  }
  if (overlay) {
    cv::Mat view = slam::MatView(*overlay);
    for (const slam::UpwardLine& l : found.lines) {
      if (l.vertical)
        cv::line(view, At(l.a_px), At(l.b_px), cv::Scalar(230, 0, 0), 1, cv::LINE_AA, 4);
    }
    for (const slam::UpwardDoorCandidate& c : found.candidates) {
      cv::line(view, At(c.top_a_px), At(c.top_b_px), cv::Scalar(255, 160, 0), 2, cv::LINE_AA, 4);
      cv::line(view, At(principal_point), At(c.top_a_px), cv::Scalar(255, 160, 0), 1, cv::LINE_AA,
               4);
      cv::line(view, At(principal_point), At(c.top_b_px), cv::Scalar(255, 160, 0), 1, cv::LINE_AA,
               4);
    }
  }
  return j;
}

nlohmann::ordered_json RunDetect(const DetectInput& input, Image8* overlay) {
  if (overlay) *overlay = input.rgb;
  nlohmann::ordered_json doc;
  doc["image"] = input.image_name;
  doc["camera"] = DetectCameraName(input.camera);
  doc["width"] = input.rgb.width;
  doc["height"] = input.rgb.height;
  doc["depth"] = input.depth_m.has_value();
  // One section per detector the camera runs (P1: the vanishing point from the front RGB-D
  // sensor, door plates from the lateral web camera; corners from either).
  if (input.camera == DetectCamera::kFront) {
    doc["vanishing_point"] = VanishingPointSection(input, overlay);
  }
  if (input.camera == DetectCamera::kLateral) doc["door_plates"] = PlatesSection(input, overlay);
  if (input.camera == DetectCamera::kUpward) {
    doc["model"] = input.model ? std::string(input.model->name()) : "";
    doc["lamps"] = LampsSection(input, overlay);
    doc["doors"] = UpwardDoorsSection(input, overlay);
  }
  doc["corners"] = CornersSection(input, overlay);
  return doc;
}

void RunDetectJob(const DetectRequest& request) {
  if (request.overlay_file) {
    const std::filesystem::path parent = request.overlay_file->parent_path();
    std::error_code error;
    if (!parent.empty() && !std::filesystem::is_directory(parent, error)) {
      throw InputError(SourceLocation{"command line", 0, 0}, "--out",
                       "the folder '" + parent.string() + "' does not exist");
    }
    // Checked before the detectors run: the image goes to a file of that name, never a folder.
    if (!request.overlay_file->has_filename() ||
        std::filesystem::is_directory(*request.overlay_file, error)) {
      throw InputError(SourceLocation{"command line", 0, 0}, "--out",
                       "'" + request.overlay_file->string() + "' is a folder, not a PNG file name");
    }
  }
  const DetectInput input = LoadDetectInput(request);
  Image8 overlay;
  const nlohmann::ordered_json doc = RunDetect(input, request.overlay_file ? &overlay : nullptr);
  if (request.overlay_file) {
    WriteFileAtomic(*request.overlay_file,
                    EncodePng(overlay, request.overlay_file->filename().string()));
  }
  std::fputs(JsonFileText(doc).c_str(), stdout);
}

}  // namespace corridorsim

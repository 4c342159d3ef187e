#include "worlds/textures.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

#include <opencv2/imgproc.hpp>

namespace corridorsim::worlds {
namespace {

Image8 ToImage(const cv::Mat& rgb) {
  Image8 out(rgb.cols, rgb.rows, 3);
  for (int y = 0; y < rgb.rows; ++y) {
    std::memcpy(out.Pixel(0, y), rgb.ptr<std::uint8_t>(y), std::size_t(rgb.cols) * 3);
  }
  return out;
}

cv::Scalar Rgb(double r, double g, double b) { return cv::Scalar(r, g, b); }

int I(double v) { return static_cast<int>(v); }

// Low-frequency seeded noise in [-1, 1]: random values on a coarse grid, smoothly upsampled
// (Catmull-Rom) with the grid wrapped around, so the texture tiles without a step at its edges.
cv::Mat SmoothNoise(RandomStream& rng, int size_px, int cells) {
  std::vector<float> coarse(static_cast<std::size_t>(cells) * cells);
  for (float& c : coarse) c = static_cast<float>(rng.Uniform(-1, 1));
  auto at = [&](int x, int y) {
    x = ((x % cells) + cells) % cells;
    y = ((y % cells) + cells) % cells;
    return coarse[static_cast<std::size_t>(y) * cells + x];
  };
  auto weights = [](double t, double w[4]) {  // Catmull-Rom at offsets -1, 0, 1, 2
    const double t2 = t * t, t3 = t2 * t;
    w[0] = 0.5 * (-t3 + 2 * t2 - t);
    w[1] = 0.5 * (3 * t3 - 5 * t2 + 2);
    w[2] = 0.5 * (-3 * t3 + 4 * t2 + t);
    w[3] = 0.5 * (t3 - t2);
  };
  cv::Mat fine(size_px, size_px, CV_32F);
  const double scale = static_cast<double>(cells) / size_px;
  for (int y = 0; y < size_px; ++y) {
    const double gy = (y + 0.5) * scale - 0.5;
    const int y0 = static_cast<int>(std::floor(gy));
    double wy[4];
    weights(gy - y0, wy);
    for (int x = 0; x < size_px; ++x) {
      const double gx = (x + 0.5) * scale - 0.5;
      const int x0 = static_cast<int>(std::floor(gx));
      double wx[4];
      weights(gx - x0, wx);
      double v = 0;
      for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 4; ++i) v += wy[j] * wx[i] * at(x0 - 1 + i, y0 - 1 + j);
      }
      fine.at<float>(y, x) = static_cast<float>(v);
    }
  }
  return fine;
}

// Draws `draw(offset)` at the offsets that put a shape of reach `r` around `c` back into a
// wrapping texture: once, or also on the far side of each edge it crosses.
template <class Draw>
void Wrapped(const cv::Mat& img, const cv::Point& c, int r, Draw&& draw) {
  for (const int dy : {-img.rows, 0, img.rows}) {
    for (const int dx : {-img.cols, 0, img.cols}) {
      const cv::Point p = c + cv::Point(dx, dy);
      if (p.x + r < 0 || p.y + r < 0 || p.x - r >= img.cols || p.y - r >= img.rows) continue;
      draw(cv::Point(dx, dy));
    }
  }
}

// A colour of three channels drawn from [lo, hi] each, one draw per statement and the last
// channel first: the order GCC gave the former `cv::Vec3d(rng.Uniform(..), ..)`, whose argument
// order was the compiler's, so that clang and GCC builds draw the same textures.
cv::Vec3d Colour(RandomStream& rng, std::pair<double, double> c0, std::pair<double, double> c1,
                 std::pair<double, double> c2) {
  const double v2 = rng.Uniform(c2.first, c2.second);
  const double v1 = rng.Uniform(c1.first, c1.second);
  const double v0 = rng.Uniform(c0.first, c0.second);
  return {v0, v1, v2};
}

// Adds `count` dots of random size and darkness (speckles give corner detectors something);
// dots across an edge continue on the other side (the texture wraps).
void Speckle(RandomStream& rng, cv::Mat& img, int count, int max_radius, double max_darkening) {
  for (int k = 0; k < count; ++k) {
    const int cy = I(rng.Uniform(0, img.rows)), cx = I(rng.Uniform(0, img.cols));
    const cv::Point c(cx, cy);
    const int r = static_cast<int>(rng.UniformInt(1, max_radius));
    const double f = 1.0 - rng.Uniform(0.3, 1.0) * max_darkening;
    const cv::Vec3b base =
        img.at<cv::Vec3b>(std::clamp(c.y, 0, img.rows - 1), std::clamp(c.x, 0, img.cols - 1));
    Wrapped(img, c, r + 1, [&](const cv::Point& offset) {
      cv::circle(img, c + offset, r, cv::Scalar(base[0] * f, base[1] * f, base[2] * f), cv::FILLED,
                 cv::LINE_AA);
    });
  }
}

cv::Mat Tinted(const cv::Mat& noise, const cv::Vec3d& colour, double amplitude) {
  cv::Mat img(noise.size(), CV_8UC3);
  for (int y = 0; y < img.rows; ++y) {
    for (int x = 0; x < img.cols; ++x) {
      const double f = 1.0 + amplitude * noise.at<float>(y, x);
      img.at<cv::Vec3b>(y, x) = cv::Vec3b(cv::saturate_cast<std::uint8_t>(colour[0] * f),
                                          cv::saturate_cast<std::uint8_t>(colour[1] * f),
                                          cv::saturate_cast<std::uint8_t>(colour[2] * f));
    }
  }
  return img;
}

const int kHersheyFonts[] = {cv::FONT_HERSHEY_SIMPLEX, cv::FONT_HERSHEY_DUPLEX,
                             cv::FONT_HERSHEY_COMPLEX, cv::FONT_HERSHEY_TRIPLEX};
const char* kHersheyNames[] = {"hershey_simplex", "hershey_duplex", "hershey_complex",
                               "hershey_triplex"};

// Draws `text` centred in `box`, as large as fits with `fill` of the box.
void CentredText(cv::Mat& img, const std::string& text, const cv::Rect& box, int font,
                 const cv::Scalar& colour, double fill) {
  int baseline = 0;
  const int thickness = std::max(1, box.height / 14);
  const cv::Size unit = cv::getTextSize(text, font, 1.0, thickness, &baseline);
  const double scale = std::min(box.width * fill / unit.width, box.height * fill / unit.height);
  const cv::Size size = cv::getTextSize(text, font, scale, thickness, &baseline);
  const cv::Point origin(box.x + (box.width - size.width) / 2,
                         box.y + (box.height + size.height) / 2);
  cv::putText(img, text, origin, font, scale, colour, thickness, cv::LINE_AA);
}

}  // namespace

Image8 MakeWallTexture(RandomStream& rng, int size_px) {
  const cv::Vec3d paint = Colour(rng, {200, 235}, {195, 230}, {180, 220});
  const cv::Mat coarse = SmoothNoise(rng, size_px, 24), fine = SmoothNoise(rng, size_px, 6);
  cv::Mat noise = fine * 0.6 + coarse * 0.4;
  cv::Mat img = Tinted(noise, paint, 0.06);
  Speckle(rng, img, size_px * 3, 2, 0.25);
  for (int k = 0; k < 6; ++k) {  // scuffs
    const int ay = I(rng.Uniform(0, size_px)), ax = I(rng.Uniform(0, size_px));
    const cv::Point a(ax, ay);
    const int dy = I(rng.Uniform(-8, 8)), dx = I(rng.Uniform(-40, 40));
    const cv::Point b = a + cv::Point(dx, dy);
    Wrapped(img, a, 42, [&](const cv::Point& offset) {
      cv::line(img, a + offset, b + offset, Rgb(paint[0] * 0.7, paint[1] * 0.7, paint[2] * 0.7), 1,
               cv::LINE_AA);
    });
  }
  return ToImage(img);
}

Image8 MakePlainWallTexture(RandomStream& rng, int size_px) {
  const cv::Vec3d paint = Colour(rng, {200, 235}, {195, 230}, {180, 220});
  return ToImage(Tinted(SmoothNoise(rng, size_px, 4), paint, 0.03));
}

Image8 MakeFloorTexture(RandomStream& rng, int size_px, int tiles) {
  const cv::Vec3d base = Colour(rng, {120, 170}, {115, 160}, {100, 150});
  cv::Mat img = Tinted(SmoothNoise(rng, size_px, 16), base, 0.08);
  Speckle(rng, img, size_px * 6, 2, 0.4);
  const int step = size_px / tiles;
  for (int k = 0; k <= tiles; ++k) {
    const int p = std::min(k * step, size_px - 1);
    const cv::Scalar seam = Rgb(base[0] * 0.55, base[1] * 0.55, base[2] * 0.55);
    cv::line(img, {p, 0}, {p, size_px - 1}, seam, 2);
    cv::line(img, {0, p}, {size_px - 1, p}, seam, 2);
  }
  return ToImage(img);
}

Image8 MakeCeilingTexture(RandomStream& rng, int size_px, int tiles) {
  const cv::Vec3d base = Colour(rng, {225, 240}, {225, 240}, {220, 235});
  cv::Mat img = Tinted(SmoothNoise(rng, size_px, 8), base, 0.03);
  const int step = size_px / tiles;
  for (int ty = 0; ty < tiles; ++ty) {  // perforation dots per tile
    for (int tx = 0; tx < tiles; ++tx) {
      for (int k = 0; k < 40; ++k) {
        const int dy = I(rng.Uniform(4, step - 4)), dx = I(rng.Uniform(4, step - 4));
        const cv::Point c(tx * step + dx, ty * step + dy);
        cv::circle(img, c, 1, Rgb(base[0] * 0.75, base[1] * 0.75, base[2] * 0.75), cv::FILLED);
      }
    }
  }
  // Seams on the tile borders: the texture wraps, so border lines straddle both edges.
  const cv::Scalar seam = Rgb(90, 90, 95);
  for (int k = 0; k <= tiles; ++k) {
    const int p = k * step;
    cv::rectangle(img, cv::Rect(p - 2, 0, 4, size_px), seam, cv::FILLED);
    cv::rectangle(img, cv::Rect(0, p - 2, size_px, 4), seam, cv::FILLED);
  }
  return ToImage(img);
}

Image8 MakeRoomCeilingTexture(RandomStream& rng, int size_px) {
  const cv::Vec3d base = Colour(rng, {215, 235}, {210, 230}, {200, 225});
  cv::Mat img = Tinted(SmoothNoise(rng, size_px, 10), base, 0.05);
  Speckle(rng, img, size_px * 2, 2, 0.3);
  return ToImage(img);
}

Image8 MakeDoorTexture(RandomStream& rng, int width_px, int height_px) {
  const cv::Vec3d wood = Colour(rng, {120, 170}, {80, 110}, {40, 70});
  cv::Mat img(height_px, width_px, CV_8UC3, cv::Scalar(wood[0], wood[1], wood[2]));
  for (int x = 0; x < width_px; ++x) {  // grain: vertical streaks of varying darkness
    const double phase = rng.Uniform(0, 0.8), jitter = rng.Uniform(-0.04, 0.04);
    const double f = 0.85 + 0.15 * std::sin(x * 0.35 + phase) + jitter;
    cv::line(img, {x, 0}, {x, height_px - 1}, Rgb(wood[0] * f, wood[1] * f, wood[2] * f));
  }
  Speckle(rng, img, width_px, 2, 0.3);
  return ToImage(img);
}

Image8 MakePlateTexture(RandomStream& rng, const std::string& room_number, double aspect,
                        PlateStyle* style,
                        const std::optional<std::array<Eigen::Vector3d, 2>>& colours_override) {
  // (plate colour, text colour) pairs seen on real door plates.
  static const cv::Vec3d kPalette[][2] = {
      {{245, 245, 240}, {20, 20, 20}}, {{200, 200, 205}, {15, 15, 60}},
      {{240, 230, 200}, {60, 30, 10}}, {{30, 60, 140}, {250, 250, 250}},
      {{20, 90, 60}, {245, 245, 245}}, {{40, 40, 40}, {240, 240, 240}},
  };
  const cv::Vec3d* colours = kPalette[rng.UniformInt(0, 5)];
  cv::Vec3d drawn[2];
  if (colours_override) {
    for (int k = 0; k < 2; ++k) {
      const Eigen::Vector3d& c = (*colours_override)[static_cast<std::size_t>(k)];
      drawn[k] = cv::Vec3d(c[0], c[1], c[2]);
    }
    colours = drawn;
  }
  const int font_index = static_cast<int>(rng.UniformInt(0, 3));
  const int height_px = 128;
  const int width_px = std::max(32, I(height_px * aspect));
  cv::Mat img(height_px, width_px, CV_8UC3,
              cv::Scalar(colours[0][0], colours[0][1], colours[0][2]));
  const int border = static_cast<int>(rng.UniformInt(0, 2)) * 3;
  if (border > 0) {
    cv::rectangle(img, cv::Rect(border, border, width_px - 2 * border, height_px - 2 * border),
                  cv::Scalar(colours[1][0], colours[1][1], colours[1][2]), border);
  }
  const double fill = rng.Uniform(0.6, 0.75);
  const int inset = border * 2 + 4;
  CentredText(img, room_number, cv::Rect(inset, inset, width_px - 2 * inset, height_px - 2 * inset),
              kHersheyFonts[font_index], cv::Scalar(colours[1][0], colours[1][1], colours[1][2]),
              fill);
  if (style) {
    style->font = kHersheyNames[font_index];
    style->border_px = border;
    style->width_px = width_px;
    style->height_px = height_px;
    // The number region: every pixel inside the text box (within the border) that the text
    // changed from the plate colour; anti-aliased edges count.
    const cv::Vec3b plate(cv::saturate_cast<std::uint8_t>(colours[0][0]),
                          cv::saturate_cast<std::uint8_t>(colours[0][1]),
                          cv::saturate_cast<std::uint8_t>(colours[0][2]));
    int x0 = width_px, y0 = height_px, x1 = 0, y1 = 0;
    for (int y = inset; y < height_px - inset; ++y) {
      for (int x = inset; x < width_px - inset; ++x) {
        if (img.at<cv::Vec3b>(y, x) == plate) continue;
        x0 = std::min(x0, x);
        y0 = std::min(y0, y);
        x1 = std::max(x1, x + 1);
        y1 = std::max(y1, y + 1);
      }
    }
    if (x1 <= x0) x0 = y0 = x1 = y1 = 0;  // no text drawn (empty number)
    style->number_x0_px = x0;
    style->number_y0_px = y0;
    style->number_x1_px = x1;
    style->number_y1_px = y1;
  }
  return ToImage(img);
}

Image8 MakePosterTexture(RandomStream& rng, const std::string& text, int width_px, int height_px) {
  const cv::Vec3d bg = Colour(rng, {150, 255}, {150, 255}, {150, 255});
  cv::Mat img(height_px, width_px, CV_8UC3, cv::Scalar(bg[0], bg[1], bg[2]));
  for (int k = 0; k < 5; ++k) {  // blocks of colour
    // The last first (see Colour).
    const int h = I(rng.Uniform(height_px * 0.05, height_px * 0.2));
    const int w = I(rng.Uniform(width_px * 0.1, width_px * 0.4));
    const int y = I(rng.Uniform(height_px * 0.35, height_px * 0.85));
    const int x = I(rng.Uniform(0, width_px * 0.7));
    const cv::Rect r(x, y, w, h);
    const cv::Vec3d colour = Colour(rng, {0, 255}, {0, 255}, {0, 255});
    cv::rectangle(img, r, Rgb(colour[0], colour[1], colour[2]), cv::FILLED);
  }
  const int font = kHersheyFonts[rng.UniformInt(0, 3)];
  CentredText(img, text, cv::Rect(0, 0, width_px, height_px / 3), font, Rgb(20, 20, 20), 0.8);
  for (int k = 0; k < 6; ++k) {  // lines of small print
    const int y = I(height_px * (0.88 + 0.018 * k));
    cv::line(img, {width_px / 10, y}, {I(width_px * rng.Uniform(0.5, 0.9)), y}, Rgb(40, 40, 40), 1);
  }
  return ToImage(img);
}

Image8 MakeNoticeBoardTexture(RandomStream& rng, const std::string& text, int width_px,
                              int height_px) {
  cv::Mat noise = SmoothNoise(rng, std::max(width_px, height_px), 30);
  cv::Mat cork = Tinted(noise(cv::Rect(0, 0, width_px, height_px)), {170, 125, 80}, 0.12);
  Speckle(rng, cork, width_px * 2, 1, 0.4);
  cv::rectangle(cork, cv::Rect(0, 0, width_px, height_px), Rgb(90, 60, 35), 8);
  for (int k = 0; k < 5; ++k) {  // pinned notes; the first carries the number
    const int w = I(rng.Uniform(width_px * 0.18, width_px * 0.3));
    const int h = I(w * rng.Uniform(1.0, 1.4));
    const int top = I(rng.Uniform(12, height_px - h - 12));
    const int left = I(rng.Uniform(12, width_px - w - 12));
    const cv::Rect r(left, top, w, h);
    const cv::Vec3d note = Colour(rng, {230, 255}, {230, 255}, {180, 255});
    cv::rectangle(cork, r, Rgb(note[0], note[1], note[2]), cv::FILLED);
    if (k == 0) {
      CentredText(cork, text, r, cv::FONT_HERSHEY_SIMPLEX, Rgb(10, 10, 10), 0.7);
    } else {
      for (int line = 1; line < 6; ++line) {
        const int y = r.y + line * h / 6;
        cv::line(cork, {r.x + 4, y}, {r.x + w - 4, y}, Rgb(60, 60, 60), 1);
      }
    }
    cv::circle(cork, {r.x + w / 2, r.y + 5}, 3, Rgb(200, 20, 20), cv::FILLED);
  }
  return ToImage(cork);
}

Image8 MakeBookshelfTexture(RandomStream& rng, int width_px, int height_px) {
  cv::Mat img(height_px, width_px, CV_8UC3, Rgb(110, 75, 45));
  const int shelves = 5;
  const int shelf_h = height_px / shelves;
  for (int s = 0; s < shelves; ++s) {
    const int top = s * shelf_h + 6, bottom = (s + 1) * shelf_h - 4;
    int x = 6;
    while (x < width_px - 10) {
      const int w = static_cast<int>(rng.UniformInt(6, 16));
      const int h = I(rng.Uniform(0.6, 1.0) * (bottom - top));
      const cv::Vec3d spine = Colour(rng, {20, 230}, {20, 230}, {20, 230});
      cv::rectangle(img, cv::Rect(x, bottom - h, std::min(w, width_px - 6 - x), h),
                    Rgb(spine[0], spine[1], spine[2]), cv::FILLED);
      x += w + 1;
    }
    cv::rectangle(img, cv::Rect(0, (s + 1) * shelf_h - 4, width_px, 4), Rgb(80, 55, 30),
                  cv::FILLED);
  }
  cv::rectangle(img, cv::Rect(0, 0, width_px, height_px), Rgb(80, 55, 30), 6);
  return ToImage(img);
}

Image8 MakeCabinetTexture(RandomStream& rng, int width_px, int height_px) {
  const double grey = rng.Uniform(140, 200);
  cv::Mat img(height_px, width_px, CV_8UC3, Rgb(grey, grey, grey + 5));
  cv::line(img, {width_px / 2, 4}, {width_px / 2, height_px - 4},
           Rgb(grey * 0.5, grey * 0.5, grey * 0.5), 2);
  cv::rectangle(img, cv::Rect(0, 0, width_px, height_px), Rgb(grey * 0.6, grey * 0.6, grey * 0.6),
                3);
  for (const int x : {width_px / 2 - 14, width_px / 2 + 8}) {
    cv::rectangle(img, cv::Rect(x, height_px / 2 - 20, 6, 40), Rgb(50, 50, 50), cv::FILLED);
  }
  cv::rectangle(img, cv::Rect(width_px / 8, height_px / 8, width_px / 4, height_px / 12),
                Rgb(250, 250, 250), cv::FILLED);
  return ToImage(img);
}

Image8 MakeVentTexture(int size_px) {
  cv::Mat img(size_px, size_px, CV_8UC3, Rgb(200, 200, 200));
  for (int y = size_px / 8; y < size_px * 7 / 8; y += 6) {
    cv::line(img, {size_px / 8, y}, {size_px * 7 / 8, y}, Rgb(40, 40, 45), 2);
  }
  cv::rectangle(img, cv::Rect(0, 0, size_px, size_px), Rgb(150, 150, 150), 4);
  return ToImage(img);
}

}  // namespace corridorsim::worlds

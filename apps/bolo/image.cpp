#include "bolo/image.hpp"

#include <algorithm>
#include <cmath>

#include "bolo/errors.hpp"

namespace bolo::cli {

Colormap parse_colormap(const std::string& name) {
  if (name == "gray" || name == "grey") return Colormap::gray;
  if (name == "iron") return Colormap::iron;
  fail("--colormap ", name, ": unknown (use gray or iron)");
}

Rgb map_colour(Colormap map, double t) {
  if (!(t > 0)) t = 0;  // also NaN
  if (t > 1) t = 1;
  if (map == Colormap::gray) {
    const auto v = static_cast<std::uint8_t>(std::lround(t * 255.0));
    return {v, v, v};
  }
  // "Iron": black -> deep blue -> violet -> red -> orange -> yellow -> white.
  struct Stop {
    double t;
    double r, g, b;
  };
  static constexpr Stop stops[] = {
      {0.00, 0, 0, 0},     {0.12, 20, 0, 90},    {0.30, 110, 0, 150}, {0.50, 200, 30, 90},
      {0.68, 240, 100, 0}, {0.85, 255, 200, 30}, {1.00, 255, 255, 240},
  };
  std::size_t k = 1;
  while (k + 1 < std::size(stops) && t > stops[k].t) ++k;
  const Stop& a = stops[k - 1];
  const Stop& b = stops[k];
  const double u = (t - a.t) / (b.t - a.t);
  const auto mix = [u](double x, double y) {
    return static_cast<std::uint8_t>(std::lround(std::clamp(x + (y - x) * u, 0.0, 255.0)));
  };
  return {mix(a.r, b.r), mix(a.g, b.g), mix(a.b, b.b)};
}

DisplayRange percentile_range(std::vector<float>& values, double p_lo, double p_hi) {
  values.erase(std::remove_if(values.begin(), values.end(), [](float v) { return !std::isfinite(v); }),
               values.end());
  if (values.empty()) return {0.0, 1.0};
  std::sort(values.begin(), values.end());
  const auto at = [&values](double p) {
    const double pos = p / 100.0 * static_cast<double>(values.size() - 1);
    const auto i = static_cast<std::size_t>(std::floor(pos));
    const std::size_t j = std::min(i + 1, values.size() - 1);
    const double f = pos - static_cast<double>(i);
    return values[i] + (values[j] - values[i]) * f;
  };
  DisplayRange range{at(p_lo), at(p_hi)};
  if (!(range.hi > range.lo)) range.hi = range.lo + 1.0;  // a flat image: avoid dividing by 0
  return range;
}

Canvas::Canvas(std::uint32_t width, std::uint32_t height, Rgb background)
    : width_(width), height_(height), rgb_(std::size_t{width} * height * 3) {
  fill(0, 0, width, height, background);
}

void Canvas::set(std::uint32_t x, std::uint32_t y, Rgb colour) {
  if (x >= width_ || y >= height_) return;
  std::uint8_t* p = rgb_.data() + (std::size_t{y} * width_ + x) * 3;
  p[0] = colour[0];
  p[1] = colour[1];
  p[2] = colour[2];
}

void Canvas::fill(std::uint32_t x, std::uint32_t y, std::uint32_t w, std::uint32_t h, Rgb colour) {
  for (std::uint32_t yy = y; yy < y + h && yy < height_; ++yy)
    for (std::uint32_t xx = x; xx < x + w && xx < width_; ++xx) set(xx, yy, colour);
}

void Canvas::draw_frame(std::uint32_t x, std::uint32_t y, std::span<const float> frame,
                        std::uint32_t frame_w, std::uint32_t frame_h, DisplayRange range,
                        Colormap map, std::uint32_t scale) {
  const double span = range.hi - range.lo;
  for (std::uint32_t fy = 0; fy < frame_h; ++fy)
    for (std::uint32_t fx = 0; fx < frame_w; ++fx) {
      const double v = frame[std::size_t{fy} * frame_w + fx];
      fill(x + fx * scale, y + fy * scale, scale, scale, map_colour(map, (v - range.lo) / span));
    }
}

void Canvas::draw_number(std::uint32_t x, std::uint32_t y, const std::string& digits,
                         std::uint32_t dot) {
  // 3x5 glyphs, one row per 3 bits (MSB = left column).
  static constexpr std::uint8_t glyphs[10][5] = {
      {7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 3, 1, 7}, {5, 5, 7, 1, 1},
      {7, 4, 7, 1, 7}, {7, 4, 7, 5, 7}, {7, 1, 2, 2, 2}, {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7},
  };
  std::uint32_t n = 0;
  for (char c : digits) n += c >= '0' && c <= '9';
  if (n == 0) return;
  fill(x, y, (4 * n + 1) * dot, 7 * dot, {0, 0, 0});
  std::uint32_t cx = x + dot;
  for (char c : digits) {
    if (c < '0' || c > '9') continue;
    const auto& g = glyphs[c - '0'];
    for (std::uint32_t row = 0; row < 5; ++row)
      for (std::uint32_t col = 0; col < 3; ++col)
        if (g[row] & (4u >> col)) fill(cx + col * dot, y + dot + row * dot, dot, dot, {255, 255, 255});
    cx += 4 * dot;
  }
}

}  // namespace bolo::cli

#include "bolo/sim/demo_scene.hpp"

#include <cmath>

namespace bolo::sim {

void render_demo_scene(std::uint32_t width, std::uint32_t height, double t_s,
                       const DemoSceneOptions& o, std::span<float> out) {
  const double w = width, h = height;
  const double radius = 0.12 * std::min(w, h) + 1.0;
  // The disc wraps around horizontally so any length of recording keeps moving.
  const double span = w + 4 * radius;
  const double cx = std::fmod(o.speed_px_per_s * t_s, span) - 2 * radius;
  const double cy = 0.55 * h;
  for (std::uint32_t y = 0; y < height; ++y) {
    for (std::uint32_t x = 0; x < width; ++x) {
      double v = o.background + o.gradient * (x / w) + 200.0 * std::sin(6.28318 * y / h);
      if ((x / std::max(1u, width / 10)) % 3 == 1) v += o.bar_contrast;
      const double dx = x - cx, dy = y - cy;
      if (dx * dx + dy * dy <= radius * radius) v += o.hot_contrast;
      out[std::size_t{y} * width + x] = static_cast<float>(v);
    }
  }
}

}  // namespace bolo::sim

#include "bolo/odometry/pinhole_remap.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace bolo::odo {
namespace {

constexpr double kScaleStep = 1.01;
constexpr double kMaxScale = 2.0;

// Where the pinhole pixel (u, v) of focal lengths scale * (fx, fy) reads in the distorted image.
Eigen::Vector2d source_of(const sim::scene::Camera& c, double scale, double u, double v) {
  const Eigen::Vector2d d = c.distort({(u - c.cx) / (scale * c.fx), (v - c.cy) / (scale * c.fy)});
  return {c.fx * d.x() + c.cx, c.fy * d.y() + c.cy};
}

bool readable(const Eigen::Vector2d& s, std::uint32_t w, std::uint32_t h) {
  return s.x() >= 0.0 && s.y() >= 0.0 && s.x() <= w - 1.0 && s.y() <= h - 1.0;
}

// Keys' cubic convolution (a = -0.5): sharper than bilinear, which blurs what the VO tracks, at a
// 4 x 4 footprint.
float keys(float t) {
  t = std::fabs(t);
  if (t < 1) return (1.5f * t - 2.5f) * t * t + 1;
  if (t < 2) return ((-0.5f * t + 2.5f) * t - 4) * t + 2;
  return 0;
}

}  // namespace

PinholeRemap::PinholeRemap(const sim::scene::Camera& c) : width_(c.width), height_(c.height) {
  c.validate();
  if (c.width < 2 || c.height < 2) throw std::invalid_argument("the image must be at least 2 x 2 pixels");
  pinhole_.fx = static_cast<float>(c.fx), pinhole_.fy = static_cast<float>(c.fy);
  pinhole_.cx = static_cast<float>(c.cx), pinhole_.cy = static_cast<float>(c.cy);
  if (!c.distorted()) return;
  if (const char* why = sim::scene::distortion_problem(c)) throw std::invalid_argument(why);
  const std::uint32_t w = c.width, h = c.height;
  // The distortion is one-to-one over the image, so the output's border reaches farthest out.
  const auto border_inside = [&](double scale) {
    for (std::uint32_t x = 0; x < w; ++x)
      if (!readable(source_of(c, scale, x, 0), w, h) || !readable(source_of(c, scale, x, h - 1.0), w, h)) return false;
    for (std::uint32_t y = 0; y < h; ++y)
      if (!readable(source_of(c, scale, 0, y), w, h) || !readable(source_of(c, scale, w - 1.0, y), w, h)) return false;
    return true;
  };
  while (!border_inside(focal_scale_)) {
    focal_scale_ *= kScaleStep;
    if (focal_scale_ > kMaxScale)
      throw std::invalid_argument("the undistorted image would need focal lengths over " +
                                  std::to_string(kMaxScale) + "x the camera's to stay inside the frame");
  }
  pinhole_.fx = static_cast<float>(focal_scale_ * c.fx), pinhole_.fy = static_cast<float>(focal_scale_ * c.fy);
  taps_.resize(std::size_t{w} * h);
  for (std::uint32_t y = 0; y < h; ++y)
    for (std::uint32_t x = 0; x < w; ++x) {
      const Eigen::Vector2d s = source_of(c, focal_scale_, x, y);
      const double sx = std::clamp(s.x(), 0.0, w - 1.0), sy = std::clamp(s.y(), 0.0, h - 1.0);
      const auto x0 = static_cast<std::uint32_t>(sx), y0 = static_cast<std::uint32_t>(sy);
      Tap& t = taps_[std::size_t{y} * w + x];
      t.x0 = x0, t.y0 = y0;
      const auto fx = static_cast<float>(sx - x0), fy = static_cast<float>(sy - y0);
      for (int k = 0; k < 4; ++k) t.wx[k] = keys(fx - static_cast<float>(k - 1)), t.wy[k] = keys(fy - static_cast<float>(k - 1));
    }
}

void PinholeRemap::apply(std::span<const std::uint16_t> in, std::span<std::uint16_t> out) const {
  if (taps_.empty()) {
    std::copy(in.begin(), in.end(), out.begin());
    return;
  }
  const auto w = static_cast<std::int64_t>(width_), h = static_cast<std::int64_t>(height_);
  for (std::size_t i = 0; i < taps_.size(); ++i) {
    const Tap& t = taps_[i];
    float value = 0;
    for (int b = 0; b < 4; ++b) {
      const std::int64_t row = std::clamp<std::int64_t>(std::int64_t{t.y0} + b - 1, 0, h - 1) * w;
      for (int a = 0; a < 4; ++a) {
        const std::int64_t column = std::clamp<std::int64_t>(std::int64_t{t.x0} + a - 1, 0, w - 1);
        value += t.wx[a] * t.wy[b] * static_cast<float>(in[static_cast<std::size_t>(row + column)]);
      }
    }
    out[i] = static_cast<std::uint16_t>(std::clamp(std::lround(value), 0L, 65535L));
  }
}

}  // namespace bolo::odo

#pragma once
// Resamples the frames of a camera with lens distortion (camera.json's k1..k6, p1, p2) onto an
// undistorted pinhole, the only camera model the VO core takes. Each output pixel's ray is
// distorted into the source image and read there with Keys' cubic. The resampling is linear in the
// frame, so the two-frame carry-over model (raw_i = alpha raw_{i-1} + beta u) holds on the
// output as on the sensor's pixels, up to the rounding to whole counts.

#include <cstdint>
#include <span>
#include <vector>

#include "bolo/sim/scene/camera.hpp"
#include "bolo/vo/config.hpp"

namespace bolo::odo {

class PinholeRemap {
 public:
  // The pinhole keeps the camera's size and principal point; its focal lengths are the camera's
  // times the smallest factor >= 1 at which every output pixel reads inside the source image
  // (1 for barrel distortion, which only crops the periphery). Throws std::invalid_argument when
  // the distortion cannot be inverted over the image (sim::scene::distortion_problem) or the
  // factor would exceed 2.
  explicit PinholeRemap(const sim::scene::Camera& camera);

  bool identity() const { return taps_.empty(); }  // no distortion: frames pass unchanged
  const vo::Camera& pinhole() const { return pinhole_; }
  double focal_scale() const { return focal_scale_; }

  // in and out: width x height; out is rounded to the nearest count and clamped to 0..65535
  // (the cubic's overshoot at a step).
  void apply(std::span<const std::uint16_t> in, std::span<std::uint16_t> out) const;

 private:
  struct Tap {
    std::uint32_t x0, y0;  // the source pixel at or left of / above the position
    float wx[4], wy[4];    // Keys' cubic weights of columns x0-1..x0+2 and rows y0-1..y0+2
  };
  std::uint32_t width_ = 0, height_ = 0;
  vo::Camera pinhole_;
  double focal_scale_ = 1.0;
  std::vector<Tap> taps_;  // one per output pixel
};

}  // namespace bolo::odo

#pragma once
// The temporal pixel noise (noise_estimator.cpp).

#include <cstddef>
#include <cstdint>
#include <span>

#include "bolo/vo/config.hpp"

namespace bolo::vo {

struct CurrentFrame;

struct NoiseEstimate {
  double var = 0;  // temporal pixel noise, counts^2 (0 until measured)
  std::span<float> scratch;  // noise_block_count() floats
};

std::size_t noise_block_count(std::uint32_t width, std::uint32_t height);
// Updates noise.var from the current and the two previous raw frames of f.
void update_noise_variance(NoiseEstimate& noise, const CurrentFrame& f, const VoConfig& cfg);
// The current frame's own estimate (no averaging over frames); negative when it cannot be
// measured (too few flat blocks).
double frame_noise_variance(NoiseEstimate& noise, const CurrentFrame& f, const VoConfig& cfg);

}  // namespace bolo::vo

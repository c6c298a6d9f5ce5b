// Temporal pixel noise of the raw frames (ir modes), for the tau estimator's noise-bias correction.
//
// The carry-over fit regresses A on B, both differences of raw samples, so the pixel noise in B
// biases alpha low (errors in variables), and the bias is large once the poses and depths are
// eliminated (tau_estimator.cpp). Correcting it needs the noise variance, which the camera does
// not state, so it is measured here each frame:
//   * in the frame difference raw_i - raw_{i-1}, static scene and fixed pattern cancel;
//   * a 2x2 checkerboard of it, (a - b - c + d) / 2, cancels what is linear in space, and row
//     or column offsets that change between frames; for white noise its variance is 2 sigma^2;
//   * only on the flattest 30 % of 2x2 blocks, chosen on the frame before (raw_{i-2}) so that the
//     choice does not depend on the noise being measured: a moving texture passes for noise
//     (all blocks: sigma 3.4-3.9 for a true 3.0 on the street sequences; flat blocks: 3.0-3.2);
//   * a mean of squares clipped at 3 sigma (iterated), corrected for the clipping, rather than a
//     median: whole counts make the median of small differences jump in steps of half a count.
// The frame estimates are averaged with a forgetting factor of 0.95 (about 20 frames).

#include <algorithm>
#include <cmath>

#include "noise_estimator.hpp"

#include "frame_state.hpp"

namespace bolo::vo {
namespace {

constexpr float kFlatShare = 0.3f;            // share of blocks used, the flattest
constexpr double kClip = 3.0;                 // clipping, in sigmas
constexpr double kClippedVariance = 0.9733;   // E[x^2 | |x| < 3 sigma] / sigma^2 for a normal x
constexpr double kNoiseVarianceForget = 0.95;

float block_roughness(const float* q, std::size_t o, std::size_t w) {
  return std::fabs(q[o + 1] - q[o]) + std::fabs(q[o + w] - q[o]) + std::fabs(q[o + w + 1] - q[o + 1]) +
         std::fabs(q[o + w + 1] - q[o + w]);
}

}  // namespace

std::size_t noise_block_count(std::uint32_t width, std::uint32_t height) {
  return std::size_t{width / 2} * (height / 2);
}

double frame_noise_variance(NoiseEstimate& noise, const CurrentFrame& f, const VoConfig& cfg) {
  const std::uint32_t w = cfg.width, h = cfg.height;
  const std::size_t blocks = noise_block_count(w, h);
  if (blocks < 16 || noise.scratch.size() < blocks) return -1.0;
  float* scratch = noise.scratch.data();
  const float* before = f.raw_prev2.data();
  std::size_t b = 0;
  for (std::uint32_t y = 0; y + 1 < h; y += 2)
    for (std::uint32_t x = 0; x + 1 < w; x += 2) scratch[b++] = block_roughness(before, std::size_t{y} * w + x, w);
  const auto k = static_cast<std::size_t>(kFlatShare * static_cast<float>(blocks));
  std::nth_element(scratch, scratch + k, scratch + blocks);
  const float flat = scratch[k];
  // The chosen blocks' checkerboards overwrite the front of the scratch (at most one per block).
  std::size_t n = 0;
  for (std::uint32_t y = 0; y + 1 < h; y += 2)
    for (std::uint32_t x = 0; x + 1 < w; x += 2) {
      const std::size_t o = std::size_t{y} * w + x;
      if (block_roughness(before, o, w) > flat) continue;
      const auto d = [&](std::size_t i) { return f.raw[i] - f.raw_prev[i]; };
      scratch[n++] = 0.5f * (d(o) - d(o + 1) - d(o + w) + d(o + w + 1));
    }
  if (n < 16) return -1.0;
  double var = 0;
  for (std::size_t i = 0; i < n; ++i) var += double{scratch[i]} * scratch[i];
  var /= static_cast<double>(n);
  std::size_t kept_before = n + 1;
  for (int iteration = 0; iteration < 8 && var > 0; ++iteration) {
    const double limit = kClip * kClip * var;
    double sum = 0;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double c2 = double{scratch[i]} * scratch[i];
      if (c2 < limit) sum += c2, ++kept;
    }
    if (kept == 0) break;
    var = sum / static_cast<double>(kept) / kClippedVariance;
    // The limit only grows or shrinks the kept set: the same set again gives the same variance.
    if (kept == kept_before) break;
    kept_before = kept;
  }
  const double frame_var = 0.5 * var;  // the difference of two frames
  return std::isfinite(frame_var) ? frame_var : -1.0;
}

void update_noise_variance(NoiseEstimate& noise, const CurrentFrame& f, const VoConfig& cfg) {
  const double frame_var = frame_noise_variance(noise, f, cfg);
  if (!(frame_var >= 0)) return;
  noise.var = noise.var > 0
                    ? kNoiseVarianceForget * noise.var + (1 - kNoiseVarianceForget) * frame_var
                    : frame_var;
}

}  // namespace bolo::vo

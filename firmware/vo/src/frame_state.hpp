#pragma once
// The current frame and the two before it (odometry.cpp's load_frame() moves them along): raw
// counts, times, the carry-over chain and the tracking image.

#include <cstdint>
#include <span>

#include "bolo/vo/carry_model.hpp"
#include "bolo/vo/image.hpp"

namespace bolo::vo {

struct CurrentFrame {
  Pyramid frame;                    // tracking image of the current frame
  TexelImage frame_texels[8];       // the same, value and gradients interleaved (tracker, depth search)
  std::span<float> raw, raw_prev, raw_prev2;  // raw counts of this and the two previous frames
  bool have_prev = false;
  // The last frame repeated its predecessor bit for bit: the sensor frame that followed that
  // predecessor was never delivered, so the next frame has no known carry-over.
  bool predecessor_missing = false;
  bool chain_ok = false;       // raw_prev is this frame's predecessor on the sensor
  bool chain_ok_prev = false;  // raw_prev2 is raw_prev's predecessor
  double exposure_s = 0, readout_prev_s = 0, t_s = 0;
  double exposure_prev_s = 0;  // the previous frame's
  double readout_prev2_s = 0;  // the readout before the previous frame (its readout_prev_s)
  std::uint32_t frames_since_timing_change = 0xffffffffu;  // 0: this frame's timing changed
  CarryCoefficients carry;  // of the current frame
  double scene_scale = 1;  // the factor the current image used
};

}  // namespace bolo::vo

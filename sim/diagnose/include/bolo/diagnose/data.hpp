#pragma once
// What diagnosis works on: a recording held in memory as float, the baseline prediction next to
// it, which pixel-frames may be used, and how the frames are cut into held-out blocks.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace bolo::diag {

struct Frames {
  int n = 0, height = 0, width = 0;
  std::size_t pixels() const { return std::size_t(height) * width; }
  std::size_t size() const { return std::size_t(n) * pixels(); }
};

// A frame's coefficients in the baseline's recursion s_n = carry_n s_{n-1} + weight_n u_n; the
// first frame and flagged shutter frames start instead from a level L: restart_n L + weight_n u_n.
struct FrameSteps {
  std::vector<double> carry, weight, restart;
};

struct DiagnoseData {
  Frames shape;
  std::vector<float> recorded;  // frames.npy as float, N*P
  std::vector<float> input;     // scene.npy, or the static background estimate for every frame
  std::vector<float> baseline;  // the fitted baseline model's prediction, N*P
  // The same model run with the median timing in every frame, kept only when the frames' timing
  // differs: where it holds still the scene does (a change of exposure moves every pixel).
  std::vector<float> baseline_nominal;
  std::vector<std::uint8_t> valid;  // 1 where a pixel-frame may enter fits (not a moving object)
  // 1 where the reading is not clipped at the recording's extreme code: a clipped pixel-frame
  // says only "at least this much", so no fit may use it. valid never holds more than this.
  std::vector<std::uint8_t> unclipped;
  std::size_t clipped_count = 0;
  // Per frame, frames.csv's values where it has them (load.cpp fills the gaps and counts the
  // frames it filled in timing_filled).
  std::vector<double> t_s, exposure_s, readout_s;
  int timing_filled = 0;
  std::vector<std::uint8_t> flagged_event;  // frames.csv ffc == 1
  std::vector<std::optional<double>> fpa_temp_c;
  bool has_scene = false;
  // The input's frame-to-frame motion in whole pixels (scene_flow.hpp), N*P each; filled once
  // by the first baseline fit; empty without a scene.
  std::vector<std::int8_t> input_flow_dy, input_flow_dx;
  // What the pixel's weighting of its exposure adds to scene.npy's exposure average where the
  // input moves (exposure_motion.hpp), N*P; empty without a scene or without motion.
  std::vector<float> exposure_motion;
  // The standing baseline's frame steps, their derivatives with respect to ln tau (both time
  // constants together), and its term for motion within the exposure (recording units, N*P;
  // empty without one): what an effect acting on tau moves (two_frame_derivative.hpp).
  FrameSteps steps, steps_per_ln_tau;
  std::vector<float> within_exposure;
  double fps = 0;
  double tau_c_s = 0;    // the baseline's fitted cooling time constant (0: none)
  double tau_h_s = 0;    // the heating time constant fitted where the exposures differ (0: none yet)
  double gain = 1;       // the baseline's gain: recording units per input unit
  double level_mid = 0;  // a typical level of the baseline (for nonlinearity and tau_temperature)
  std::string units;
  std::string name;

  float* frame(std::vector<float>& v, int n) const { return v.data() + std::size_t(n) * shape.pixels(); }
  const float* frame(const std::vector<float>& v, int n) const {
    return v.data() + std::size_t(n) * shape.pixels();
  }
  // What "the baseline holds still at a pixel" is judged on: the baseline at the median timing.
  const std::vector<float>& still_reference() const { return baseline_nominal.empty() ? baseline : baseline_nominal; }
  const std::uint8_t* valid_frame(int n) const { return valid.data() + std::size_t(n) * shape.pixels(); }
  void reset_valid() { valid = unclipped.size() == shape.size() ? unclipped : std::vector<std::uint8_t>(shape.size(), 1); }
};

// Contiguous blocks of frames dealt to folds in turn, so every fold's held-out frames are spread
// over the whole recording while each held-out block is a whole run of frames.
struct Blocks {
  int count = 0, folds = 0;
  std::vector<int> block_of_frame;
  std::vector<int> fold_of_block;
  int fold_of_frame(int n) const { return fold_of_block[block_of_frame[n]]; }
};
Blocks make_blocks(int frames, int folds_wanted);
// The same blocks in two folds: the first half of the recording and the second.
Blocks halves(const Blocks& blocks);

}  // namespace bolo::diag

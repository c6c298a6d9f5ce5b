#pragma once
// The host simulator: a scene (any function giving steady-state counts at a time) seen through the
// continuous-time bolometer array, the selected catalogue effects, temporal noise and quantisation,
// one frame at a time, with everything known about it for truth/.

#include <cstdint>
#include <functional>
#include <memory>
#include <random>
#include <span>
#include <vector>

#include <nlohmann/json.hpp>

#include "bolo/recording/recording.hpp"
#include "bolo/sim/bolometer_array.hpp"
#include "bolo/sim/effect.hpp"

namespace bolo::sim {

// A camera that changes its exposure (integration) time while its frame period stays: every
// `every_frames` frames the exposure switches between SimulationInfo::exposure_s and
// `alternate_exposure_s`, and the readout takes up what the exposure gives up (their sum stays
// SimulationInfo's). every_frames 0: a constant timing.
struct ExposureSchedule {
  double alternate_exposure_s = 0.0;
  std::uint32_t every_frames = 0;
};

// How a pixel forms its reading over the frame period T.
enum class PixelLag {
  // Heats during the exposure t_e (the sub-steps spread over it) on top of what is left of the
  // previous reading, then only cools over the readout t_r. frames.csv's t_s is the exposure's
  // start; the truth pose is the exposure's middle.
  exposure_readout,
  // A first-order lag through the whole period: the pixel relaxes towards its moving input with
  // one tau (tau_h = tau_c), the sub-steps spread over the period, and is read at its end, which
  // is frames.csv's t_s and the truth pose's time. The same arithmetic as exposure_readout with
  // t_e = t_r = T (heating from zero and the decay of the previous reading, superposed), which is
  // what frames.csv records: the two-frame model's coefficients are then the lag's exactly.
  continuous,
};

struct SimulatorConfig {
  SimulationInfo info;           // size, bits, fps, exposure/readout, tau, 300 K level, seed
  PixelLag lag = PixelLag::exposure_readout;  // continuous: info's exposure and readout are 1/fps
  ExposureSchedule exposure_schedule;
  // Each frame's exposure and readout scaled by independent factors 1 + timing_jitter * z,
  // z ~ N(0, 1) cut at +-3 (a camera whose timing wanders), written exactly to frames.csv; the
  // frame interval takes up the change, so t_s follows. 0: the nominal timing.
  double timing_jitter = 0.0;
  std::uint32_t substeps = 4;    // scene samples per exposure (motion within a frame)
  double noise_counts = 2.0;     // white temporal noise, standard deviation in counts
  double noise_1f_counts = 0.0;  // 1/f temporal noise per pixel, standard deviation in counts
  std::vector<EffectSpec> effects;
};

// Writes the scene's steady-state counts at time t (row-major width * height).
using InputSampler = std::function<void(double t_s, std::span<float> counts)>;

struct SimulatedFrame {
  std::vector<std::uint16_t> counts;  // frames.npy
  std::vector<float> scene;           // scene.npy: the input averaged over the exposure
  rec::FrameRow row;                  // frames.csv
  double pose_t_s = 0.0;              // the instant the frame's truth pose stands for (PixelLag)
};

class Simulator {
 public:
  // Throws std::invalid_argument naming the option or effect that is wrong.
  Simulator(SimulatorConfig config, InputSampler input);
  void next(SimulatedFrame& frame);
  // Frame `index`'s exposure and the readout after it (the schedule and the jitter applied).
  struct Timing {
    double exposure_s, readout_s;
  };
  // Frame `index`'s exposure and readout; `jittered` false: the schedule's, without the jitter.
  Timing timing(std::uint64_t index, bool jittered = true) const;
  std::uint64_t frames_done() const { return index_; }
  const SimulatorConfig& config() const { return config_; }
  // truth/effects.json: the sensor model and every effect's parameters as used.
  nlohmann::json truth() const;
  std::vector<std::pair<std::string, std::vector<float>>> truth_maps() const;

 private:
  void sample_input(double t0, double exposure_s);

  SimulatorConfig config_;
  InputSampler input_;
  std::vector<std::unique_ptr<Effect>> effects_;
  BolometerArray array_;
  std::vector<float> pixel_input_;           // this frame's input per pixel, each row at its own time
  std::vector<double> row_delay_s_;          // how late each row's exposure starts
  std::vector<std::vector<float>> grid_;     // scene samples on the sub-step time grid
  std::vector<std::vector<float>> substeps_; // the per-row assembled input of each sub-step
  std::vector<double> reading_, previous_, tau_h_, tau_c_;
  std::vector<double> noise_state_;          // 1/f: octave AR(1) states per pixel
  std::mt19937_64 noise_rng_;
  std::uint64_t index_ = 0;
  double clock_s_ = 0.0;  // start of the next frame's exposure
};

}  // namespace bolo::sim

#include "bolo/sim/simulator.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace bolo::sim {
namespace {

constexpr int kNoiseOctaves = 4;

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

std::vector<std::unique_ptr<Effect>> build_effects(const SimulatorConfig& c) {
  std::vector<std::unique_ptr<Effect>> out;
  for (const EffectSpec& spec : c.effects) {
    for (const auto& e : out)
      require(spec.id != e->id(), "--effect " + spec.id + ": given twice");
    out.push_back(make_effect(spec, c.info));
  }
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a->order < b->order; });
  return out;
}

}  // namespace

Simulator::Simulator(SimulatorConfig config, InputSampler input)
    : config_(std::move(config)),
      input_(std::move(input)),
      effects_(build_effects(config_)),
      array_(std::max(1u, config_.info.width), std::max(1u, config_.info.height),
             config_.info.tau_h_s > 0 ? config_.info.tau_h_s : 1.0,
             config_.info.tau_c_s > 0 ? config_.info.tau_c_s : 1.0),
      noise_rng_(config_.info.seed) {
  const SimulationInfo& i = config_.info;
  require(i.width >= 2 && i.height >= 2, "size: at least 2x2");
  require(i.fps > 0 && std::isfinite(i.fps), "fps: must be > 0");
  require(i.tau_h_s > 0 && i.tau_c_s > 0, "tau: must be > 0");
  require(i.exposure_s > 0 && i.readout_s >= 0, "exposure must be > 0 and readout >= 0");
  if (config_.lag == PixelLag::continuous) {
    const double period = 1.0 / i.fps;
    require(std::fabs(i.exposure_s - period) <= 1e-9 * period && std::fabs(i.readout_s - period) <= 1e-9 * period,
            "continuous lag: exposure and readout must both be the frame period (1/fps)");
    require(i.tau_h_s == i.tau_c_s, "continuous lag: one time constant (tau_h = tau_c)");
    require(config_.exposure_schedule.every_frames == 0 && config_.timing_jitter == 0,
            "continuous lag: no exposure schedule or timing jitter (the period is the exposure)");
  } else {
    require(i.exposure_s + i.readout_s <= 1.0 / i.fps * (1 + 1e-9),
            "exposure + readout must fit in one frame period (1/fps)");
  }
  require(i.bits >= 8 && i.bits <= 16, "bits: 8..16");
  require(config_.substeps >= 1 && config_.substeps <= 64, "substeps: 1..64");
  require(config_.noise_counts >= 0 && config_.noise_1f_counts >= 0, "noise: must be >= 0");
  require(config_.timing_jitter >= 0 && config_.timing_jitter <= 0.1, "timing jitter: 0..0.1 (a relative spread)");
  const ExposureSchedule& schedule = config_.exposure_schedule;
  if (schedule.every_frames > 0)
    require(schedule.alternate_exposure_s > 0 && schedule.alternate_exposure_s <= i.exposure_s + i.readout_s,
            "alternate exposure: must be > 0 and fit exposure + readout");

  const std::size_t n = std::size_t{i.width} * i.height;
  row_delay_s_.assign(i.height, 0.0);
  for (const auto& e : effects_)
    for (std::uint32_t r = 0; r < i.height; ++r) row_delay_s_[r] += e->row_delay_s(r);
  // A late row reads between two grid samples: one more sample for the interpolation. The grid
  // is sized for the shortest exposure's sub-steps.
  const double shortest = schedule.every_frames > 0 ? std::min(i.exposure_s, schedule.alternate_exposure_s) : i.exposure_s;
  const double latest = *std::max_element(row_delay_s_.begin(), row_delay_s_.end()) / (shortest / config_.substeps);
  const auto grid = config_.substeps + static_cast<std::uint32_t>(std::ceil(latest)) + (latest > 0 ? 1u : 0u);
  grid_.assign(grid, std::vector<float>(n));
  substeps_.assign(config_.substeps, std::vector<float>(n));
  reading_.assign(n, 0.0);
  tau_h_.assign(n, i.tau_h_s);
  tau_c_.assign(n, i.tau_c_s);
  noise_state_.assign(n * kNoiseOctaves, 0.0);
}

Simulator::Timing Simulator::timing(std::uint64_t index, bool jittered) const {
  const SimulationInfo& i = config_.info;
  const ExposureSchedule& schedule = config_.exposure_schedule;
  Timing t{i.exposure_s, i.readout_s};
  if (schedule.every_frames > 0 && (index / schedule.every_frames) % 2 == 1)
    t = {schedule.alternate_exposure_s, i.readout_s + (i.exposure_s - schedule.alternate_exposure_s)};
  if (jittered && config_.timing_jitter > 0) {
    // Drawn from the frame's index alone (its own stream, not the noise's): any frame's timing
    // can be asked for in any order and adding jitter changes no other random draw.
    std::mt19937_64 rng(i.seed * 0x9E3779B97F4A7C15ull + index * 0xD1B54A32D192ED03ull + 0x7417);
    std::normal_distribution<double> normal(0.0, 1.0);
    const double ze = std::clamp(normal(rng), -3.0, 3.0), zr = std::clamp(normal(rng), -3.0, 3.0);
    t.exposure_s *= 1.0 + config_.timing_jitter * ze;
    t.readout_s *= 1.0 + config_.timing_jitter * zr;
  }
  return t;
}

void Simulator::sample_input(double t0, double exposure_s) {
  const SimulationInfo& i = config_.info;
  const double d = exposure_s / config_.substeps;
  for (std::size_t j = 0; j < grid_.size(); ++j) input_(t0 + (static_cast<double>(j) + 0.5) * d, grid_[j]);
  // Row r's k-th sub-step is the scene at grid position k + shift(r), linear between samples:
  // rows exposed later see later scenes, by any fraction of a sub-step.
  for (std::uint32_t k = 0; k < config_.substeps; ++k)
    for (std::uint32_t r = 0; r < i.height; ++r) {
      const double at = k + row_delay_s_[r] / d;
      const auto j = static_cast<std::size_t>(at);
      const auto w = static_cast<float>(at - static_cast<double>(j));
      const auto row = std::ptrdiff_t{r} * i.width;
      const float* a = grid_[j].data() + row;
      float* dst = substeps_[k].data() + row;
      if (w == 0.0f) {
        std::copy_n(a, i.width, dst);
      } else {
        const float* b = grid_[j + 1].data() + row;
        for (std::uint32_t c = 0; c < i.width; ++c) dst[c] = (1 - w) * a[c] + w * b[c];
      }
    }
}

void Simulator::next(SimulatedFrame& out) {
  const SimulationInfo& i = config_.info;
  const std::size_t n = reading_.size();
  FrameState f;
  f.index = index_;
  f.period_s = 1.0 / i.fps;
  const Timing timing_now = timing(index_);
  // The interval after this frame takes up its timing's departure from the nominal one.
  f.t_s = config_.timing_jitter > 0 ? clock_s_ : static_cast<double>(index_) * f.period_s;
  clock_s_ = f.t_s + f.period_s + (timing_now.exposure_s + timing_now.readout_s) - (i.exposure_s + i.readout_s);
  for (const auto& e : effects_) e->begin_frame(f);

  sample_input(f.t_s, timing_now.exposure_s);
  // scene.npy is the scene over the nominal exposure, every row at the same time: what a model
  // without a rolling readout assumes. The pixels' own input (mean_input) has each row's delay.
  out.scene.assign(n, 0.0f);
  pixel_input_.assign(n, 0.0f);
  for (std::uint32_t k = 0; k < config_.substeps; ++k)
    for (std::size_t p = 0; p < n; ++p) {
      out.scene[p] += grid_[k][p];
      pixel_input_[p] += substeps_[k][p];
    }
  for (float& v : out.scene) v /= static_cast<float>(config_.substeps);
  for (float& v : pixel_input_) v /= static_cast<float>(config_.substeps);
  f.mean_input = pixel_input_;

  // Time constants: per pixel only when an effect asks for it.
  std::fill(tau_h_.begin(), tau_h_.end(), i.tau_h_s);
  std::fill(tau_c_.begin(), tau_c_.end(), i.tau_c_s);
  for (const auto& e : effects_) e->time_constants(f, previous_, tau_h_, tau_c_);
  const bool per_pixel = std::any_of(tau_h_.begin(), tau_h_.end(), [&](double t) { return t != i.tau_h_s; }) ||
                         std::any_of(tau_c_.begin(), tau_c_.end(), [&](double t) { return t != i.tau_c_s; });
  if (per_pixel)
    array_.set_time_constants(tau_h_, tau_c_);
  else
    array_.set_time_constants({i.tau_h_s}, {i.tau_c_s});

  // The camera has been running before the first frame; a shutter event leaves the pixels
  // settled on the shutter, which sits at about the scene's mean level. Either at the nominal
  // timing (what the frames before ran at on average; they are not logged), carried over a
  // nominal readout into this frame's own exposure.
  if (index_ == 0 || f.shutter_event) {
    const Timing settled_at = timing(index_, false);
    if (index_ == 0) {
      array_.settle(pixel_input_, settled_at.exposure_s, settled_at.readout_s);
    } else {
      const double level = std::accumulate(out.scene.begin(), out.scene.end(), 0.0) / static_cast<double>(n);
      array_.settle(std::vector<float>(n, static_cast<float>(level)), settled_at.exposure_s, settled_at.readout_s);
    }
  }
  std::vector<std::span<const float>> steps(substeps_.begin(), substeps_.end());
  array_.expose(steps, timing_now.exposure_s, timing_now.readout_s, reading_);
  previous_ = reading_;

  for (const auto& e : effects_) e->on_reading(f, reading_);

  // Temporal noise: white, plus 1/f from AR(1) octaves whose corner frequencies are fps/4^k.
  std::normal_distribution<double> normal(0.0, 1.0);
  if (config_.noise_counts > 0 || config_.noise_1f_counts > 0) {
    for (std::size_t p = 0; p < n; ++p) {
      double noise = config_.noise_counts * normal(noise_rng_);
      if (config_.noise_1f_counts > 0) {
        for (int k = 0; k < kNoiseOctaves; ++k) {
          const double a = std::exp(-2.0 * 3.14159265358979 / std::pow(4.0, k + 1));
          double& s = noise_state_[p * kNoiseOctaves + static_cast<std::size_t>(k)];
          s = a * s + std::sqrt(1 - a * a) * normal(noise_rng_);
          noise += config_.noise_1f_counts / std::sqrt(double{kNoiseOctaves}) * s;
        }
      }
      reading_[p] += noise;
    }
  }
  for (const auto& e : effects_) e->on_output(f, reading_);

  const double full = std::ldexp(1.0, static_cast<int>(i.bits)) - 1.0;
  out.counts.resize(n);
  for (std::size_t p = 0; p < n; ++p)
    out.counts[p] = static_cast<std::uint16_t>(std::clamp(std::round(reading_[p]), 0.0, full));
  for (const auto& e : effects_) e->on_counts(f, out.counts);

  out.row = rec::FrameRow{};
  out.row.index = index_;
  // A continuous lag is read at the end of the period it relaxed over; that instant is the frame's
  // time and its pose's. The exposure_readout pose is the middle of the exposure.
  const bool lag = config_.lag == PixelLag::continuous;
  out.row.t_s = lag ? f.t_s + timing_now.exposure_s : f.t_s;
  out.pose_t_s = lag ? *out.row.t_s : f.t_s + 0.5 * timing_now.exposure_s;
  out.row.exposure_s = timing_now.exposure_s;
  out.row.readout_s = timing_now.readout_s;
  out.row.ffc = f.shutter_event && f.shutter_flagged;
  out.row.fpa_temp_c = f.fpa_temp_c;
  ++index_;
}

nlohmann::json Simulator::truth() const {
  const SimulationInfo& i = config_.info;
  nlohmann::json effects = nlohmann::json::object();
  for (const auto& e : effects_) effects[e->id()] = e->parameters();
  const bool lag = config_.lag == PixelLag::continuous;
  nlohmann::json baseline = {{"model", lag ? "continuous first-order lag through the frame period, read at its end "
                                             "(two-frame model with exposure = readout = the period)"
                                           : "continuous-time bolometer (two-frame model for frame-constant input)"},
                             {"lag", lag ? "continuous" : "exposure-readout"},
                             {"tau_h_s", i.tau_h_s}, {"tau_c_s", i.tau_c_s}, {"exposure_s", i.exposure_s},
                             {"readout_s", i.readout_s}, {"substeps", config_.substeps}, {"bits", i.bits},
                             {"reference_level", i.reference_level}, {"seed", i.seed}};
  if (config_.timing_jitter > 0) baseline["timing_jitter"] = config_.timing_jitter;
  if (config_.exposure_schedule.every_frames > 0)
    baseline["exposure_schedule"] = {{"alternate_exposure_s", config_.exposure_schedule.alternate_exposure_s},
                                     {"every_frames", config_.exposure_schedule.every_frames}};
  return {{"baseline", baseline},
          {"noise", {{"white_counts", config_.noise_counts}, {"one_over_f_counts", config_.noise_1f_counts}}},
          {"effects", effects}};
}

std::vector<std::pair<std::string, std::vector<float>>> Simulator::truth_maps() const {
  std::vector<std::pair<std::string, std::vector<float>>> out;
  for (const auto& e : effects_)
    for (auto& m : e->maps()) out.push_back(std::move(m));
  return out;
}

}  // namespace bolo::sim

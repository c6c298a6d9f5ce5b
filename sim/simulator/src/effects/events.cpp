// Slow and event-driven effects: shutter (FFC) events with offset steps, and focal-plane
// temperature drift that the last shutter event zeroes (a sawtooth between events).

#include <algorithm>
#include <cmath>

#include "effects.hpp"
#include "params.hpp"

namespace bolo::sim::effects {
namespace {

// At each event frame the global offset jumps by a random +-[step/2, step]; frames.csv flags the
// event when `flagged` is 1 (a concealed event when 0).
class FfcStep final : public Effect {
 public:
  FfcStep(const EffectSpec& spec, const SimulationInfo& info) : rng_(effect_rng(info.seed, id())) {
    Params p(spec);
    every_ = static_cast<std::uint64_t>(p.number("every", 0, 0, 1e9));
    for (double f : p.list("frames", 1, 1e12)) frames_.push_back(static_cast<std::uint64_t>(f));
    step_ = p.number("step", 20.0, 0.0, 1e4);
    flagged_ = p.number("flagged", 1, 0, 1) != 0;
    p.finish();
    if (every_ == 0 && frames_.empty())
      throw std::invalid_argument("--effect ffc_step: give every=N or frames=A/B/...");
    std::sort(frames_.begin(), frames_.end());
  }
  const char* id() const override { return "ffc_step"; }
  void begin_frame(FrameState& f) override {
    const bool event = (every_ != 0 && f.index > 0 && f.index % every_ == 0) ||
                       std::binary_search(frames_.begin(), frames_.end(), f.index);
    if (!event) return;
    f.shutter_event = true;
    f.shutter_flagged = flagged_;
    std::uniform_real_distribution<double> magnitude(0.5 * step_, step_);
    offset_ += (rng_() & 1 ? 1.0 : -1.0) * magnitude(rng_);
    events_.push_back(f.index);
  }
  void on_reading(const FrameState&, std::span<double> y) override {
    for (double& v : y) v += offset_;
  }
  nlohmann::json parameters() const override {
    return {{"every", every_}, {"frames", events_}, {"step", step_}, {"flagged", flagged_ ? 1 : 0}};
  }

 private:
  std::mt19937_64 rng_;
  std::uint64_t every_ = 0;
  std::vector<std::uint64_t> frames_, events_;
  double step_ = 0, offset_ = 0;
  bool flagged_ = true;
};

// T_fpa = t0 + rate * t (deg C, written to frames.csv); y += k (T_fpa - T at the last shutter event).
class FpaDrift final : public Effect {
 public:
  FpaDrift(const EffectSpec& spec, const SimulationInfo&) {
    Params p(spec);
    rate_ = p.number("rate", 0.02, -10.0, 10.0);
    k_ = p.number("k", 50.0, -1e4, 1e4);
    t0_ = p.number("t0_c", 30.0, -60.0, 120.0);
    p.finish();
  }
  const char* id() const override { return "fpa_drift"; }
  void begin_frame(FrameState& f) override {
    temp_ = t0_ + rate_ * f.t_s;
    if (!reference_ || f.shutter_event) reference_ = temp_;
    f.fpa_temp_c = temp_;
  }
  void on_reading(const FrameState&, std::span<double> y) override {
    const double offset = k_ * (temp_ - *reference_);
    for (double& v : y) v += offset;
  }
  nlohmann::json parameters() const override { return {{"rate", rate_}, {"k", k_}, {"t0_c", t0_}}; }

 private:
  double rate_, k_, t0_, temp_ = 0;
  std::optional<double> reference_;
};

}  // namespace

std::unique_ptr<Effect> make_ffc_step(const EffectSpec& s, const SimulationInfo& i) { return std::make_unique<FfcStep>(s, i); }
std::unique_ptr<Effect> make_fpa_drift(const EffectSpec& s, const SimulationInfo& i) { return std::make_unique<FpaDrift>(s, i); }

}  // namespace bolo::sim::effects

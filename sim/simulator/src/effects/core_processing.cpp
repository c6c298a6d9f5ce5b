// What the camera core does to its output: a recursive temporal filter, automatic gain control,
// defective pixels, and repeated frames.

#include <algorithm>
#include <cmath>

#include "effects.hpp"
#include "params.hpp"

namespace bolo::sim::effects {
namespace {

// y[n] = alpha y[n-1] + (1 - alpha) x[n], per frame.
class TemporalFilter final : public Effect {
 public:
  TemporalFilter(const EffectSpec& spec, const SimulationInfo&) {
    Params p(spec);
    alpha_ = p.number("alpha", 0.3, 0.0, 0.999);
    p.finish();
  }
  const char* id() const override { return "temporal_filter"; }
  void on_output(const FrameState&, std::span<double> y) override {
    if (previous_.size() != y.size()) {
      previous_.assign(y.begin(), y.end());
      return;
    }
    for (std::size_t p = 0; p < y.size(); ++p) {
      y[p] = alpha_ * previous_[p] + (1 - alpha_) * y[p];
      previous_[p] = y[p];
    }
  }
  nlohmann::json parameters() const override { return {{"alpha", alpha_}}; }

 private:
  double alpha_;
  std::vector<double> previous_;
};

// y = a_n u + b_n mapping the frame's percentiles p_lo..p_hi onto 10 %..90 % of the output range,
// with a and b following their targets at rate `damping` per frame.
class Agc final : public Effect {
 public:
  Agc(const EffectSpec& spec, const SimulationInfo& info)
      : full_(std::ldexp(1.0, static_cast<int>(info.bits)) - 1.0) {
    Params p(spec);
    damping_ = p.number("damping", 0.3, 0.0, 1.0);
    lo_ = p.number("p_lo", 1.0, 0.0, 50.0);
    hi_ = p.number("p_hi", 99.0, 50.0, 100.0);
    p.finish();
  }
  const char* id() const override { return "agc"; }
  void on_output(const FrameState&, std::span<double> y) override {
    sorted_.assign(y.begin(), y.end());
    auto pick = [&](double pct) {
      const auto k = static_cast<std::size_t>(pct / 100.0 * static_cast<double>(sorted_.size() - 1));
      std::nth_element(sorted_.begin(), sorted_.begin() + static_cast<std::ptrdiff_t>(k), sorted_.end());
      return sorted_[k];
    };
    const double lo = pick(lo_), hi = std::max(pick(hi_), lo + 1.0);
    const double a_target = 0.8 * full_ / (hi - lo);
    const double b_target = 0.1 * full_ - a_target * lo;
    if (!started_) {
      a_ = a_target;
      b_ = b_target;
      started_ = true;
    } else {
      a_ += damping_ * (a_target - a_);
      b_ += damping_ * (b_target - b_);
    }
    for (double& v : y) v = a_ * v + b_;
  }
  nlohmann::json parameters() const override {
    return {{"damping", damping_}, {"p_lo", lo_}, {"p_hi", hi_}};
  }

 private:
  double full_, damping_, lo_, hi_, a_ = 1, b_ = 0;
  bool started_ = false;
  std::vector<double> sorted_;
};

// `count` pixels stuck at 0 or at full scale (alternately), chosen by the seed.
class DeadPixels final : public Effect {
 public:
  DeadPixels(const EffectSpec& spec, const SimulationInfo& info)
      : full_(static_cast<std::uint16_t>((1u << info.bits) - 1)),
        mask_(std::size_t{info.width} * info.height, 0) {
    Params p(spec);
    const double max_count = static_cast<double>(mask_.size());
    count_ = static_cast<std::size_t>(p.number("count", 10, 0, max_count));
    p.finish();
    auto rng = effect_rng(info.seed, id());
    std::vector<std::uint32_t> order(mask_.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<std::uint32_t>(i);
    std::shuffle(order.begin(), order.end(), rng);
    for (std::size_t i = 0; i < count_; ++i) mask_[order[i]] = static_cast<std::uint8_t>(1 + i % 2);
  }
  const char* id() const override { return "dead_pixels"; }
  void on_counts(const FrameState&, std::span<std::uint16_t> counts) override {
    for (std::size_t p = 0; p < counts.size(); ++p)
      if (mask_[p]) counts[p] = mask_[p] == 1 ? 0 : full_;
  }
  nlohmann::json parameters() const override { return {{"count", count_}}; }
  std::vector<std::pair<std::string, std::vector<float>>> maps() const override {
    return {{"dead_pixels_mask", std::vector<float>(mask_.begin(), mask_.end())}};
  }

 private:
  std::uint16_t full_;
  std::vector<std::uint8_t> mask_;
  std::size_t count_ = 0;
};

// Every `every`-th frame repeats the previous one bit for bit.
class FrameDuplication final : public Effect {
 public:
  FrameDuplication(const EffectSpec& spec, const SimulationInfo&) {
    Params p(spec);
    every_ = static_cast<std::uint64_t>(p.number("every", 10, 2, 1e9));
    p.finish();
  }
  const char* id() const override { return "frame_duplication"; }
  void on_counts(const FrameState& f, std::span<std::uint16_t> counts) override {
    if (f.index % every_ == every_ - 1 && previous_.size() == counts.size()) {
      std::copy(previous_.begin(), previous_.end(), counts.begin());
      duplicated_.push_back(f.index);
    }
    previous_.assign(counts.begin(), counts.end());
  }
  nlohmann::json parameters() const override { return {{"every", every_}, {"frames", duplicated_}}; }

 private:
  std::uint64_t every_;
  std::vector<std::uint16_t> previous_;
  std::vector<std::uint64_t> duplicated_;
};

}  // namespace

std::unique_ptr<Effect> make_temporal_filter(const EffectSpec& s, const SimulationInfo& i) { return std::make_unique<TemporalFilter>(s, i); }
std::unique_ptr<Effect> make_agc(const EffectSpec& s, const SimulationInfo& i) { return std::make_unique<Agc>(s, i); }
std::unique_ptr<Effect> make_dead_pixels(const EffectSpec& s, const SimulationInfo& i) { return std::make_unique<DeadPixels>(s, i); }
std::unique_ptr<Effect> make_frame_duplication(const EffectSpec& s, const SimulationInfo& i) { return std::make_unique<FrameDuplication>(s, i); }

}  // namespace bolo::sim::effects

// agc: the core stretches each frame's range onto its output, y_n = a_n s + b_n, with a_n and b_n
// following targets set by the frame's own percentiles (p_lo, p_hi) at a per-frame damping.
// Its signature is that static pixels change when something changes elsewhere in the frame: the
// gain moves with the frame's range, not with the pixel's own input. The model predicts a_n and
// b_n from the baseline's image of every frame (held-out frames included, since the scene is
// known there too), so the only fitted quantities are the stretch's percentiles and damping and
// a global gain and offset: the evidence is whether the frame's content predicts the gain
// changes. The stretch enters at full strength: for a slow AGC a free strength would be
// degenerate with the damping (both only scale a slowly accumulating gain change).

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Dense>

#include "bolo/effects/stats.hpp"
#include "entries.hpp"
#include "params.hpp"

namespace bolo::effects {
namespace {

struct AgcSchema {
  static constexpr std::string_view id = "agc";
  static constexpr Param damping{"damping", "", 0.3, 0.0, 1.0};  // per frame
  static constexpr Param p_lo{"p_lo", "%", 1.0, 0.0, 50.0};
  static constexpr Param p_hi{"p_hi", "%", 99.0, 50.0, 100.0};
};

}  // namespace
}  // namespace bolo::effects

namespace bolo::sim {
namespace {

// y = a_n u + b_n mapping the frame's percentiles p_lo..p_hi onto 10 %..90 % of the output range,
// with a and b following their targets at rate `damping` per frame.
class AgcEffect final : public Effect {
  using S = effects::AgcSchema;

 public:
  AgcEffect(const EffectSpec& spec, const SimulationInfo& info)
      : full_(std::ldexp(1.0, static_cast<int>(info.bits)) - 1.0) {
    effects::Params p(spec);
    damping_ = p.number(S::damping);
    lo_ = p.number(S::p_lo);
    hi_ = p.number(S::p_hi);
    p.finish();
  }
  const char* id() const override { return S::id.data(); }
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
    return {{S::damping.name, damping_}, {S::p_lo.name, lo_}, {S::p_hi.name, hi_}};
  }

 private:
  double full_, damping_, lo_, hi_, a_ = 1, b_ = 0;
  bool started_ = false;
  std::vector<double> sorted_;
};

}  // namespace
}  // namespace bolo::sim

namespace bolo::diag {
namespace {

struct Stretch {
  double p_lo, p_hi;
};
constexpr Stretch kStretches[] = {{0, 100}, {0.5, 99.5}, {1, 99}, {2, 98}, {5, 95}};
// Dampings from 1 (the target at once) down to 3e-6 per frame, eight per decade: the fit is O(frames)
// per alternative, and a slow AGC's damping is only as good as this grid.
constexpr int kDampingCount = 45;
double damping_of(int i) { return std::pow(10.0, -i / 8.0); }
constexpr int kStretchCount = int(std::size(kStretches));
constexpr int kAlternatives = kStretchCount * kDampingCount;

// Per frame, over the valid pixels: what the 3x3 normal equations of [u s + v, s, 1] need.
struct FrameSums {
  double count = 0, s = 0, ss = 0, r = 0, rs = 0, rr = 0;
};

class AgcFit final : public FittedEffect {
 public:
  AgcFit(const DiagnoseData& d, std::vector<double> u, std::vector<double> v, Eigen::Vector3d beta,
         nlohmann::json params, std::string sim, Where where)
      : d_(d), u_(std::move(u)), v_(std::move(v)), beta_(beta), params_(std::move(params)),
        sim_(std::move(sim)), where_(std::move(where)) {}
  void predict(int n, std::span<float> out) const override {
    const float* s = d_.frame(d_.baseline, n);
    const double gain = u_[n] + beta_[0], offset = v_[n] + beta_[1] + beta_[2] * u_[n];
    for (std::size_t p = 0; p < out.size(); ++p) out[p] = static_cast<float>(gain * s[p] + offset);
  }
  nlohmann::json params() const override { return params_; }
  std::string simulator_effect() const override { return sim_; }
  Where where() const override { return where_; }

 private:
  const DiagnoseData& d_;
  std::vector<double> u_, v_;  // per frame: relative gain change and offset of the stretch
  Eigen::Vector3d beta_;  // global gain, offset, and the core's zero, beside the stretch
  nlohmann::json params_;
  std::string sim_;
  Where where_;
};

class AgcCandidate final : public Candidate {
  using S = effects::AgcSchema;

 public:
  const char* id() const override { return S::id.data(); }
  // Damping and the percentile pair (the global gain and offset are nuisance).
  int parameter_count() const override { return 2; }

  void prepare(const DiagnoseData& d, const std::vector<float>& r) override {
    data_ = &d;
    const int N = d.shape.n;
    const std::size_t P = d.shape.pixels();
    usable_ = d.has_scene && N >= 8;
    if (!usable_) return;
    sums_.assign(N, {});
    std::vector<double> lo(std::size_t(N) * kStretchCount), hi(lo.size());  // [frame][stretch]
    std::vector<float> sorted(P);
    for (int n = 0; n < N; ++n) {
      const float *s = d.frame(d.baseline, n), *res = d.frame(r, n);
      const std::uint8_t* valid = d.valid_frame(n);
      FrameSums& f = sums_[n];
      for (std::size_t p = 0; p < P; ++p) {
        if (!valid[p]) continue;
        f.count += 1;
        f.s += s[p];
        f.ss += double(s[p]) * s[p];
        f.r += res[p];
        f.rs += double(res[p]) * s[p];
        f.rr += double(res[p]) * res[p];
      }
      // The core sees the whole frame, moving objects included. Only the ten ranks are needed:
      // selection in ascending rank order, each on what lies above the previous rank.
      sorted.assign(s, s + P);
      std::array<std::size_t, 2 * kStretchCount> ranks{};
      for (int k = 0; k < kStretchCount; ++k) {
        ranks[2 * k] = rank_of(kStretches[k].p_lo, P);
        ranks[2 * k + 1] = rank_of(kStretches[k].p_hi, P);
      }
      std::array<std::size_t, 2 * kStretchCount> order = ranks;
      std::sort(order.begin(), order.end());
      std::size_t from = 0;  // everything below `from` is in place
      for (std::size_t rank : order) {
        if (rank < from) continue;  // a repeated rank
        std::nth_element(sorted.begin() + std::ptrdiff_t(from), sorted.begin() + std::ptrdiff_t(rank), sorted.end());
        from = rank + 1;
      }
      for (int k = 0; k < kStretchCount; ++k) {
        lo[std::size_t(n) * kStretchCount + k] = sorted[ranks[2 * k]];
        hi[std::size_t(n) * kStretchCount + k] = sorted[ranks[2 * k + 1]];
      }
    }
    // The stretches depend on the baseline only, not on which frames a fold trains on.
    stretches_.assign(kAlternatives, {});
    for (int alt = 0; alt < kAlternatives; ++alt) stretches_[alt] = stretch_of(alt, lo, hi);
  }

  std::unique_ptr<FittedEffect> fit(const std::vector<char>& train) const override {
    if (!usable_) return nullptr;
    const int N = data_->shape.n;
    int best = -1;
    double best_gain = 0;
    Eigen::Vector3d best_beta = Eigen::Vector3d::Zero();
    for (int alt = 0; alt < kAlternatives; ++alt) {
      const std::vector<double>&u = stretches_[alt].u, &v = stretches_[alt].v;
      if (u.empty()) continue;
      // r - (u s + v) regressed on [s, 1, u]: a global gain and offset, and where the core's zero
      // lies in the baseline's units (the stretch's offset moves with the gain about that zero).
      Eigen::Matrix3d xtx = Eigen::Matrix3d::Zero();
      Eigen::Vector3d xtq = Eigen::Vector3d::Zero();
      double before = 0, qq = 0;
      for (int n = 0; n < N; ++n) {
        if (!train[n]) continue;
        const FrameSums& f = sums_[n];
        const double a = u[n], b = v[n];
        const double qs = f.rs - a * f.ss - b * f.s, q1 = f.r - a * f.s - b * f.count;
        xtx(0, 0) += f.ss;
        xtx(0, 1) += f.s;
        xtx(0, 2) += a * f.s;
        xtx(1, 1) += f.count;
        xtx(1, 2) += a * f.count;
        xtx(2, 2) += a * a * f.count;
        xtq += Eigen::Vector3d(qs, q1, a * q1);
        before += f.rr;
        qq += f.rr - 2 * (a * f.rs + b * f.r) + a * a * f.ss + 2 * a * b * f.s + b * b * f.count;
      }
      xtx = xtx.selfadjointView<Eigen::Upper>();
      if (!(xtx(1, 1) > 0)) continue;
      xtx.diagonal().array() *= 1 + 1e-9;  // relative: the regressors' scales differ by 1e8
      const Eigen::Vector3d beta = xtx.ldlt().solve(xtq);
      const double gain = before - (qq - beta.dot(xtq));
      if (std::isfinite(gain) && gain > 0 && (best < 0 || gain > best_gain)) {
        best = alt;
        best_gain = gain;
        best_beta = beta;
      }
    }
    if (best < 0) return nullptr;
    const std::vector<double>& best_u = stretches_[best].u;
    const Stretch st = kStretches[best % kStretchCount];
    const double damping = damping_of(best / kStretchCount);
    // Where: the frames whose gain moves most from its typical value.
    double lo = 1e300, hi = -1e300;
    int from = 0, to = 0;
    for (int n = 0; n < N; ++n) {
      const double g = best_u[n];
      if (g < lo) { lo = g; from = n; }
      if (g > hi) { hi = g; to = n; }
    }
    Where where;
    where.frames = {{std::min(from, to), std::max(from, to)}};
    where.row1 = data_->shape.height - 1;
    where.col1 = data_->shape.width - 1;
    where.summary = "whole-frame gain and offset follow each frame's " + number(st.p_lo) + "-" + number(st.p_hi) +
                    " percentile range (gain varies by " + number(100 * (hi - lo)) + " % between frames " +
                    std::to_string(from) + " and " + std::to_string(to) + "): static pixels change when the rest of the frame does";
    nlohmann::json params = {{S::damping.name, damping},
                             {S::p_lo.name, st.p_lo},
                             {S::p_hi.name, st.p_hi},
                             {"gain_range", hi - lo}};
    const std::string sim =
        effects::SpecText(S::id).set(S::damping, number(damping)).set(S::p_lo, number(st.p_lo)).set(S::p_hi, number(st.p_hi)).str();
    return std::make_unique<AgcFit>(*data_, best_u, stretches_[best].v, best_beta, params, sim, where);
  }

  static std::size_t rank_of(double pct, std::size_t pixels) {
    return std::size_t(pct / 100.0 * double(pixels - 1) + 0.5);
  }

  void release() override {
    sums_.clear();
    stretches_.clear();
  }

 private:
  // The damped stretch of one alternative, as a gain change u_n (relative to the mean gain) and
  // an offset v_n (in the same units), so that the stretched frame is s + u_n s + v_n up to a
  // global gain and offset. Empty when the frames' range never changes.
  struct Stretched {
    std::vector<double> u, v;
  };
  Stretched stretch_of(int alt, const std::vector<double>& lo_of, const std::vector<double>& hi_of) const {
    const int N = data_->shape.n, k = alt % kStretchCount;
    const double damping = damping_of(alt / kStretchCount);
    std::vector<double> u(N), v(N);
    double a = 0, b = 0, mean_a = 0;
    for (int n = 0; n < N; ++n) {
      const double lo = lo_of[std::size_t(n) * kStretchCount + k], hi = hi_of[std::size_t(n) * kStretchCount + k];
      if (!(hi > lo)) return {};
      const double a_target = 1.0 / (hi - lo), b_target = -lo * a_target;
      if (n == 0) { a = a_target; b = b_target; }
      else { a += damping * (a_target - a); b += damping * (b_target - b); }
      u[n] = a;
      v[n] = b;
      mean_a += a;
    }
    mean_a /= N;
    double spread = 0;
    for (int n = 0; n < N; ++n) {
      u[n] = u[n] / mean_a - 1.0;
      v[n] /= mean_a;
      spread = std::max(spread, std::fabs(u[n]));
    }
    if (!(spread > 1e-6)) return {};
    return {std::move(u), std::move(v)};
  }

  const DiagnoseData* data_ = nullptr;
  bool usable_ = false;
  std::vector<FrameSums> sums_;
  std::vector<Stretched> stretches_;  // [alternative]
};

}  // namespace
}  // namespace bolo::diag

namespace bolo::effects {

EffectEntry agc() {
  using S = AgcSchema;
  return make_entry<sim::AgcEffect, diag::AgcCandidate>(S::id, {S::damping, S::p_lo, S::p_hi});
}

}  // namespace bolo::effects

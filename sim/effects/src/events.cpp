// Slow and event-driven effects that move the whole frame at once: ffc_step (shutter events with
// offset steps) and fpa_drift (focal-plane temperature drift that the last shutter event zeroes,
// a sawtooth between events). Diagnose's evidence for both is the per-frame mean residual.

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Dense>

#include "bolo/effects/stats.hpp"
#include "entries.hpp"
#include "params.hpp"

namespace bolo::effects {
namespace {

// Give `every` or `frames` (or both).
struct FfcStepSchema {
  static constexpr std::string_view id = "ffc_step";
  static constexpr Param every{"every", "frames", 0, 0, 1e9};  // 0: no periodic events
  static constexpr Param frames{"frames", "", kNoDefault, 1, 1e12, true};  // first frames after each event
  static constexpr Param step{"step", "counts", 20.0, 0.0, 1e4};
  static constexpr Param flagged{"flagged", "", 1, 0, 1};  // 1: frames.csv flags the event
};

struct FpaDriftSchema {
  static constexpr std::string_view id = "fpa_drift";
  static constexpr Param rate{"rate", "degC/s", 0.02, -10.0, 10.0};
  static constexpr Param k{"k", "counts/degC", 50.0, -1e4, 1e4};
  static constexpr Param t0_c{"t0_c", "degC", 30.0, -60.0, 120.0};
};

}  // namespace
}  // namespace bolo::effects

namespace bolo::sim {
namespace {

// At each event frame the global offset jumps by a random +-[step/2, step]; frames.csv flags the
// event when `flagged` is 1 (a concealed event when 0).
class FfcStepEffect final : public Effect {
  using S = effects::FfcStepSchema;

 public:
  FfcStepEffect(const EffectSpec& spec, const SimulationInfo& info) : rng_(effects::effect_rng(info.seed, id())) {
    effects::Params p(spec);
    every_ = static_cast<std::uint64_t>(p.number(S::every));
    for (double f : p.list(S::frames)) frames_.push_back(static_cast<std::uint64_t>(f));
    step_ = p.number(S::step);
    flagged_ = p.number(S::flagged) != 0;
    p.finish();
    if (every_ == 0 && frames_.empty())
      throw std::invalid_argument("--effect " + std::string(S::id) + ": give every=N or frames=A/B/...");
    std::sort(frames_.begin(), frames_.end());
  }
  const char* id() const override { return S::id.data(); }
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
    return {{S::every.name, every_}, {S::frames.name, events_}, {S::step.name, step_}, {S::flagged.name, flagged_ ? 1 : 0}};
  }

 private:
  std::mt19937_64 rng_;
  std::uint64_t every_ = 0;
  std::vector<std::uint64_t> frames_, events_;
  double step_ = 0, offset_ = 0;
  bool flagged_ = true;
};

// T_fpa = t0 + rate * t (deg C, written to frames.csv); y += k (T_fpa - T at the last shutter event).
class FpaDriftEffect final : public Effect {
  using S = effects::FpaDriftSchema;

 public:
  FpaDriftEffect(const EffectSpec& spec, const SimulationInfo&) {
    effects::Params p(spec);
    rate_ = p.number(S::rate);
    k_ = p.number(S::k);
    t0_ = p.number(S::t0_c);
    p.finish();
  }
  const char* id() const override { return S::id.data(); }
  void begin_frame(FrameState& f) override {
    temp_ = t0_ + rate_ * f.t_s;
    if (!reference_ || f.shutter_event) reference_ = temp_;
    f.fpa_temp_c = temp_;
  }
  void on_reading(const FrameState&, std::span<double> y) override {
    const double offset = k_ * (temp_ - *reference_);
    for (double& v : y) v += offset;
  }
  nlohmann::json parameters() const override { return {{S::rate.name, rate_}, {S::k.name, k_}, {S::t0_c.name, t0_}}; }

 private:
  double rate_, k_, t0_, temp_ = 0;
  std::optional<double> reference_;
};

}  // namespace
}  // namespace bolo::sim

namespace bolo::diag {
namespace {

struct FrameMeans {
  std::vector<double> sum, count;
};

FrameMeans frame_means(const DiagnoseData& d, const std::vector<float>& r) {
  FrameMeans m;
  const std::size_t P = d.shape.pixels();
  m.sum.assign(d.shape.n, 0.0);
  m.count.assign(d.shape.n, 0.0);
  for (int n = 0; n < d.shape.n; ++n) {
    const float* f = d.frame(r, n);
    const std::uint8_t* v = d.valid_frame(n);
    for (std::size_t p = 0; p < P; ++p)
      if (v[p]) { m.sum[n] += f[p]; m.count[n] += 1; }
  }
  return m;
}

class FrameOffsetFit final : public FittedEffect {
 public:
  FrameOffsetFit(std::vector<double> offset, nlohmann::json params, std::string sim, Where where)
      : offset_(std::move(offset)), params_(std::move(params)), sim_(std::move(sim)), where_(std::move(where)) {}
  void predict(int n, std::span<float> out) const override {
    std::fill(out.begin(), out.end(), static_cast<float>(offset_[n]));
    for (const auto& [frame, image] : transients_)
      if (frame == n)
        for (std::size_t p = 0; p < out.size(); ++p) out[p] += image[p];
  }
  nlohmann::json params() const override { return params_; }
  std::string simulator_effect() const override { return sim_; }
  Where where() const override { return where_; }
  std::vector<std::pair<int, std::vector<float>>> transients_;  // per-pixel extra at single frames

 private:
  std::vector<double> offset_;
  nlohmann::json params_;
  std::string sim_;
  Where where_;
};

// Weighted least squares of frame means on per-frame regressors X (N x k), train frames only.
Eigen::VectorXd fit_frames(const FrameMeans& m, const Eigen::MatrixXd& X, const std::vector<char>& train) {
  const int k = static_cast<int>(X.cols());
  Eigen::MatrixXd xtx = Eigen::MatrixXd::Zero(k, k);
  Eigen::VectorXd xtr = Eigen::VectorXd::Zero(k);
  for (int n = 0; n < X.rows(); ++n) {
    if (!train[n] || m.count[n] == 0) continue;
    xtx += m.count[n] * X.row(n).transpose() * X.row(n);
    xtr += X.row(n).transpose() * m.sum[n];
  }
  xtx.diagonal().array() += 1e-9 * (xtx.trace() + 1e-12);
  return xtx.ldlt().solve(xtr);
}

// Offset jumps at shutter events, and the shift that settles in after one (a core's per-frame
// filter, or its re-settling after the flat-field correction; a long settle is a drift restarting
// at the event). Events are the flagged frames and frames whose mean residual leaves the line the
// frames before it follow by far more than the frame-to-frame scatter: found with or without
// frames.csv's flag, with or without a time gap at the event.
class FfcStepCandidate final : public Candidate {
  using S = effects::FfcStepSchema;

 public:
  const char* id() const override { return S::id.data(); }
  int parameter_count() const override {
    const int settling = int(std::count(settles_after_.begin(), settles_after_.end(), 1));
    return std::max<int>(1, int(events_.size())) + (settling > 0 ? settling + 1 : 0);
  }
  void prepare(const DiagnoseData& d, const std::vector<float>& r) override {
    data_ = &d;
    residual_ = &r;
    means_ = frame_means(d, r);
    events_ = find_events(d, means_);
    settles_after_.assign(events_.size(), 0);
    settle_frames_ = 0;
    if (events_.empty()) return;
    // An event's settling step is part of the model when it pays for its parameter on the frame
    // means of the whole recording (BIC on their residual sum of squares); the held-out scoring
    // then judges the whole model. One at a time, the strongest first.
    const std::vector<char> all(d.shape.n, 1);
    const double log_n = std::log(double(d.shape.n));
    double sse = mean_sse(offsets(all, nullptr));
    for (std::size_t round = 0; round < events_.size(); ++round) {
      int best = -1;
      double best_sse = sse;
      for (std::size_t e = 0; e < events_.size(); ++e) {
        if (settles_after_[e]) continue;
        settles_after_[e] = 1;
        const double with = mean_sse(offsets(all, nullptr));
        settles_after_[e] = 0;
        if (with < best_sse) { best_sse = with; best = int(e); }
      }
      if (best < 0 || !(double(d.shape.n) * std::log(sse / std::max(1e-300, best_sse)) > log_n + 10)) break;
      settles_after_[best] = 1;
      sse = best_sse;
    }
    // The settle is the shape of the shift, chosen here on all frames as the events are: a fold
    // whose training frames hold only the start of a settling cannot tell a curve from a line.
    settle_frames_ = 0;
    if (std::find(settles_after_.begin(), settles_after_.end(), 1) != settles_after_.end()) offsets(all, &settle_frames_);
    // A shift that does not settle but goes on as a line until the next event is a drift
    // between shutter events: fpa_drift's, not this effect's.
    if (settle_frames_ >= kLinearSettle) {
      std::fill(settles_after_.begin(), settles_after_.end(), 0);
      settle_frames_ = 0;
    }
  }
  std::unique_ptr<FittedEffect> fit(const std::vector<char>& train) const override {
    if (events_.empty()) return nullptr;
    const int k = int(events_.size());
    double settle_frames = 0;
    Eigen::VectorXd beta;
    std::vector<double> offset = offsets(train, &settle_frames, &beta);
    nlohmann::json steps = nlohmann::json::array(), settling = nlohmann::json::array();
    std::string frames;
    double biggest = 0;
    Where where;
    for (int e = 0; e < k; ++e) {
      steps.push_back(beta[e + 1]);
      settling.push_back(beta[k + 1 + e]);
      frames += (e ? "/" : "") + std::to_string(events_[e]);
      biggest = std::max(biggest, std::fabs(beta[e + 1]));
      where.frames.push_back({events_[e], events_[e]});
    }
    where.row1 = data_->shape.height - 1;
    where.col1 = data_->shape.width - 1;
    int flagged = 0;
    for (int e : events_) flagged += data_->flagged_event[e];
    std::string settling_after;
    for (int e = 0; e < k; ++e)
      if (settles_after_[e]) settling_after += (settling_after.empty() ? "" : "/") + std::to_string(events_[e]);
    where.summary = "global offset steps at frames " + frames + " (" + std::to_string(flagged) + " of " +
                    std::to_string(k) + " flagged in frames.csv)" +
                    (settling_after.empty() ? "" : "; after " + settling_after + " the offset goes on moving, settling over ~" +
                                                 number(settle_frames) + " frames");
    nlohmann::json params = {{S::frames.name, events_}, {"steps", steps}, {S::flagged.name, flagged}};
    if (!settling_after.empty()) {
      params["settling_steps"] = settling;  // per event; 0 where none follows
      params["settle_frames"] = settle_frames;
    }
    const std::string sim =
        effects::SpecText(S::id).set(S::frames, frames).set(S::step, number(biggest)).set(S::flagged, flagged == k ? "1" : "0").str();
    auto fitted = std::make_unique<FrameOffsetFit>(std::move(offset), params, sim, where);
    // An unflagged event also closed the shutter: the first frame after it carries the shutter
    // (taken at the scene's mean level, as for flagged events in the baseline) instead of the
    // previous frame. No free parameter: the carry fraction is the baseline's.
    const DiagnoseData& d = *data_;
    if (d.has_scene && d.tau_c_s > 0) {
      const std::size_t P = d.shape.pixels();
      for (int e : events_) {
        if (d.flagged_event[e] || e < 1) continue;
        const double c = std::exp(-d.readout_s[e - 1] / d.tau_c_s);
        const float *u = d.frame(d.input, e), *bp = d.frame(d.baseline, e - 1);
        double mean = 0;
        for (std::size_t p = 0; p < P; ++p) mean += u[p];
        mean /= double(P);
        std::vector<float> image(P);
        for (std::size_t p = 0; p < P; ++p) image[p] = static_cast<float>(c * (mean - bp[p]));
        // Only where the frame shows it (a jump without a shutter closing is possible too).
        const float* r = d.frame(*residual_, e);
        double with = 0, without = 0;
        for (std::size_t p = 0; p < P; ++p) {
          without += double(r[p]) * r[p];
          with += double(r[p] - image[p]) * (r[p] - image[p]);
        }
        if (with >= without) continue;
        // ... and each later frame carries a share c of the previous one's difference.
        for (int n = e; n < d.shape.n; ++n) {
          fitted->transients_.push_back({n, image});
          if (std::pow(c, n - e + 1) < 1e-4) break;
          for (float& v : image) v *= static_cast<float>(c);
        }
      }
    }
    return fitted;
  }

 private:
  // Per frame: a constant, a step at each event, and for the events in settles_after_ a second step
  // that settles in over the frames after it, 1 - a^(n - e + 1) with a = exp(-1 / settle): a
  // shift seen through a core's per-frame filter, or re-settling after the correction; a long
  // settle is a straight line. The settle is settle_frames_ or else the best of a grid. Fitted on
  // the training frames' means. Where the first three settles after an event hold fewer than 3
  // training frames, the immediate step cannot be told from the settling one: that fold fits the
  // settling step alone (the shift starts from the level before the event).
  std::vector<double> offsets(const std::vector<char>& train, double* settle_frames, Eigen::VectorXd* coefficients = nullptr) const {
    const DiagnoseData& d = *data_;
    const int N = d.shape.n, k = int(events_.size());
    const bool any_settling = std::find(settles_after_.begin(), settles_after_.end(), 1) != settles_after_.end();
    std::vector<double> best;
    double best_sse = std::numeric_limits<double>::infinity();
    const std::vector<double> settles = !any_settling ? std::vector<double>{0}
                                        : settle_frames_ > 0 ? std::vector<double>{settle_frames_}
                                                             : std::vector<double>{1, 2, 4, 8, 16, 32, 64, kLinearSettle};
    for (double settle : settles) {
      std::vector<char> step(k, 1);
      for (int e = 0; e < k && any_settling; ++e) {
        if (!settles_after_[e]) continue;
        int seen = 0;
        for (int n = events_[e]; n < N && n - events_[e] < 3 * settle && (e + 1 == k || n < events_[e + 1]); ++n)
          seen += train[n] && means_.count[n] > 0;
        step[e] = seen >= 3;
      }
      Eigen::MatrixXd X = Eigen::MatrixXd::Zero(N, 1 + 2 * k);
      const double a = any_settling ? std::exp(-1.0 / settle) : 0.0;
      const double full = 1 - std::pow(a, N);  // scales a long settle's line to reach 1 in N frames
      for (int n = 0; n < N; ++n) {
        X(n, 0) = 1.0;
        for (int e = 0; e < k; ++e) {
          if (n < events_[e]) continue;
          if (step[e]) X(n, e + 1) = 1.0;
          if (settles_after_[e]) X(n, 1 + k + e) = (1 - std::pow(a, n - events_[e] + 1)) / full;
        }
      }
      const Eigen::VectorXd beta = fit_frames(means_, X, train);
      std::vector<double> offset(N);
      double sse = 0;
      for (int n = 0; n < N; ++n) {
        offset[n] = X.row(n).dot(beta);
        if (train[n] && means_.count[n] > 0) {
          const double e = means_.sum[n] / means_.count[n] - offset[n];
          sse += means_.count[n] * e * e;
        }
      }
      if (sse < best_sse) {
        best_sse = sse;
        best = std::move(offset);
        if (settle_frames) *settle_frames = settle;
        if (coefficients) *coefficients = beta;
      }
    }
    return best;
  }
  double mean_sse(const std::vector<double>& offset) const {
    double sse = 0;
    for (std::size_t n = 0; n < offset.size(); ++n) {
      if (means_.count[n] == 0) continue;
      const double e = means_.sum[n] / means_.count[n] - offset[n];
      sse += e * e;
    }
    return sse;
  }
  // Flagged frames, and jumps: a frame whose mean leaves the line fitted to the (up to 8) frames
  // before it by more than 8 times the frame-to-frame scatter of the means and 8 times that
  // line's own scatter (so the frames of a drift that follows an event do not count again).
  static std::vector<int> find_events(const DiagnoseData& d, const FrameMeans& m) {
    const int N = d.shape.n;
    std::vector<double> mean(N), abs_diff;
    for (int n = 0; n < N; ++n) mean[n] = m.count[n] > 0 ? m.sum[n] / m.count[n] : 0.0;
    for (int n = 1; n < N; ++n) abs_diff.push_back(std::fabs(mean[n] - mean[n - 1]));
    const double scatter = 1.4826 * median_of(abs_diff);
    constexpr int kWindow = 8;
    std::vector<int> events;
    int last = -1000;
    for (int n = 1; n < N; ++n) {
      bool event = d.flagged_event[n];
      // A jump needs a line before it: in the first frames a start-up transient (a slow path
      // starting cold) cannot be told from an event.
      if (!event && n >= 3) {
        double jump = mean[n] - mean[n - 1], line_scatter = 0;
        const int first = std::max({0, n - kWindow, last});
        if (n - first >= 3) {
          // Least-squares line over time through frames first..n-1, extrapolated to frame n.
          double st = 0, sm = 0, stt = 0, stm = 0, c = 0;
          for (int j = first; j < n; ++j) {
            const double t = d.t_s[j] - d.t_s[n];
            st += t; sm += mean[j]; stt += t * t; stm += t * mean[j]; c += 1;
          }
          const double den = stt - st * st / c;
          const double slope = den > 0 ? (stm - st * sm / c) / den : 0.0, at_n = sm / c - slope * st / c;
          // The drift a line allows stops at the time of one typical frame: across a time gap
          // (the camera busy with its shutter) the line is not carried further.
          const double gap = d.t_s[n] - d.t_s[n - 1], typical = 1.0 / d.fps;
          const double extrapolated = at_n - slope * std::max(0.0, gap - typical);
          jump = mean[n] - extrapolated;
          double ss = 0;
          for (int j = first; j < n; ++j) {
            const double e = mean[j] - (at_n + slope * (d.t_s[j] - d.t_s[n]));
            ss += e * e;
          }
          line_scatter = c > 2 ? std::sqrt(ss / (c - 2)) : 0.0;
        }
        event = std::fabs(jump) > 8 * scatter + 1e-9 && std::fabs(jump) > 8 * line_scatter;
      }
      // Neighbouring detections are one event (a transient spreads a jump over two frames).
      if (event && n - last > 5) {
        events.push_back(n);
        last = n;
      } else if (event && d.flagged_event[n] && !events.empty() && !d.flagged_event[events.back()]) {
        events.back() = n;  // a flag names the event's frame better than a jump before it
        last = n;
      }
    }
    if (events.size() > 12) events.resize(12);
    return events;
  }

  const DiagnoseData* data_ = nullptr;
  const std::vector<float>* residual_ = nullptr;
  FrameMeans means_;
  std::vector<int> events_;
  static constexpr double kLinearSettle = 1e6;  // frames: a settle this long is a straight line
  std::vector<char> settles_after_;  // per event: a settling step follows it
  double settle_frames_ = 0;  // frames over which the settling steps come in (0: not chosen yet)
};

// y += k (T_fpa - T at the last shutter event); without FPA temperatures, a slow drift since
// the last event (time as the regressor).
class FpaDriftCandidate final : public Candidate {
  using S = effects::FpaDriftSchema;

 public:
  const char* id() const override { return S::id.data(); }
  int parameter_count() const override { return 1; }
  void prepare(const DiagnoseData& d, const std::vector<float>& r) override {
    data_ = &d;
    means_ = frame_means(d, r);
    const int N = d.shape.n;
    has_temp_ = true;
    for (const auto& t : d.fpa_temp_c) has_temp_ = has_temp_ && t.has_value();
    x_.assign(N, 0.0);
    double reference = has_temp_ ? *d.fpa_temp_c[0] : d.t_s[0];
    for (int n = 0; n < N; ++n) {
      const double v = has_temp_ ? *d.fpa_temp_c[n] : d.t_s[n];
      if (d.flagged_event[n]) reference = v;
      x_[n] = v - reference;
    }
    // Temperature slope over time, for the simulator's `rate`.
    rate_ = 0;
    if (has_temp_ && N > 1) {
      double st = 0, sv = 0, stt = 0, stv = 0;
      for (int n = 0; n < N; ++n) { st += d.t_s[n]; sv += *d.fpa_temp_c[n]; stt += d.t_s[n] * d.t_s[n]; stv += d.t_s[n] * *d.fpa_temp_c[n]; }
      const double den = stt - st * st / N;
      rate_ = den > 0 ? (stv - st * sv / N) / den : 0.0;
    }
  }
  std::unique_ptr<FittedEffect> fit(const std::vector<char>& train) const override {
    const int N = data_->shape.n;
    const double lo = *std::min_element(x_.begin(), x_.end()), hi = *std::max_element(x_.begin(), x_.end());
    if (!(hi - lo > 1e-9)) return nullptr;
    Eigen::MatrixXd X(N, 2);
    for (int n = 0; n < N; ++n) { X(n, 0) = 1.0; X(n, 1) = x_[n]; }
    const Eigen::VectorXd beta = fit_frames(means_, X, train);
    std::vector<double> offset(N);
    for (int n = 0; n < N; ++n) offset[n] = beta[0] + beta[1] * x_[n];
    Where where;
    where.frames = {{0, N - 1}};
    where.row1 = data_->shape.height - 1;
    where.col1 = data_->shape.width - 1;
    nlohmann::json params;
    std::string sim;
    if (has_temp_) {
      where.summary = "global offset tracking the FPA temperature (frames.csv fpa_temp_c) since the last shutter event";
      params = {{S::k.name, beta[1]}, {S::rate.name, rate_}, {"regressor", "fpa_temp_c"}};
      sim = effects::SpecText(S::id)
                .set(S::rate, number(rate_))
                .set(S::k, number(beta[1]))
                .set(S::t0_c, number(*data_->fpa_temp_c[0]))
                .str();
    } else {
      where.summary = "slow global drift with time since the last shutter event (no FPA temperature in frames.csv)";
      params = {{"rate_counts_per_s", beta[1]}, {"regressor", "time since last event"}};
      // The simulator's drift is k * rate * t: any split of the product reproduces it.
      sim = effects::SpecText(S::id).set(S::rate, number(S::rate.fallback)).set(S::k, number(beta[1] / S::rate.fallback)).str();
    }
    return std::make_unique<FrameOffsetFit>(std::move(offset), params, sim, where);
  }

 private:
  const DiagnoseData* data_ = nullptr;
  FrameMeans means_;
  std::vector<double> x_;
  bool has_temp_ = false;
  double rate_ = 0;
};

}  // namespace
}  // namespace bolo::diag

namespace bolo::effects {

EffectEntry ffc_step() {
  using S = FfcStepSchema;
  return make_entry<sim::FfcStepEffect, diag::FfcStepCandidate>(S::id, {S::every, S::frames, S::step, S::flagged});
}

EffectEntry fpa_drift() {
  using S = FpaDriftSchema;
  return make_entry<sim::FpaDriftEffect, diag::FpaDriftCandidate>(S::id, {S::rate, S::k, S::t0_c});
}

}  // namespace bolo::effects

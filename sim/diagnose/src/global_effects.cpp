// Effects that move the whole frame at once: ffc_step (offset jumps at shutter events),
// fpa_drift (offset tracking the focal-plane temperature, or time since the last event), and
// frame_duplication (frames repeated bit for bit). Their evidence is the per-frame mean residual.

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <sstream>

#include <Eigen/Dense>

#include "dynamic_effects.hpp"
#include "stats.hpp"

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
class FfcStep final : public Candidate {
 public:
  const char* id() const override { return "ffc_step"; }
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
    nlohmann::json params = {{"frames", events_}, {"steps", steps}, {"flagged", flagged}};
    if (!settling_after.empty()) {
      params["settling_steps"] = settling;  // per event; 0 where none follows
      params["settle_frames"] = settle_frames;
    }
    const std::string sim = "ffc_step:frames=" + frames + ",step=" + number(biggest) +
                            ",flagged=" + (flagged == k ? "1" : "0");
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
class FpaDrift final : public Candidate {
 public:
  const char* id() const override { return "fpa_drift"; }
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
      params = {{"k", beta[1]}, {"rate", rate_}, {"regressor", "fpa_temp_c"}};
      sim = "fpa_drift:rate=" + number(rate_) + ",k=" + number(beta[1]) + ",t0_c=" + number(*data_->fpa_temp_c[0]);
    } else {
      where.summary = "slow global drift with time since the last shutter event (no FPA temperature in frames.csv)";
      params = {{"rate_counts_per_s", beta[1]}, {"regressor", "time since last event"}};
      // The simulator's drift is k * rate * t: any split of the product reproduces it.
      sim = "fpa_drift:rate=0.02,k=" + number(beta[1] / 0.02);
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

// Frames that repeat their predecessor bit for bit. The fit learns the period and phase from
// the training frames; held out, the repeats it predicts must be there.
class DuplicateFit final : public FittedEffect {
 public:
  DuplicateFit(const DiagnoseData& d, const std::vector<float>& r, int period, int phase, std::vector<int> repeats)
      : d_(d), r_(r), period_(period), phase_(phase), repeats_(std::move(repeats)) {}
  // The period where the training blocks show one; and every frame the bit-identity test flags,
  // held-out ones included: that test is a fixed rule read off each frame (as a stuck pixel's
  // value is), not a parameter fitted to them, and noise never passes it.
  bool acts_on(int n) const override {
    return n > 0 && ((period_ > 0 && n % period_ == phase_) || std::binary_search(repeats_.begin(), repeats_.end(), n));
  }
  void predict(int n, std::span<float> out) const override {
    std::fill(out.begin(), out.end(), 0.0f);
    if (!acts_on(n)) return;
    // The repeat reads what the previous frame read: residual becomes y_n - y_{n-1}.
    const float *y = d_.frame(d_.recorded, n), *yp = d_.frame(d_.recorded, n - 1), *r = d_.frame(r_, n);
    for (std::size_t p = 0; p < out.size(); ++p) out[p] = r[p] - (y[p] - yp[p]);
  }
  nlohmann::json params() const override {
    return {{"every", period_}, {"frames", repeats_}};
  }
  std::string simulator_effect() const override {
    return period_ > 0 ? "frame_duplication:every=" + std::to_string(period_) : "";
  }
  Where where() const override {
    Where w;
    for (int n : repeats_) w.frames.push_back({n - 1, n});
    w.row1 = d_.shape.height - 1;
    w.col1 = d_.shape.width - 1;
    w.summary = std::to_string(repeats_.size()) + " frame(s) identical to their predecessor" +
                (period_ > 0 ? ", every " + std::to_string(period_) + " frames" : "");
    return w;
  }

 private:
  const DiagnoseData& d_;
  const std::vector<float>& r_;
  int period_, phase_;
  std::vector<int> repeats_;
};

class FrameDuplication final : public Candidate {
 public:
  const char* id() const override { return "frame_duplication"; }
  int parameter_count() const override { return 1; }
  bool scored_where_it_acts() const override { return true; }
  void prepare(const DiagnoseData& d, const std::vector<float>& r) override {
    data_ = &d;
    residual_ = &r;
    repeats_.clear();
    const std::size_t P = d.shape.pixels();
    for (int n = 1; n < d.shape.n; ++n) {
      const float *y = d.frame(d.recorded, n), *yp = d.frame(d.recorded, n - 1);
      std::size_t same = 0;
      for (std::size_t p = 0; p < P; ++p) same += y[p] == yp[p];
      // Bit-identical frames (a few stuck pixels aside) cannot come from a sensor with noise.
      if (same >= P - P / 1000) repeats_.push_back(n);
    }
  }
  std::unique_ptr<FittedEffect> fit(const std::vector<char>& train) const override {
    std::vector<int> seen;
    for (int n : repeats_)
      if (train[n]) seen.push_back(n);
    if (repeats_.empty()) return nullptr;
    // The most common gap between repeats, if it explains all of them, is the period.
    int period = 0, phase = 0;
    if (seen.size() >= 2) {
      std::map<int, int> gaps;
      for (std::size_t i = 1; i < seen.size(); ++i) ++gaps[seen[i] - seen[i - 1]];
      int g = 0;
      for (auto [gap, count] : gaps) {
        bool divides = true;
        for (auto [other, c] : gaps) divides = divides && other % gap == 0;
        if (divides) { g = gap; break; }
      }
      if (g > 1) { period = g; phase = seen[0] % g; }
    }
    return std::make_unique<DuplicateFit>(*data_, *residual_, period, phase, repeats_);
  }

 private:
  const DiagnoseData* data_ = nullptr;
  const std::vector<float>* residual_ = nullptr;
  std::vector<int> repeats_;
};

}  // namespace

std::unique_ptr<Candidate> make_ffc_step() { return std::make_unique<FfcStep>(); }
std::unique_ptr<Candidate> make_fpa_drift() { return std::make_unique<FpaDrift>(); }
std::unique_ptr<Candidate> make_frame_duplication() { return std::make_unique<FrameDuplication>(); }

}  // namespace bolo::diag

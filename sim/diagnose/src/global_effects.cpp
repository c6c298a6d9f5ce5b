// Effects that move the whole frame at once: ffc_step (offset jumps at shutter events),
// fpa_drift (offset tracking the focal-plane temperature, or time since the last event), and
// frame_duplication (frames repeated bit for bit). Their evidence is the per-frame mean residual.

#include <algorithm>
#include <cmath>
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

// Offset jumps at shutter events: flagged frames, and unflagged jumps of the frame mean far
// above its frame-to-frame scatter.
class FfcStep final : public Candidate {
 public:
  const char* id() const override { return "ffc_step"; }
  int parameter_count() const override { return std::max<int>(1, int(events_.size())); }
  void prepare(const DiagnoseData& d, const std::vector<float>& r) override {
    data_ = &d;
    residual_ = &r;
    means_ = frame_means(d, r);
    events_.clear();
    const int N = d.shape.n;
    std::vector<double> mean(N), diff;
    for (int n = 0; n < N; ++n) mean[n] = means_.count[n] > 0 ? means_.sum[n] / means_.count[n] : 0.0;
    for (int n = 1; n < N; ++n) diff.push_back(mean[n] - mean[n - 1]);
    std::vector<double> abs_diff;
    for (double v : diff) abs_diff.push_back(std::fabs(v));
    const double scatter = 1.4826 * median_of(abs_diff);
    for (int n = 1; n < N; ++n) {
      const bool flagged = d.flagged_event[n] || (n + 1 < N && d.flagged_event[n + 1] && false);
      if (flagged || std::fabs(diff[n - 1]) > 8 * scatter + 1e-9) events_.push_back(n);
    }
    // Neighbouring detections are one event (a transient spreads a jump over two frames).
    std::vector<int> merged;
    for (int e : events_)
      if (merged.empty() || e - merged.back() > 5) merged.push_back(e);
    events_ = merged;
    if (events_.size() > 12) events_.resize(12);
  }
  std::unique_ptr<FittedEffect> fit(const std::vector<char>& train) const override {
    if (events_.empty()) return nullptr;
    const int N = data_->shape.n, k = int(events_.size());
    Eigen::MatrixXd X = Eigen::MatrixXd::Zero(N, k + 1);
    for (int n = 0; n < N; ++n) {
      X(n, 0) = 1.0;
      for (int e = 0; e < k; ++e) X(n, e + 1) = n >= events_[e] ? 1.0 : 0.0;
    }
    const Eigen::VectorXd beta = fit_frames(means_, X, train);
    std::vector<double> offset(N);
    for (int n = 0; n < N; ++n) offset[n] = X.row(n).dot(beta);
    nlohmann::json steps = nlohmann::json::array();
    std::string frames;
    double biggest = 0;
    Where where;
    for (int e = 0; e < k; ++e) {
      steps.push_back(beta[e + 1]);
      frames += (e ? "/" : "") + std::to_string(events_[e]);
      biggest = std::max(biggest, std::fabs(beta[e + 1]));
      where.frames.push_back({events_[e], events_[e]});
    }
    where.row1 = data_->shape.height - 1;
    where.col1 = data_->shape.width - 1;
    int flagged = 0;
    for (int e : events_) flagged += data_->flagged_event[e];
    where.summary = "global offset steps at frames " + frames + " (" + std::to_string(flagged) + " of " +
                    std::to_string(k) + " flagged in frames.csv)";
    nlohmann::json params = {{"frames", events_}, {"steps", steps}, {"flagged", flagged}};
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
  const DiagnoseData* data_ = nullptr;
  const std::vector<float>* residual_ = nullptr;
  FrameMeans means_;
  std::vector<int> events_;
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

#include "pooled.hpp"

#include "two_frame_derivative.hpp"

#include <cmath>
#include <sstream>

namespace bolo::diag {
namespace {

class PooledFit final : public FittedEffect {
 public:
  PooledFit(std::shared_ptr<const Regressors> X, Eigen::VectorXd beta, std::size_t pixels, nlohmann::json params,
            std::string sim, Where where)
      : X_(std::move(X)), beta_(std::move(beta)), P_(pixels), params_(std::move(params)),
        sim_(std::move(sim)), where_(std::move(where)) {}
  void predict(int n, std::span<float> out) const override {
    std::fill(out.begin(), out.end(), 0.0f);
    for (std::size_t j = 0; j < X_->size(); ++j) {
      const float b = static_cast<float>(beta_[j]);
      const float* x = (*X_)[j].data() + std::size_t(n) * P_;
      for (std::size_t p = 0; p < P_; ++p) out[p] += b * x[p];
    }
  }
  nlohmann::json params() const override { return params_; }
  std::string simulator_effect() const override { return sim_; }
  Where where() const override { return where_; }

 private:
  std::shared_ptr<const Regressors> X_;
  Eigen::VectorXd beta_;
  std::size_t P_;
  nlohmann::json params_;
  std::string sim_;
  Where where_;
};

// One frame's X'r and X'X (lower triangle mirrored) for K regressors in one pass over the
// pixels: each sum is taken in pixel order, as one loop per entry would (so equal to it), the
// entries interleaved.
template <int K>
void frame_products(const Regressors& X, std::size_t first, std::size_t P, const std::uint8_t* v, const float* r,
                    std::vector<double>& xtx, std::vector<double>& xtr) {
  const float* x[K];
  for (int i = 0; i < K; ++i) x[i] = X[i].data() + first;
  double sr[K] = {}, sx[K][K] = {};
  for (std::size_t p = 0; p < P; ++p) {
    const bool use = v[p] != 0;
    for (int i = 0; i < K; ++i) {
      sr[i] += use ? double(x[i][p]) * r[p] : 0.0;
      for (int j = 0; j <= i; ++j) sx[i][j] += use ? double(x[i][p]) * x[j][p] : 0.0;
    }
  }
  for (int i = 0; i < K; ++i) {
    xtr[i] = sr[i];
    for (int j = 0; j <= i; ++j) xtx[i * K + j] = xtx[j * K + i] = sx[i][j];
  }
}

}  // namespace

void PooledLinear::prepare(const DiagnoseData& data, const std::vector<float>& residual) {
  data_ = &data;
  residual_ = &residual;
  const int A = alternatives();
  const std::size_t P = data.shape.pixels();
  tau_nuisance_.clear();
  if (refits_tau() && data.has_scene && data.tau_c_s > 0) transient_tau_derivative(data, data.tau_c_s, tau_nuisance_);
  const int k = regressor_count() + (tau_nuisance_.empty() ? 0 : 1);
  stats_.assign(A, {});
  usable_.assign(A, 0);
  cache_.assign(A, nullptr);
  // Per-frame statistics; select.cpp's blocks are sums of frames, so keep them per frame.
  for (int a = 0; a < A; ++a) {
    auto X = std::make_shared<Regressors>();
    if (!fill(a, *X)) continue;
    usable_[a] = 1;
    auto& per_frame = stats_[a];
    per_frame.assign(data.shape.n, {Eigen::MatrixXd::Zero(k, k), Eigen::VectorXd::Zero(k)});
    std::vector<double> xtx(k * k), xtr(k);
    for (int n = 0; n < data.shape.n; ++n) {
      std::fill(xtx.begin(), xtx.end(), 0.0);
      std::fill(xtr.begin(), xtr.end(), 0.0);
      const std::uint8_t* v = data.valid_frame(n);
      const float* r = data.frame(residual, n);
      const std::size_t first = std::size_t(n) * P;
      if (k == 1) frame_products<1>(*X, first, P, v, r, xtx, xtr);
      else if (k == 2) frame_products<2>(*X, first, P, v, r, xtx, xtr);
      else if (k == 3) frame_products<3>(*X, first, P, v, r, xtx, xtr);
      else
        for (int i = 0; i < k; ++i) {
          const float* xi = (*X)[i].data() + first;
          double sr = 0;
          for (std::size_t p = 0; p < P; ++p) sr += v[p] ? double(xi[p]) * r[p] : 0.0;
          xtr[i] = sr;
          for (int j = 0; j <= i; ++j) {
            const float* xj = (*X)[j].data() + first;
            double s = 0;
            for (std::size_t p = 0; p < P; ++p) s += v[p] ? double(xi[p]) * xj[p] : 0.0;
            xtx[i * k + j] = xtx[j * k + i] = s;
          }
        }
      per_frame[n].xtx = Eigen::Map<Eigen::MatrixXd>(xtx.data(), k, k);
      per_frame[n].xtr = Eigen::Map<Eigen::VectorXd>(xtr.data(), k);
    }
    cache_[a] = X;  // keep the last few alternatives' regressors only if small
    if (std::size_t(A) * k * data.shape.size() > 60'000'000) cache_[a].reset();
  }
}

std::shared_ptr<const Regressors> PooledLinear::regressors_for(int alt) const {
  if (!cache_[alt]) {
    auto X = std::make_shared<Regressors>();
    fill(alt, *X);
    cache_[alt] = X;
  }
  return cache_[alt];
}

bool PooledLinear::fill(int alt, Regressors& X) const {
  if (!regressors(alt, X)) return false;
  if (!tau_nuisance_.empty()) X.push_back(tau_nuisance_);
  return true;
}

std::unique_ptr<FittedEffect> PooledLinear::fit(const std::vector<char>& train) const {
  const int k = regressor_count() + (tau_nuisance_.empty() ? 0 : 1);
  int best = -1;
  double best_gain = 0;
  Eigen::VectorXd best_beta;
  for (int a = 0; a < alternatives(); ++a) {
    if (!usable_[a]) continue;
    Eigen::MatrixXd xtx = Eigen::MatrixXd::Zero(k, k);
    Eigen::VectorXd xtr = Eigen::VectorXd::Zero(k);
    for (int n = 0; n < data_->shape.n; ++n)
      if (train[n]) { xtx += stats_[a][n].xtx; xtr += stats_[a][n].xtr; }
    if (xtx.trace() <= 0) continue;
    // A whisker of ridge keeps a nearly constant regressor from blowing up.
    xtx.diagonal().array() += 1e-9 * xtx.trace() / k + 1e-30;
    const Eigen::VectorXd beta = xtx.ldlt().solve(xtr);
    const double gain = beta.dot(xtr);  // training SSE reduction
    if (std::isfinite(gain) && (best < 0 || gain > best_gain)) { best = a; best_gain = gain; best_beta = beta; }
  }
  if (best < 0 || !physical(best, best_beta)) return nullptr;
  Where where;
  where.frames = {{0, data_->shape.n - 1}};
  where.row1 = data_->shape.height - 1;
  where.col1 = data_->shape.width - 1;
  where.summary = summary();
  return std::make_unique<PooledFit>(regressors_for(best), best_beta, data_->shape.pixels(),
                                     params_of(best, best_beta), simulator_text(best, best_beta), where);
}

}  // namespace bolo::diag

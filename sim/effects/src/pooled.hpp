#pragma once
// Effects whose model is linear in a few coefficients given the baseline: the residual is
// regressed on k regressor images per frame, pooled over every valid pixel-frame. A nonlinear
// parameter (tau2, a derivative scheme) is a small set of alternatives; the fit picks the one that
// explains the most of the training frames.

#include <memory>
#include <vector>

#include <Eigen/Dense>

#include "bolo/diagnose/candidate.hpp"

namespace bolo::diag {

using Regressors = std::vector<std::vector<float>>;  // k arrays of N*P

class PooledLinear : public Candidate {
 public:
  void prepare(const DiagnoseData& data, const std::vector<float>& residual) override;
  std::unique_ptr<FittedEffect> fit(const std::vector<char>& train_frame) const override;
  void release() override {
    cache_.clear();
    stats_.clear();
    tau_nuisance_ = {};
  }

 protected:
  virtual int alternatives() const { return 1; }
  virtual int regressor_count() const { return 1; }
  // Fills X (regressor_count() arrays of N*P) for alternative `alt`; false if it is all zero.
  virtual bool regressors(int alt, Regressors& X) const = 0;
  virtual nlohmann::json params_of(int alt, const Eigen::VectorXd& beta) const = 0;
  virtual std::string simulator_text(int /*alt*/, const Eigen::VectorXd& /*beta*/) const { return ""; }
  virtual std::string summary() const = 0;
  // Lets the baseline's tau move with the effect (the nested model is "baseline + effect", and a
  // transient effect fitted against a frozen tau would be charged with tau's share).
  virtual bool refits_tau() const { return false; }
  // A fit outside the parameter's physical range is no finding (a pole at 1, a negative blur).
  virtual bool physical(int /*alt*/, const Eigen::VectorXd& /*beta*/) const { return true; }

  const DiagnoseData* data_ = nullptr;
  const std::vector<float>* residual_ = nullptr;
  // d(baseline)/d(ln tau) on the transients, found by prepare() for a candidate that refits tau
  // (empty otherwise).
  const std::vector<float>& tau_nuisance() const { return tau_nuisance_; }

 private:
  std::shared_ptr<const Regressors> regressors_for(int alt) const;
  struct BlockStats {
    Eigen::MatrixXd xtx;
    Eigen::VectorXd xtr;
  };
  std::vector<std::vector<BlockStats>> stats_;  // [alt][block]
  std::vector<char> usable_;
  std::vector<float> tau_nuisance_;
  bool fill(int alt, Regressors& X) const;
  mutable std::vector<std::shared_ptr<const Regressors>> cache_;
};

}  // namespace bolo::diag

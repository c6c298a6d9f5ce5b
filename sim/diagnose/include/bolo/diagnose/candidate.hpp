#pragma once
// One catalogue effect as a fitting model (diagnose's half of an entry of bolo/effects/catalogue.hpp). A candidate sees the data and the current residual
// (recorded minus baseline minus the effects already accepted), fits its parameters on a set of
// training frames, and predicts its contribution to the residual on any frame. Selection
// (select.cpp) scores it on held-out blocks; nothing in a candidate knows which frames are held out.

#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bolo/diagnose/data.hpp"

namespace bolo::diag {

struct Where {
  std::vector<std::pair<int, int>> frames;  // inclusive
  int row0 = 0, row1 = -1, col0 = 0, col1 = -1;
  std::string summary;
};

class FittedEffect {
 public:
  virtual ~FittedEffect() = default;
  // Adds nothing to `out`; writes the effect's predicted residual for frame n (P values).
  virtual void predict(int n, std::span<float> out) const = 0;
  // Physical parameters, named as in diagnosis.md.
  virtual nlohmann::json params() const = 0;
  // The same effect as `bolo simulate --effect` text, or "" if the simulator cannot take it.
  virtual std::string simulator_effect() const { return ""; }
  virtual Where where() const = 0;
  // Frames where the prediction is identically zero need no evaluation.
  virtual bool acts_on(int /*n*/) const { return true; }
};

class Candidate {
 public:
  virtual ~Candidate() = default;
  virtual const char* id() const = 0;
  virtual int parameter_count() const = 0;  // scalar physical parameters (for the BIC penalty)
  // Called once per selection round with the current residual (kept by reference until the
  // next prepare); precomputes what every fold's fit shares.
  virtual void prepare(const DiagnoseData& data, const std::vector<float>& residual) = 0;
  // nullptr when nothing can be fitted (e.g. the regressor is zero: no motion, no FPA sensor).
  virtual std::unique_ptr<FittedEffect> fit(const std::vector<char>& train_frame) const = 0;
  // Static maps are validated on the far half of the recording (fitted on the first half, scored
  // on the second and back): slow noise of neighbouring blocks would otherwise look stable.
  virtual bool needs_distant_holdout() const { return false; }
  // An effect of a few frames whose test is exact (a bit-identical repeat) is scored on the
  // held-out frames it acts on, not diluted by all the others (whose noise, correlated over a
  // moving scene, would shrink the effective sample size below what two exact repeats need).
  virtual bool scored_where_it_acts() const { return false; }
  // An effect with a signature that the baseline's imperfections do not make (an in-core filter
  // keeps part of each pixel's own noise for one frame; a rolling readout's delay grows with the
  // row) can be measured far below any visible share of the noise or of the mismatch: its
  // statistic's z against its own sampling error (after prepare()), which selection takes in
  // place of the practical floor and the mismatch share. NaN: judged by those rules.
  virtual double signature_z() const { return std::numeric_limits<double>::quiet_NaN(); }
  // Frees what prepare() built (fitted effects keep their own share alive).
  virtual void release() {}
};

}  // namespace bolo::diag

#pragma once
// bolo::diag: find the physics a simulation left out (../shared/docs/diagnosis.md).
// diagnose() compares a recording with its baseline model, names catalogue effects that explain
// held-out residual, fits them, and lists what stays unexplained. The JSON result has the shape
// of diagnosis.md; the report (report.hpp) shows the same with plots.

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bolo/diagnose/baseline.hpp"
#include "bolo/diagnose/candidate.hpp"
#include "bolo/diagnose/data.hpp"

namespace bolo::diag {

struct Options {
  int folds = 4;
  int max_findings = 8;
  // A finding needs held-out Delta BIC above this and a consistent gain over held-out blocks
  // (z of the per-block gains); calibrated on null recordings (docs/diagnosis-study.md).
  double min_delta_bic = 10.0;
  double min_block_z = 1.0;
  // ... and must explain at least this share of the noise floor (RMS over all held-out samples).
  double min_explained_share = 0.03;
  // ... and at least this share of the mismatch it is scored on (its held-out mean square above
  // the noise floor's). A candidate that takes a sliver of a larger structure leans on something
  // else the baseline misses (motion within the exposure, an effect outside the catalogue): that
  // structure is reported as unexplained, not named after the candidate.
  double min_mismatch_share = 0.2;
  // A candidate with a signature of its own (Candidate::signature_z) needs this z instead.
  double min_signature_z = 5.0;
};

// delta_bic and log_likelihood_ratio of an effect that leaves no held-out residual at all (a
// repeated frame explained by repeating it): the JSON contract wants a number, the report says "exact".
inline constexpr double kExactEvidence = 1e9;

struct Evidence {
  double delta_bic = 0, log_likelihood_ratio = 0, p_value = 1, block_z = 0, n_eff = 0;
  double sse_before = 0, sse_after = 0, count = 0;
};

struct Finding {
  std::string effect;
  Evidence evidence;
  Where where;
  nlohmann::json params;
  std::string simulator_effect;
  double heldout_rms_before = 0, heldout_rms_after = 0;
  nlohmann::json baseline_refit;  // the baseline's parameters refitted with this finding in the model
};

struct CandidateScore {  // every candidate of every round, for the report
  int round = 0;
  std::string effect;
  Evidence evidence;
  bool accepted = false;
  std::string note;
};

struct Unexplained {
  Where where;
  double rms = 0;
};

struct Diagnosis {
  std::string recording;
  BaselineFit baseline;
  double fit_rms = 0, heldout_rms = 0, noise_floor_rms = 0;
  std::vector<Finding> findings;
  std::vector<CandidateScore> scores;
  std::vector<Unexplained> unexplained;
  nlohmann::json locate;  // where the baseline residual lives (profiles, spectra, correlations)
  double final_heldout_rms = 0;
};

// The residuals the report plots, kept from a run.
struct ResidualViews {
  std::vector<float> before, after;  // N*P: baseline residual, final residual
};

using ProgressFn = std::function<void(const std::string& stage, int done, int total)>;

Diagnosis diagnose(DiagnoseData& data, const Options& options, ResidualViews* views = nullptr,
                   const ProgressFn& progress = {});

// Diagnosis allocates and frees many arrays of the recording's size (residuals, regressors,
// simulated baselines). With glibc each would be mapped afresh and page-faulted in (most of the
// system time); this keeps freed memory in the process's heap for the next array instead.
// Process-wide and lasting: for a process whose work is diagnosis (bolo diagnose, its benchmark).
void keep_freed_memory_for_reuse();

nlohmann::json to_json(const Diagnosis& d);
// The simulator configuration of the fitted augmented model, as `bolo simulate --config` reads it.
std::string simulator_config(const Diagnosis& d, const DiagnoseData& data);

// Reads and checks a diagnosis.json (the shape of diagnosis.md); throws std::runtime_error
// naming the field that is wrong.
Diagnosis read_diagnosis_json(const std::string& text);

}  // namespace bolo::diag

#pragma once
// Loading a recording for diagnosis and the baseline it is compared with.
//  * With scene.npy: the two-frame model driven by the scene, tau_c fitted (log-scale search),
//    then gain and offset by linear least squares; tau_h follows from the DC gain.
//  * Without: a static camera is assumed. The scene is the per-pixel median over frames that are
//    not shutter events (nor the frame after one); pixel-frames far from it after removing the
//    frame's global shift are moving objects and are left out of every fit.

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "bolo/diagnose/data.hpp"

namespace bolo::diag {

struct BaselineFit {
  std::string model;       // "two-frame" or "static-background"
  std::string assumption;  // stated in the report and the JSON
  double tau_h_s = 0, tau_c_s = 0, gain = 1, offset = 0;
  double timing_frames = 0;       // scene read this many frames late (motion within an exposure)
  double exposure_motion = 0;     // share of data.exposure_motion in the reading (1: the scene moves throughout)
  bool tau_h_fitted = false;      // the exposures differ: tau_h fitted, not derived from the gain
  double exposure_offset = 0;     // offset per relative change of the exposure (0 with one exposure)
  bool tau_identifiable = false;  // false when a frame keeps < 1e-3 of the previous one
  double moving_fraction = 0;     // share of pixel-frames masked as moving objects
  bool large_miss_mask = false;   // steps where the baseline misses by > 3 sigma were masked too
  nlohmann::json to_json() const;
};

DiagnoseData load_for_diagnosis(const std::filesystem::path& recording);
BaselineFit fit_baseline(DiagnoseData& data);  // fills data.baseline, data.input, data.valid

// Temporal noise of one pixel from frame-to-frame differences where the baseline does not move,
// after removing each frame's common shift (outliers cut at five robust spreads). With
// `without_line_patterns`, each row's and column's median of those differences is taken out too
// when that lowers the figure by more than 5 %: the floor the findings must reach and the report
// shows. The baseline's masks use the plain figure, a conservative scale for what a large miss is.
double noise_floor(const DiagnoseData& data, bool without_line_patterns = true);

}  // namespace bolo::diag

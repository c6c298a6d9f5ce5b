#pragma once
// Evaluation of a `bolo odometry` run against ground truth (the host side of `bolo evaluate`):
// ATE after Sim(3) alignment, RPE, and the paper's map/trajectory metrics.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace bolo::odo {

struct EvaluateOptions {
  std::filesystem::path run;                  // output folder of `bolo odometry`
  // The trajectory scored, in `run`: trajectory.tum (the poses as tracked) or
  // trajectory-refined.tum (carried on the keyframes' last poses).
  std::string trajectory = "trajectory.tum";
  std::optional<std::filesystem::path> truth;  // default: <recording>/poses.tum from summary.json
  double rpe_delta_s = 1.0;
  double road_band_m = 0.3;                   // |z| below this (aligned) counts as road plane
};

// A stretch of the trajectory between restarts (the VO reinitialised after losing the track):
// each starts a new map with its own scale and origin, so it is aligned on its own as well.
struct TrackedSegment {
  std::size_t number = 1;          // 1 + the restarts before it (as trajectory.svg labels it)
  double first_t = 0, last_t = 0;  // of its poses, seconds
  std::size_t poses = 0;           // matched with the ground truth
  std::optional<double> ate_rmse;  // metres, after its own Sim(3) alignment (3 poses or more)
  double path_length_m = 0;        // of the ground truth over its poses
  double scale = 1;
};

struct Evaluation {
  std::string photometric;
  std::size_t frames = 0, posed = 0, lost = 0, keyframes = 0, reinitialisations = 0;
  std::size_t duplicates = 0;  // frames repeating the previous one (skipped: not in coverage)
  double coverage = 0;          // posed / (frames - duplicates)
  double ate_rmse = 0;          // metres, after Sim(3) alignment
  double ate_rmse_relative = 0;  // ATE / ground-truth path length over the posed frames
  double scale = 1;
  double rpe_trans_rmse = 0;    // metres over rpe_delta_s (estimate scaled by the Sim(3) scale)
  double rpe_rot_rmse_deg = 0;
  double path_length_m = 0;
  std::size_t tracked_points_total = 0;
  std::size_t map_points = 0, road_points = 0;
  double road_plane_rmse = 0, road_plane_std = 0;
  std::size_t line_segments = 0;
  double line_rmse = 0, line_std = 0;
  std::optional<double> tau_true_h, tau_true_c;
  double tau_h = 0, tau_c = 0;
  std::optional<double> tau_c_at_2s;   // estimate 2 s after tracking started
  std::optional<double> tau_c_error_final, tau_c_error_2s;  // relative
  double vo_ms_per_frame = 0;
  std::vector<TrackedSegment> segments;
  // Over the segments with an alignment, each aligned on its own: how well the VO tracks where it
  // tracks, apart from the scale and origin each restart begins anew.
  double segments_ate_rmse = 0, segments_ate_relative = 0;
};

Evaluation evaluate_run(const EvaluateOptions& options);
nlohmann::json to_json(const Evaluation& e);
std::string to_table(const Evaluation& e);

}  // namespace bolo::odo

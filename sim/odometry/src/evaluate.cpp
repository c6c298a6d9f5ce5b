#include "bolo/odometry/evaluate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>

#include "bolo/odometry/align.hpp"
#include "bolo/odometry/ply.hpp"
#include "bolo/odometry/stats_csv.hpp"
#include "bolo/odometry/tum.hpp"

namespace bolo::odo {
namespace {

namespace fs = std::filesystem;

nlohmann::json read_json(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw Error(file.string() + ": cannot open (is this a `bolo odometry` output folder?)");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw Error(file.string() + ": not valid JSON");
  }
}

// Each matched pose's segment, through the stats row of its time (nearest within half a period).
std::vector<std::size_t> segment_of_matches(const std::vector<StampedPose>& est, const Association& a,
                                            const std::vector<StatsRow>& stats, double period, const fs::path& trajectory) {
  std::vector<std::string> states;
  for (const StatsRow& r : stats) states.push_back(r.state);
  const std::vector<std::size_t> row_segment = tracking_segments(states);
  std::vector<std::size_t> out;
  std::size_t row = 0;
  for (const std::size_t e : a.estimate) {
    const double t = est[e].t;
    while (row + 1 < stats.size() && std::fabs(stats[row + 1].t_s - t) <= std::fabs(stats[row].t_s - t)) ++row;
    if (stats.empty() || std::fabs(stats[row].t_s - t) > 0.5 * period)
      throw Error(trajectory.string() + ": pose at t = " + std::to_string(t) + " s has no row in stats.csv");
    out.push_back(row_segment[row]);
  }
  return out;
}

double yaw_of(const vo::Vec3& d) { return std::atan2(d.y(), d.x()); }
double angle_diff(double a, double b) {
  double d = a - b;
  while (d > M_PI) d -= 2 * M_PI;
  while (d < -M_PI) d += 2 * M_PI;
  return std::fabs(d);
}

}  // namespace

Evaluation evaluate_run(const EvaluateOptions& options) {
  Evaluation e;
  const nlohmann::json summary = read_json(options.run / "summary.json");
  e.photometric = summary.value("photometric", "");
  const fs::path recording = summary.value("recording", "");
  const fs::path truth_file = options.truth ? *options.truth : recording / "poses.tum";
  if (!fs::exists(truth_file)) throw Error(truth_file.string() + ": missing (ground truth; use --truth)");
  const std::vector<StampedPose> truth = read_tum(truth_file);
  const fs::path trajectory = options.run / options.trajectory;
  if (!fs::exists(trajectory)) throw Error(trajectory.string() + ": missing (written by `bolo odometry`)");
  const std::vector<StampedPose> est = read_tum(trajectory);
  const std::vector<StatsRow> stats = read_stats_csv(options.run / "stats.csv");
  e.frames = stats.size();
  for (const StatsRow& r : stats) {
    e.tracked_points_total += r.tracked_points;
    e.keyframes += r.keyframe;
    e.lost += r.state == "lost";
    e.duplicates += r.state == "duplicate";
    e.vo_ms_per_frame += r.time_ms;
  }
  if (!stats.empty()) e.vo_ms_per_frame /= static_cast<double>(stats.size());
  e.posed = est.size();
  const std::size_t new_frames = e.frames - e.duplicates;
  e.coverage = new_frames ? static_cast<double>(e.posed) / static_cast<double>(new_frames) : 0;
  e.reinitialisations = summary.value("reinitialisations", 0u);
  e.tau_h = summary.value("tau_h_s", 0.0), e.tau_c = summary.value("tau_c_s", 0.0);

  double period = 0.01;
  if (truth.size() > 1) period = (truth.back().t - truth.front().t) / static_cast<double>(truth.size() - 1);
  const Association a = associate(est, truth, 0.5 * period);
  if (a.estimate.size() < 3) throw Error(trajectory.string() + ": fewer than 3 poses match the ground truth in time");
  std::vector<vo::Vec3> from, to;
  for (std::size_t k = 0; k < a.estimate.size(); ++k)
    from.push_back(est[a.estimate[k]].T_wc.t), to.push_back(truth[a.truth[k]].T_wc.t);
  // The whole run as one segment (at least 3 pairs, checked above).
  const SegmentAlignment whole = align_segments(from, to, std::vector<std::size_t>(from.size(), 0)).front();
  const Similarity sim = whole.similarity.value();
  e.scale = sim.s;
  e.ate_rmse = std::sqrt(whole.squared_error / static_cast<double>(from.size()));
  for (std::size_t k = 1; k < to.size(); ++k) e.path_length_m += (to[k] - to[k - 1]).norm();
  e.ate_rmse_relative = e.path_length_m > 0 ? e.ate_rmse / e.path_length_m : 0;

  // The same per tracking segment, each with its own alignment (a run that never restarted is
  // one segment: the whole run's).
  const std::vector<std::size_t> match_segment = segment_of_matches(est, a, stats, period, trajectory);
  const bool one_segment = std::all_of(match_segment.begin(), match_segment.end(),
                                       [&](std::size_t m) { return m == match_segment.front(); });
  double segments_sq = 0, segments_path = 0;
  std::size_t segments_n = 0;
  for (const SegmentAlignment& fit : one_segment ? std::vector<SegmentAlignment>{whole} : align_segments(from, to, match_segment)) {
    TrackedSegment seg;
    seg.number = match_segment[fit.begin] + 1;
    seg.first_t = est[a.estimate[fit.begin]].t, seg.last_t = est[a.estimate[fit.end - 1]].t, seg.poses = fit.end - fit.begin;
    for (std::size_t q = fit.begin + 1; q < fit.end; ++q) seg.path_length_m += (to[q] - to[q - 1]).norm();
    if (fit.similarity) {
      seg.ate_rmse = std::sqrt(fit.squared_error / static_cast<double>(seg.poses));
      seg.scale = fit.similarity->s;
      segments_sq += fit.squared_error, segments_n += seg.poses, segments_path += seg.path_length_m;
    }
    e.segments.push_back(seg);
  }
  if (segments_n) {
    e.segments_ate_rmse = std::sqrt(segments_sq / static_cast<double>(segments_n));
    e.segments_ate_relative = segments_path > 0 ? e.segments_ate_rmse / segments_path : 0;
  }

  // RPE over rpe_delta_s: relative motions of the estimate (scaled) against the truth's.
  double rpe_t = 0, rpe_r = 0;
  std::size_t rpe_n = 0, j = 0;
  for (std::size_t i = 0; i < a.estimate.size(); ++i) {
    const double t_i = est[a.estimate[i]].t;
    while (j < a.estimate.size() && est[a.estimate[j]].t < t_i + options.rpe_delta_s - 1e-9) ++j;
    if (j >= a.estimate.size()) break;
    if (est[a.estimate[j]].t - t_i > options.rpe_delta_s + 2 * period) continue;
    vo::Se3 Ei = est[a.estimate[i]].T_wc, Ej = est[a.estimate[j]].T_wc;
    Ei.t *= sim.s, Ej.t *= sim.s;
    const vo::Se3 dE = Ei.inverse() * Ej;
    const vo::Se3 dG = truth[a.truth[i]].T_wc.inverse() * truth[a.truth[j]].T_wc;
    const vo::Se3 err = dG.inverse() * dE;
    rpe_t += err.t.squaredNorm();
    const double ang = vo::so3_log(err.R).norm() * 180.0 / M_PI;
    rpe_r += ang * ang;
    ++rpe_n;
  }
  if (rpe_n) e.rpe_trans_rmse = std::sqrt(rpe_t / rpe_n), e.rpe_rot_rmse_deg = std::sqrt(rpe_r / rpe_n);

  // Map: points on the road plane (ground z = 0 of the simulated world) after alignment.
  const std::vector<vo::Vec3> map = read_ply_points(options.run / "points.ply");
  e.map_points = map.size();
  std::vector<vo::Vec3> road;
  for (const vo::Vec3& p : map) {
    const vo::Vec3 q = sim.apply(p);
    if (std::fabs(q.z()) < options.road_band_m) road.push_back(q);
  }
  e.road_points = road.size();
  const Fit plane = plane_fit(road);
  e.road_plane_rmse = plane.rmse, e.road_plane_std = plane.std;

  // Straight segments of the true path (heading within 2 degrees for >= 1 s): line fits of the
  // aligned estimated camera positions there.
  std::vector<double> heading(to.size(), NAN);
  for (std::size_t k = 0; k < to.size(); ++k) {
    std::size_t m = k;
    while (m + 1 < to.size() && (to[m] - to[k]).norm() < 0.5) ++m;
    if ((to[m] - to[k]).norm() >= 0.5) heading[k] = yaw_of(to[m] - to[k]);
  }
  double line_sq = 0, line_sum = 0;
  std::size_t line_n = 0;
  for (std::size_t k = 0; k < to.size();) {
    if (std::isnan(heading[k])) {
      ++k;
      continue;
    }
    std::size_t m = k;
    while (m + 1 < to.size() && !std::isnan(heading[m + 1]) && angle_diff(heading[m + 1], heading[k]) < 2.0 * M_PI / 180.0) ++m;
    const double duration = est[a.estimate[m]].t - est[a.estimate[k]].t;
    if (duration >= 1.0 && (to[m] - to[k]).norm() >= 2.0) {
      std::vector<vo::Vec3> seg;
      for (std::size_t q = k; q <= m; ++q) seg.push_back(sim.apply(from[q]));
      const Fit f = line_fit(seg);
      line_sq += f.rmse * f.rmse * static_cast<double>(f.count);
      line_sum += static_cast<double>(f.count) * f.std * f.std;
      line_n += f.count;
      ++e.line_segments;
    }
    k = m + 1;
  }
  if (line_n) e.line_rmse = std::sqrt(line_sq / line_n), e.line_std = std::sqrt(line_sum / line_n);

  // Tau against the simulation's truth (evaluation may read truth/).
  const fs::path effects = recording / "truth" / "effects.json";
  if (fs::exists(effects)) {
    const nlohmann::json fx = read_json(effects);
    if (fx.contains("baseline") && fx["baseline"].contains("tau_c_s")) {
      e.tau_true_h = fx["baseline"].value("tau_h_s", 0.0);
      e.tau_true_c = fx["baseline"].value("tau_c_s", 0.0);
    }
  }
  double t_start = NAN;
  for (const StatsRow& r : stats)
    if (r.state == "tracking") {
      if (std::isnan(t_start)) t_start = r.t_s;
      if (r.t_s >= t_start + 2.0) {
        e.tau_c_at_2s = r.tau_c_s;
        break;
      }
    }
  if (e.tau_true_c && *e.tau_true_c > 0 && (e.photometric == "ir" || e.photometric == "ir-loop")) {
    e.tau_c_error_final = std::fabs(e.tau_c - *e.tau_true_c) / *e.tau_true_c;
    if (e.tau_c_at_2s) e.tau_c_error_2s = std::fabs(*e.tau_c_at_2s - *e.tau_true_c) / *e.tau_true_c;
  }
  return e;
}

nlohmann::json to_json(const Evaluation& e) {
  nlohmann::json j = {{"photometric", e.photometric}, {"frames", e.frames}, {"posed", e.posed},
                      {"coverage", e.coverage}, {"lost", e.lost}, {"duplicates", e.duplicates}, {"keyframes", e.keyframes},
                      {"reinitialisations", e.reinitialisations}, {"ate_rmse_m", e.ate_rmse},
                      {"ate_relative", e.ate_rmse_relative}, {"path_length_m", e.path_length_m},
                      {"scale", e.scale}, {"rpe_trans_rmse_m", e.rpe_trans_rmse},
                      {"rpe_rot_rmse_deg", e.rpe_rot_rmse_deg}, {"tracked_points_total", e.tracked_points_total},
                      {"map_points", e.map_points}, {"road_points", e.road_points},
                      {"road_plane_rmse_m", e.road_plane_rmse}, {"road_plane_std_m", e.road_plane_std},
                      {"line_segments", e.line_segments}, {"line_rmse_m", e.line_rmse}, {"line_std_m", e.line_std},
                      {"tau_h_s", e.tau_h}, {"tau_c_s", e.tau_c}, {"vo_ms_per_frame", e.vo_ms_per_frame}};
  j["tau_true_c_s"] = e.tau_true_c ? nlohmann::json(*e.tau_true_c) : nlohmann::json(nullptr);
  j["tau_c_at_2s_s"] = e.tau_c_at_2s ? nlohmann::json(*e.tau_c_at_2s) : nlohmann::json(nullptr);
  j["tau_c_error_final"] = e.tau_c_error_final ? nlohmann::json(*e.tau_c_error_final) : nlohmann::json(nullptr);
  j["tau_c_error_2s"] = e.tau_c_error_2s ? nlohmann::json(*e.tau_c_error_2s) : nlohmann::json(nullptr);
  nlohmann::json segments = nlohmann::json::array();
  for (const TrackedSegment& seg : e.segments)
    segments.push_back({{"number", seg.number}, {"first_t_s", seg.first_t}, {"last_t_s", seg.last_t}, {"poses", seg.poses},
                        {"ate_rmse_m", seg.ate_rmse ? nlohmann::json(*seg.ate_rmse) : nlohmann::json(nullptr)},
                        {"path_length_m", seg.path_length_m}, {"scale", seg.scale}});
  j["segments"] = segments;
  j["segments_ate_rmse_m"] = e.segments_ate_rmse;
  j["segments_ate_relative"] = e.segments_ate_relative;
  return j;
}

std::string to_table(const Evaluation& e) {
  std::ostringstream s;
  char buf[160];
  const auto row = [&](const char* key, const std::string& value) {
    std::snprintf(buf, sizeof buf, "  %-28s %s\n", key, value.c_str());
    s << buf;
  };
  const auto num = [](double v, const char* fmt) {
    char b[64];
    std::snprintf(b, sizeof b, fmt, v);
    return std::string(b);
  };
  row("photometric", e.photometric);
  row("frames (posed / lost)", std::to_string(e.frames) + " (" + std::to_string(e.posed) + " / " + std::to_string(e.lost) + ")" +
                                   (e.duplicates ? ", " + std::to_string(e.duplicates) + " repeated (skipped)" : std::string()));
  row("keyframes", std::to_string(e.keyframes));
  row("reinitialisations", std::to_string(e.reinitialisations));
  row("ATE rmse (Sim3)", num(e.ate_rmse, "%.3f m") + num(100 * e.ate_rmse_relative, " (%.2f %% of ") + num(e.path_length_m, "%.1f m)"));
  if (e.segments.size() > 1) {
    row("tracking segments", std::to_string(e.segments.size()) + " (a restart begins a new map: each aligned on its own)");
    for (const TrackedSegment& seg : e.segments) {
      const std::string ate = seg.ate_rmse ? num(*seg.ate_rmse, "ATE %.3f m") +
                                                 num(seg.path_length_m > 0 ? 100 * *seg.ate_rmse / seg.path_length_m : 0.0, " (%.2f %% of ") +
                                                 num(seg.path_length_m, "%.1f m)") + num(seg.scale, ", scale %.3g")
                                           : std::string("too short to align");
      row(("  segment " + std::to_string(seg.number)).c_str(),
          num(seg.first_t, "%.2f-") + num(seg.last_t, "%.2f s, ") + std::to_string(seg.poses) + " poses, " + ate);
    }
    row("ATE over the segments", num(e.segments_ate_rmse, "%.3f m") + num(100 * e.segments_ate_relative, " (%.2f %% of their path)"));
  }
  row("RPE trans / rot", num(e.rpe_trans_rmse, "%.3f m / ") + num(e.rpe_rot_rmse_deg, "%.2f deg"));
  row("tracked points (total)", std::to_string(e.tracked_points_total));
  row("map / road points", std::to_string(e.map_points) + " / " + std::to_string(e.road_points));
  row("road plane rmse / std", num(e.road_plane_rmse, "%.3f m / ") + num(e.road_plane_std, "%.3f m"));
  row("line fit rmse / std", num(e.line_rmse, "%.3f m / ") + num(e.line_std, "%.3f m") + " (" + std::to_string(e.line_segments) + " segments)");
  row("tau_h / tau_c", num(e.tau_h * 1e3, "%.2f / ") + num(e.tau_c * 1e3, "%.2f ms"));
  if (e.tau_true_c) row("tau_c true", num(*e.tau_true_c * 1e3, "%.2f ms"));
  if (e.tau_c_error_2s) row("tau_c error after 2 s", num(100 * *e.tau_c_error_2s, "%.1f %%"));
  if (e.tau_c_error_final) row("tau_c error at the end", num(100 * *e.tau_c_error_final, "%.1f %%"));
  row("VO time per frame", num(e.vo_ms_per_frame, "%.2f ms"));
  return s.str();
}

}  // namespace bolo::odo

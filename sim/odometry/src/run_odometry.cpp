#include "bolo/odometry/run_odometry.hpp"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <set>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bolo/core/frame_collector.hpp"
#include "bolo/firmware/carry_over_rule.hpp"
#include "bolo/firmware/two_frame_corrector.hpp"
#include "bolo/odometry/align.hpp"
#include "bolo/odometry/pinhole_remap.hpp"
#include "bolo/odometry/plot.hpp"
#include "bolo/odometry/ply.hpp"
#include "bolo/odometry/stats_csv.hpp"
#include "bolo/odometry/trajectory_plot.hpp"
#include "bolo/recording/frame_row_header.hpp"
#include "bolo/recording/recording.hpp"
#include "bolo/vo/odometry.hpp"

namespace bolo::odo {
namespace {

namespace fs = std::filesystem;

// The frames the VO runs over: a recording's, read as they are needed, or a live source's (read
// through hal::FrameReader by the caller). A recording is not read through the HAL: the VO needs
// the whole run's median frame interval before its first frame, --reverse reads it last to first,
// and the VO's times are frames.csv's seconds as written (a FrameHeader rounds them to ns).
struct Input {
  std::string name;  // the recording folder or the spec, as errors and summary.json name it
  fs::path csv;      // what errors about a frame's row name: frames.csv, or the spec
  std::uint32_t width = 0, height = 0;
  rec::Units units = rec::Units::counts;
  const std::vector<rec::FrameRow>* rows = nullptr;
  std::optional<nlohmann::json> camera;  // camera.json
  fs::path dir;                          // a recording's folder (camera.json, poses.tum)
  std::optional<rec::Recording> recording;
  std::optional<LiveFrames> live;

  void read(std::uint64_t i, std::span<std::uint16_t> out) {
    if (recording) return recording->read_frame(i, out);
    const std::size_t n = std::size_t{width} * height;
    std::copy_n(live->pixels.begin() + static_cast<std::ptrdiff_t>(i * n), n, out.begin());
  }
};

// camera.json as the recording format defines it (a pinhole with OpenCV's rational distortion).
sim::scene::Camera read_camera(const Input& input) {
  if (input.live) throw Error(input.name + ": a live source has no camera.json (give --hfov DEG)");
  const fs::path file = input.dir / "camera.json";
  if (!input.camera)
    throw Error(file.string() + ": missing (the VO needs the camera intrinsics: add it, or give --hfov DEG)");
  try {
    return sim::scene::Camera::from_json(*input.camera, input.width, input.height);
  } catch (const std::invalid_argument& e) {
    throw Error(file.string() + ": " + e.what());
  }
}

// The frames' resampling onto the VO's pinhole (no resampling without distortion or with --hfov).
PinholeRemap pinhole_remap(const OdometryOptions& options, const Input& input) {
  const std::uint32_t w = input.width, h = input.height;
  if (options.hfov_deg) {
    sim::scene::Camera pinhole(w, h, *options.hfov_deg);
    return PinholeRemap(pinhole);
  }
  const sim::scene::Camera camera = read_camera(input);
  try {
    return PinholeRemap(camera);
  } catch (const std::invalid_argument& e) {
    throw Error((input.dir / "camera.json").string() + ": distortion coefficients: " + e.what());
  }
}

struct FrameTiming {
  double exposure_s = 0, readout_s = 0;  // 0 where the photometric model does not use them (or unknown)
};

std::uint32_t to_ns(double seconds) { return static_cast<std::uint32_t>(std::llround(seconds * 1e9)); }

// A setting the VO holds as a float, as the decimal it was given (0.01, not 0.009999999776): the
// shortest decimal that reads back as the same float.
double as_given(float value) {
  char text[32];
  const std::to_chars_result written = std::to_chars(text, text + sizeof text, value);
  double out = value;
  std::from_chars(text, written.ptr, out);
  return out;
}

// A change of exposure or readout between frames is a step response of the static scene, which
// the tau fit reads at first order, as it does a shutter event; compared as the VO compares them.
TauSource tau_source(bool ir, bool estimated, bool from_shutter, const std::vector<FrameTiming>& timing) {
  if (!ir) return TauSource::none;
  if (!estimated) return TauSource::fixed;
  if (from_shutter) return TauSource::shutter_events;
  for (std::size_t i = 1; i < timing.size(); ++i)
    if (timing[i].exposure_s != timing[i - 1].exposure_s || timing[i].readout_s != timing[i - 1].readout_s)
      return TauSource::exposure_changes;
  return TauSource::motion;
}

// Removes the temporary output folder unless committed.
void write_text(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary);
  out << text;
  if (!out) throw Error(file.string() + ": cannot write");
}

}  // namespace

const char* to_string(TauSource source) {
  switch (source) {
    case TauSource::none: return "none";
    case TauSource::fixed: return "fixed";
    case TauSource::shutter_events: return "shutter_events";
    case TauSource::exposure_changes: return "exposure_changes";
    case TauSource::motion: return "motion";
  }
  return "none";
}

double corrected_image_delay_s(double exposure_s, double tau_h_s) {
  const double x = exposure_s / tau_h_s;
  return x < 1e-6 ? 0.5 * exposure_s : tau_h_s - exposure_s * std::exp(-x) / -std::expm1(-x);
}

namespace {
OdometrySummary run(const OdometryOptions& options, const std::function<void(Input&)>& open);
}  // namespace

OdometrySummary run_odometry(const OdometryOptions& options) {
  return run(options, [&](Input& input) {
    const rec::Recording& r = input.recording.emplace(options.recording);
    input.name = options.recording.string();
    input.csv = r.dir() / "frames.csv";
    input.width = r.width(), input.height = r.height();
    input.units = r.info().units;
    input.rows = &r.rows();
    input.camera = r.camera();
    input.dir = r.dir();
  });
}

OdometrySummary run_odometry(const OdometryOptions& options, const std::function<LiveFrames()>& read) {
  OdometryOptions all = options;
  all.max_frames.reset();
  return run(all, [&](Input& input) {
    LiveFrames& frames = input.live.emplace(read());
    if (frames.rows.empty()) throw Error(frames.name + ": no frames");
    input.name = frames.name;
    input.csv = frames.name;
    input.width = frames.width, input.height = frames.height;
    input.units = frames.units;
    input.rows = &frames.rows;
  });
}

namespace {

OdometrySummary run(const OdometryOptions& options, const std::function<void(Input&)>& open) {
  const fs::path out_dir = options.output.has_filename() ? options.output : options.output.parent_path();
  rec::AtomicFolder folder(out_dir, options.overwrite);  // the destination checked before the work
  Input input;
  open(input);
  const std::uint32_t w = input.width, h = input.height;
  vo::VoConfig config = options.vo;
  config.width = w, config.height = h;
  const PinholeRemap remap = pinhole_remap(options, input);
  config.camera = remap.pinhole();
  if (const char* why = vo::invalid_reason(config)) throw Error(input.name + ": " + why);

  const std::vector<rec::FrameRow>& rows = *input.rows;
  const std::uint64_t frames = std::min<std::uint64_t>(rows.size(), options.max_frames.value_or(rows.size()));
  const bool ir = config.photometric == vo::Photometric::ir || config.photometric == vo::Photometric::ir_loop;
  if (ir && options.reverse) throw Error(input.name + ": the ir modes' carry-over runs forward in time (reverse: none or affine)");
  const fs::path& csv = input.csv;
  for (std::uint64_t i = 0; i < frames; ++i)
    if (!rows[i].t_s) throw Error(csv.string() + ": frame " + std::to_string(i) + ": t_s is empty (the VO needs frame times)");
  // Frame period for gap detection: the median interval.
  std::vector<double> intervals;
  for (std::uint64_t i = 1; i < frames; ++i) intervals.push_back(*rows[i].t_s - *rows[i - 1].t_s);
  std::sort(intervals.begin(), intervals.end());
  const double period = intervals.empty() ? 0.0 : intervals[intervals.size() / 2];
  const std::uint64_t period_ns = static_cast<std::uint64_t>(std::llround(period * 1e9));

  OdometrySummary summary;
  summary.ir_on_tone_mapped = ir && input.units == rec::Units::counts8;
  summary.live = input.live.has_value();
  // The ir modes' frame timing: frames.csv, else the options, else half the frame interval each.
  std::vector<FrameTiming> timing(frames);
  if (ir) {
    const double half = 0.5 * period;
    for (std::uint64_t i = 0; i < frames; ++i) {
      const rec::FrameRow& row = rows[i];
      // 0: from frames.csv, 1: from the options, 2: assumed.
      const auto fill = [&](const std::optional<double>& cell, const std::optional<double>& option, double& value) {
        if (cell) {
          value = *cell;
          return 0;
        }
        if (option) {
          value = *option;
          return 1;
        }
        value = half;
        return 2;
      };
      const int e = fill(row.exposure_s, options.exposure_s, timing[i].exposure_s);
      const int r = fill(row.readout_s, options.readout_s, timing[i].readout_s);
      if (std::max(e, r) == 1) ++summary.timing_from_options;
      if (std::max(e, r) == 2) ++summary.timing_assumed;
      const std::string at = csv.string() + ": frame " + std::to_string(i) + ": ";
      if (!(timing[i].exposure_s > 0))
        throw Error(at + (e == 0 ? "exposure_s must be positive"
                                 : "exposure_s empty and no frame interval to assume it from (give --exposure)"));
      if (!(timing[i].readout_s >= 0)) throw Error(at + "readout_s must not be negative");
    }
    if (summary.timing_assumed > 0) summary.assumed_half_period_s = half;
  } else if (config.photometric == vo::Photometric::affine) {
    // affine starts a frame whose exposure changed at the exposures' ratio (as DSO with known
    // exposure times); where frames.csv does not give them, nothing is assumed.
    for (std::uint64_t i = 0; i < frames; ++i) {
      if (rows[i].exposure_s && *rows[i].exposure_s > 0) timing[i].exposure_s = *rows[i].exposure_s;
      if (rows[i].readout_s && *rows[i].readout_s >= 0) timing[i].readout_s = *rows[i].readout_s;
    }
  }

  std::vector<std::byte> arena(vo::Odometry::arena_bytes(config));
  vo::Odometry odometry(config, arena);
  if (!odometry.ok()) throw Error(input.name + ": the VO could not be set up for this size");

  // ir-loop: the firmware corrector in front, fed back with the VO's tau.
  std::vector<fw::Pixel> corrected_storage(fw::FrameCollector::storage_pixels(w, h));
  fw::FrameCollector corrected(w, h, corrected_storage);
  std::vector<fw::Pixel> corrector_storage(fw::TwoFrameCorrector::storage_pixels(w, h));
  fw::CorrectorConfig cc;
  cc.width = w, cc.height = h;
  cc.tau = {to_ns(as_given(config.tau_init_s)), to_ns(as_given(config.tau_init_s))};
  fw::TwoFrameCorrector corrector(cc, corrector_storage, corrected);


  std::vector<std::uint16_t> raw(std::size_t{w} * h), previous_raw(raw.size());
  std::vector<std::uint16_t> distorted(remap.identity() ? 0 : raw.size());
  std::vector<StampedPose> trajectory;
  std::vector<std::size_t> pose_frame;  // the frame of each trajectory pose
  // Each trajectory pose's keyframe tie, and what --poses-at-read moved it by (the VO's pose times
  // it is the pose written): with the keyframes' last poses, the refined trajectory.
  std::vector<std::pair<vo::KeyframeTie, vo::Se3>> pose_tie;
  std::map<std::uint32_t, vo::KeyframePose> keyframe_last;  // by id: as it left the window, or at the end
  std::vector<std::string> states;      // every frame's VO state
  std::vector<vo::WorldPoint> points;
  std::ostringstream stats;
  stats << stats_csv_header();
  summary.arena_bytes = arena.size();
  summary.undistorted = !remap.identity();
  summary.focal_scale = remap.focal_scale();
  double vo_seconds = 0;
  bool held_before = false;
  // --poses-at-read: the pose written last, at its frame's t_s, while frames are posed in a row in one
  // map. The camera's velocity is taken over that one step: a mean over more steps lags a
  // look-around's turn (docs/odometry-study.md, "A continuous lag").
  std::optional<std::pair<double, vo::Se3>> previous_pose;
  // The frame fed i-th, and the time the VO gets for it (mirrored when reversed, so it increases).
  const auto frame_of = [&](std::uint64_t i) { return options.reverse ? frames - 1 - i : i; };
  const auto vo_time = [&](std::uint64_t j) {
    return options.reverse ? *rows[0].t_s + *rows[frames - 1].t_s - *rows[j].t_s : *rows[j].t_s;
  };
  // The header of the frame fed i-th as the VO gets it: reversed, counted and timed in the order
  // fed, with the shutter flag of the later of it and the frame fed before (the event lies between).
  const auto fed_header = [&](std::uint64_t i) {
    const std::uint64_t j = frame_of(i);
    fw::FrameHeader header = rec::header_from_row(rows[j], w, h, csv);
    if (options.reverse) {
      header.sequence = i;
      header.timestamp_ns = std::llround(vo_time(j) * 1e9);
      if (i > 0) header.ffc = rec::header_from_row(rows[frame_of(i - 1)], w, h, csv).ffc;
    }
    return header;
  };
  const auto vo_time_to_recording = [&](double t) { return options.reverse ? *rows[0].t_s + *rows[frames - 1].t_s - t : t; };
  std::vector<double> fed_t;  // the time the VO got with the frame fed i-th
  fed_t.reserve(frames);
  const auto is_sane = [](const vo::Se3& T_wc) { return T_wc.t.allFinite() && T_wc.R.allFinite() && T_wc.t.norm() < 1e6; };
  fw::FrameHeader previous_header;
  for (std::uint64_t i = 0; i < frames; ++i) {
    const std::uint64_t j = frame_of(i), before = i > 0 ? frame_of(i - 1) : j;
    if (remap.identity()) {
      input.read(j, raw);
    } else {
      input.read(j, distorted);
      remap.apply(distorted, raw);
    }
    const rec::FrameRow& row = rows[j];
    vo::FrameInput in;
    in.raw = raw;
    in.t_s = vo_time(j);
    fed_t.push_back(in.t_s);
    in.exposure_s = timing[j].exposure_s;
    in.readout_prev_s = i > 0 ? timing[before].readout_s : 0.0;
    // The carry-over chain breaks where the corrector's does (a shutter event, a gap in time).
    fw::FrameHeader header = fed_header(i);
    in.shutter_event = i > 0 && header.ffc == fw::FfcState::completed;
    in.chain_broken = i == 0 || fw::carry_over_between(previous_header, header, period_ns) != fw::CarryOver::applied;
    previous_header = header;
    // A repeated frame is skipped by the VO; the corrector does not see it either, so the frame
    // sequence it gets has a gap and it restarts its carry-over chain after it.
    const bool repeated = !in.chain_broken && raw == previous_raw;
    const auto start = std::chrono::steady_clock::now();
    if (config.photometric == vo::Photometric::ir_loop && !repeated) {
      const vo::Tau tau = odometry.tau();
      corrector.set_time_constants({to_ns(tau.h), to_ns(tau.c)});
      // The frame's header with the timing resolved above (assumed where frames.csv has none).
      header.exposure_ns = to_ns(in.exposure_s);
      header.readout_ns = to_ns(timing[j].readout_s);
      corrector.begin_frame(header);
      for (std::uint32_t y = 0; y < h; ++y) corrector.push_line(y, fw::LineView(raw.data() + std::size_t{y} * w, w));
      corrector.end_frame();
      in.corrected = corrected.pixels();
    }
    const vo::FrameResult r = odometry.process(in);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    vo_seconds += ms / 1e3;
    for (const vo::WorldPoint& p : odometry.retired_points()) points.push_back(p);
    for (const vo::KeyframePose& k : odometry.retired_keyframes()) keyframe_last[k.id] = k;
    // A pose into the trajectory; --poses-at-read carries it from its image's instant to t_s at the
    // camera's motion over the step from the pose before (posed in a row, in the same map).
    const auto write_pose = [&](std::uint64_t fed, const vo::Se3& T_wc, const vo::KeyframeTie& tie) {
      const std::uint64_t row_index = frame_of(fed);
      const double t = *rows[row_index].t_s;
      vo::Se3 pose = T_wc;
      if (options.poses_at_read && previous_pose) {
        const auto& [t0, from] = *previous_pose;
        const double dt = t - t0;
        if (dt > 0 && dt < 1.5 * period) {
          const double delay = corrected_image_delay_s(timing[row_index].exposure_s, odometry.tau().h);
          pose = (pose * vo::Se3::exp((from.inverse() * pose).log() * (delay / dt))).orthonormalised();
        }
      }
      previous_pose.emplace(t, T_wc);
      trajectory.push_back({t, pose}), pose_frame.push_back(fed), ++summary.posed;
      pose_tie.push_back({tie, T_wc.inverse() * pose});
    };
    if (r.reinitialised) previous_pose.reset();
    // The frames the initialisation that completed here took, posed now (before this frame's pose,
    // so that the trajectory stays in the order fed).
    for (const vo::TimedPose& p : options.online_poses_only ? std::span<const vo::TimedPose>() : odometry.initialisation_poses()) {
      const auto fed = std::find(fed_t.rbegin(), fed_t.rend(), p.t_s);
      if (fed == fed_t.rend() || !is_sane(p.T_wc)) continue;
      write_pose(static_cast<std::uint64_t>(fed_t.rend() - fed - 1), p.T_wc, p.tie);
      ++summary.posed_at_initialisation;
    }
    // A pose the VO reports but that has run away (scale blow-up) is not written as one.
    if (r.has_pose && is_sane(r.T_wc))
      write_pose(i, r.T_wc, r.tie);
    else
      previous_pose.reset();
    states.emplace_back(vo::to_string(r.state));
    summary.lost += r.state == vo::TrackingState::lost;
    summary.duplicates += r.state == vo::TrackingState::duplicate;
    summary.keyframes += r.keyframe;
    summary.reinitialisations += r.reinitialised;
    summary.shutter_events += in.shutter_event;
    summary.carry_over_breaks += i > 0 && in.chain_broken;
    if (r.shutter_tau_s > 0) summary.shutter_taus.push_back({*row.t_s, r.shutter_tau_s});
    if (r.centre_held) {
      if (!held_before) summary.scale_bridges.push_back({*row.t_s, *row.t_s});
      summary.scale_bridges.back().second = *row.t_s;
      ++summary.centre_held;
    }
    held_before = r.centre_held;
    stats << stats_csv_line({j, *row.t_s, vo::to_string(r.state), r.tracked_points, r.keyframe,
                             static_cast<double>(r.residual_rms), r.tau.h, r.tau.c, ms});
    if (options.progress) options.progress(i + 1, frames);
    std::swap(raw, previous_raw);  // the next frame is read into the older buffer
  }
  std::vector<vo::WorldPoint> window(8 * 1200);
  window.resize(odometry.window_points(window));
  points.insert(points.end(), window.begin(), window.end());
  std::vector<vo::KeyframePose> window_keyframes(vo::kMaxKeyframes);
  window_keyframes.resize(odometry.window_keyframes(window_keyframes));
  for (const vo::KeyframePose& k : window_keyframes) keyframe_last[k.id] = k;

  summary.frames = frames;
  summary.points = points.size();
  summary.tau_h_s = odometry.tau().h, summary.tau_c_s = odometry.tau().c;
  summary.tau_c_standard_error_s = odometry.tau_standard_error();
  summary.intensity_scale = odometry.intensity_scale();
  summary.seconds = vo_seconds;

  std::string tum = "# bolo odometry: " + std::string(vo::to_string(config.photometric)) +
                    " (t tx ty tz qx qy qz qw, camera-to-world)\n";
  const auto tum_text = [&](std::vector<StampedPose> poses) {
    std::sort(poses.begin(), poses.end(), [](const StampedPose& a, const StampedPose& b) { return a.t < b.t; });  // a reversed run's come last to first
    std::string text = tum;
    for (const StampedPose& p : poses) text += tum_line(p);
    return text;
  };
  write_text(folder.path() / "trajectory.tum", tum_text(trajectory));
  // Every pose carried on its keyframe's last pose (a pose whose keyframe never had one, as written).
  std::vector<StampedPose> refined = trajectory;
  for (std::size_t k = 0; k < refined.size(); ++k) {
    const auto& [tie, moved] = pose_tie[k];
    const auto last = keyframe_last.find(tie.keyframe);
    if (last == keyframe_last.end()) continue;
    const vo::Se3 pose = last->second.T_wc * tie.T_kc * moved;
    if (is_sane(pose)) refined[k].T_wc = pose, ++summary.refined_poses;
  }
  write_text(folder.path() / "trajectory-refined.tum", tum_text(refined));
  // The keyframes of the maps the trajectory lies in (not those of initialisations that never completed).
  std::set<std::uint32_t> tied;
  for (const auto& [tie, moved] : pose_tie) tied.insert(tie.keyframe);
  std::vector<StampedPose> keyframes;
  for (const auto& [id, k] : keyframe_last)
    if (tied.count(id) != 0) keyframes.push_back({vo_time_to_recording(k.t_s), k.T_wc});
  write_text(folder.path() / "keyframes.tum", tum_text(keyframes));
  write_text(folder.path() / "stats.csv", stats.str());
  write_text(folder.path() / "points.ply", ply_text(points));

  // The plot: the estimate aligned (Sim(3)) onto the ground truth when there is one.
  const std::vector<std::size_t> frame_segment = tracking_segments(states);
  std::vector<std::size_t> pose_segment;
  for (const std::size_t frame : pose_frame) pose_segment.push_back(frame_segment[frame]);
  std::optional<std::vector<StampedPose>> truth;
  if (!input.live && fs::exists(input.dir / "poses.tum")) truth = read_tum(input.dir / "poses.tum");
  const std::vector<PlotSeries> series = trajectory_series(
      trajectory, pose_segment, truth, period, "estimate (" + std::string(vo::to_string(config.photometric)) + ")");
  write_text(folder.path() / "trajectory.svg", trajectory_svg("bolo odometry: " + (input.live ? input.name : input.dir.filename().string()) +
                                                             ", top view (x, y)", series));
  summary.tau_source = tau_source(ir, config.estimate_tau, !summary.shutter_taus.empty(), timing);
  nlohmann::json shutter_json = nlohmann::json::array();
  for (const auto& [t, tau] : summary.shutter_taus) shutter_json.push_back({{"t_s", t}, {"tau_s", tau}});
  nlohmann::json bridges_json = nlohmann::json::array();
  for (const auto& [from, to] : summary.scale_bridges) bridges_json.push_back({{"from_t_s", from}, {"to_t_s", to}});
  nlohmann::json j = {{"photometric", vo::to_string(config.photometric)},
                      {"reverse", options.reverse},
                      {"poses_at_read", options.poses_at_read},
                      {"frames", summary.frames},
                      {"posed", summary.posed},
                      {"posed_at_initialisation", summary.posed_at_initialisation},
                      {"refined_poses", summary.refined_poses},
                      {"online_poses_only", options.online_poses_only},
                      {"lost", summary.lost},
                      {"duplicates", summary.duplicates},
                      {"keyframes", summary.keyframes},
                      {"reinitialisations", summary.reinitialisations},
                      {"points", summary.points},
                      {"undistorted", !remap.identity()},
                      {"intensity_scale", summary.intensity_scale},
                      {"camera", {{"fx", remap.pinhole().fx},
                                  {"fy", remap.pinhole().fy},
                                  {"cx", remap.pinhole().cx},
                                  {"cy", remap.pinhole().cy}}},
                      {"tau_init_s", as_given(config.tau_init_s)},
                      {"tau_estimated", config.estimate_tau},
                      {"carry_coring", as_given(config.carry_coring)},
                      {"smoothing", config.smoothing},
                      {"max_keyframes", config.max_keyframes},
                      {"points_per_keyframe", vo::resolved(config).points_per_keyframe},
                      {"window_ba", config.window_ba},
                      {"marginalisation_prior", vo::builds_marginalisation_prior(config)},
                      {"retirement", vo::to_string(config.retirement)},
                      {"keyframe_parallax", vo::to_string(config.keyframe_parallax)},
                      {"scale_bridge", config.scale_bridge},
                      {"scale_bridges", bridges_json},
                      {"timing_from_options", summary.timing_from_options},
                      {"timing_assumed", summary.timing_assumed},
                      {"timing_assumed_s", summary.timing_assumed ? nlohmann::json(summary.assumed_half_period_s)
                                                                  : nlohmann::json(nullptr)},
                      {"tau_h_s", summary.tau_h_s},
                      {"tau_c_s", summary.tau_c_s},
                      {"tau_c_standard_error_s", summary.tau_c_standard_error_s > 0
                                                     ? nlohmann::json(summary.tau_c_standard_error_s)
                                                     : nlohmann::json(nullptr)},
                      {"shutter_events", summary.shutter_events},
                      {"carry_over_breaks", summary.carry_over_breaks},
                      {"tau_from_shutter_events", shutter_json},
                      {"tau_source", to_string(summary.tau_source)},
                      {"vo_seconds", summary.seconds},
                      {"arena_bytes", summary.arena_bytes}};
  // A recording's folder (bolo evaluate finds poses.tum there); a live source's spec.
  if (input.live)
    j["source"] = {{"spec", input.name}, {"live", true}, {"faults", input.live->faults}, {"skipped", input.live->skipped}};
  else
    j["recording"] = fs::absolute(fs::path(input.name)).lexically_normal().string();
  write_text(folder.path() / "summary.json", j.dump(2) + "\n");
  folder.commit();
  return summary;
}

}  // namespace
}  // namespace bolo::odo

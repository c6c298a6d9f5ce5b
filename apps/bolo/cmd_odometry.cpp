// bolo odometry SOURCE --out DIR --photometric none|affine|ir|ir-loop: monocular direct visual
// odometry (firmware/vo) over a recording or any other source hal::open_source opens.

#include <iomanip>
#include <memory>
#include <optional>

#include "bolo/commands.hpp"
#include "bolo/errors.hpp"
#include "bolo/frame_stack.hpp"
#include "bolo/odometry/run_odometry.hpp"
#include "bolo/progress.hpp"
#include "bolo/recording_source.hpp"
#include "bolo/registry.hpp"

namespace bolo::cli {

namespace fs = std::filesystem;

int run_odometry(const OdometryOptions& o, std::ostream& out) {
  odo::OdometryOptions options = o;  // the run's part, checked below
  const std::optional<fs::path> folder = recording_folder_or_live(o.input.string(), o.max_frames.has_value());
  if (folder) options.recording = *folder;
  vo::VoConfig& config = options.vo;
  if (!vo::parse_photometric(o.photometric_name.c_str(), config.photometric))
    fail("--photometric: unknown model '", o.photometric_name, "' (none, affine, ir, ir-loop)");
  // The ranges are the VO's (vo::invalid_reason); the VO holds these settings as floats, so a bound
  // itself (0.05) is in range.
  if (!vo::kTauInitRange.contains(config.tau_init_s))
    fail("--tau-init: must be within ", vo::kTauInitRange.min, "..", vo::kTauInitRange.max, " s, got ", config.tau_init_s);
  if (o.hfov_deg && !(*o.hfov_deg > 1.0 && *o.hfov_deg < 179.0))
    fail("--hfov: must be within 1..179 degrees, got ", *o.hfov_deg);
  if (o.exposure_s && !(*o.exposure_s > 0.0 && *o.exposure_s < 1.0))
    fail("--exposure: must be within 0..1 s (exclusive), got ", *o.exposure_s);
  if (o.readout_s && !(*o.readout_s >= 0.0 && *o.readout_s < 1.0))
    fail("--readout: must be within 0..1 s, got ", *o.readout_s);
  if (!vo::kIntensityScaleRange.contains(config.intensity_scale))
    fail("--intensity-scale: must be within ", vo::kIntensityScaleRange.min, "..", vo::kIntensityScaleRange.max,
         " (0: measured), got ", config.intensity_scale);
  if (!vo::kCarryCoringRange.contains(config.carry_coring))
    fail("--carry-coring: must be within ", vo::kCarryCoringRange.min, "..", vo::kCarryCoringRange.max,
         " (0: the full correction), got ", config.carry_coring);
  if (!vo::kSmoothingRange.contains(config.smoothing))
    fail("--smoothing: must be within ", vo::kSmoothingRange.min, "..", vo::kSmoothingRange.max, " passes, got ",
         config.smoothing);
  if (!vo::parse_retirement(o.retirement_name.c_str(), config.retirement))
    fail("--retirement: must be oldest or spread, got ", o.retirement_name);
  if (!vo::parse_keyframe_parallax(o.keyframe_parallax_name.c_str(), config.keyframe_parallax))
    fail("--keyframe-parallax: must be rms or quantile, got ", o.keyframe_parallax_name);
  if (config.points_per_keyframe != 0 && !vo::kPointsPerKeyframeRange.contains(config.points_per_keyframe))
    fail("--points-per-keyframe: must be 0 (one per 40 pixels, at most ", vo::kMaxDefaultPointsPerKeyframe, ") or within ",
         vo::kPointsPerKeyframeRange.min, "..", vo::kPointsPerKeyframeRange.max, ", got ", config.points_per_keyframe);
  if (!vo::kKeyframesRange.contains(config.max_keyframes))
    fail("--max-keyframes: must be within ", vo::kKeyframesRange.min, "..", vo::kKeyframesRange.max, ", got ",
         config.max_keyframes);
  if (o.reverse && (config.photometric == vo::Photometric::ir || config.photometric == vo::Photometric::ir_loop))
    fail("--reverse: the ir modes' carry-over runs forward in time (use none or affine)");
  if (o.poses_at_read && config.photometric != vo::Photometric::ir && config.photometric != vo::Photometric::ir_loop)
    fail("--poses-at-read: the ir modes only (their corrected image's instant is known from tau and the exposure)");
  Progress progress("odometry", 0, o.progress_bar);
  std::uint64_t total = 0;
  options.progress = [&](std::uint64_t done, std::uint64_t n) {
    total = n;
    progress.update(done);
  };
  const odo::OdometrySummary s =
      folder ? odo::run_odometry(options)
             : odo::run_odometry(options, [&] { return read_live_frames(o.input.string(), o.max_frames, o.max_faults); });
  progress.finish();
  out << "odometry: wrote " << o.output.string() << ": " << s.frames << " frames, " << s.posed << " posed, "
      << s.lost << " lost, " << (s.duplicates ? std::to_string(s.duplicates) + " repeated (skipped), " : std::string())
      << s.keyframes << " keyframes, " << s.points << " map points, "
      << s.reinitialisations << " restarts; photometric " << o.photometric_name << ", tau_h "
      << std::setprecision(4) << s.tau_h_s * 1e3 << " ms, tau_c " << s.tau_c_s * 1e3 << " ms; "
      << std::setprecision(3) << (s.seconds > 0 ? s.frames / s.seconds : 0.0) << " fps (VO only), arena "
      << s.arena_bytes / 1024 << " KiB\n";
  if (s.live) out << "odometry: live source " << o.input.string() << " (device faults in summary.json)\n";
  if (s.intensity_scale != 1.0 && config.intensity_scale == 0.0f)
    out << "odometry: thresholds scaled by " << std::setprecision(3) << s.intensity_scale
        << " (the frames' pixel noise is above " << vo::kNominalNoiseCounts << " counts)\n";
  if (s.ir_on_tone_mapped)
    out << "odometry: warning: the recording's units are counts8 (tone-mapped): the carry-over model "
           "needs the sensor's linear counts, and an AGC breaks it; affine is the model for such video\n";
  if (s.undistorted)
    out << "odometry: camera.json has lens distortion: frames resampled onto a pinhole (focal lengths x"
        << std::setprecision(4) << s.focal_scale << ")\n";
  if (!s.shutter_taus.empty()) {
    out << "odometry: tau from the step response after " << s.shutter_taus.size() << " of " << s.shutter_events
        << " shutter events (frames.csv ffc = 1):";
    for (const auto& [t, tau] : s.shutter_taus) out << " " << std::setprecision(4) << tau * 1e3 << " ms at " << t << " s;";
    out << " the carry-over pairs no longer move it\n";
  }
  if (s.tau_source == odo::TauSource::motion)
    out << "odometry: tau from camera motion alone (no shutter event or exposure change in the recording): its "
           "reading depends on how smooth the frames are (docs/odometry-study.md); flagged "
           "shutter events (frames.csv ffc = 1) or --fixed-tau --tau-init S from a calibration give a first-order tau\n";
  if (!s.scale_bridges.empty()) {
    out << "odometry: the camera centre held on its velocity over " << s.scale_bridges.size() << " look-around"
        << (s.scale_bridges.size() > 1 ? "s" : "") << " (the map's scale carried over them):";
    for (const auto& [from, to] : s.scale_bridges) out << " " << std::setprecision(4) << from << "-" << to << " s;";
    out << "\n";
  }
  if (s.timing_assumed > 0)
    out << "odometry: frames.csv has no exposure_s/readout_s for " << s.timing_assumed
        << " frames: assumed half the frame interval each (" << std::setprecision(4) << s.assumed_half_period_s * 1e3
        << " ms); tau is reported for that split (give --exposure/--readout if the camera's are known)\n";
  (void)total;
  return kExitOk;
}

Command add_odometry_command(CLI::App& parent) {
  auto o = std::make_shared<OdometryOptions>();
  CLI::App* app = add_command(
      parent, "odometry", "Monocular direct visual odometry with a microbolometer photometric model",
      "Runs the on-board VO (firmware/vo: direct sparse odometry, frame-to-keyframe alignment,\n"
      "epipolar depth search, sliding-window bundle adjustment) over a recording with camera.json\n"
      "(a lens with distortion, OpenCV's k1..k6, p1, p2: the frames are resampled onto a pinhole first) or\n"
      "over any other source of `bolo capture --help` (a camera, a transfer log: see below),\n"
      "and writes to DIR: trajectory.tum (camera-to-world, per posed frame, as tracked),\n"
      "trajectory-refined.tum (each of those poses carried on its keyframe's last pose, as DSO and\n"
      "ORB-SLAM write theirs at the end), keyframes.tum (their last poses), stats.csv (per frame:\n"
      "state, tracked points, keyframe flag, residual, tau estimates, time), points.ply (keyframe\n"
      "points, world), trajectory.svg (top view; with the ground truth, Sim(3)-aligned, when\n"
      "poses.tum exists; after a restart each tracking segment is its own line, aligned on its\n"
      "own) and summary.json. Photometric models:\n"
      "  none     brightness constancy on raw counts\n"
      "  affine   per-frame gain/offset (DSO)\n"
      "  ir       carry-over model raw_i - a*raw_{i-1} = b*u (paper Eq. 7), tau estimated online\n"
      "  ir-loop  the firmware corrector runs in front with the VO's current tau, which the VO refines\n"
      "The ir modes use exposure_s/readout_s from frames.csv; where a cell is empty, --exposure /\n"
      "--readout, else half the frame interval each (said on the output and counted in summary.json:\n"
      "alpha = exp(-t_r/tau) is what the frames fix, so tau is then reported for that split); on\n"
      "tone-mapped frames (units counts8) they warn: the model needs linear counts.\n"
      "Shutter events (ffc=1) and time gaps (> 1.5 frame periods) break the carry-over chain; such\n"
      "frames are tracked on raw counts with a free gain and offset, and the next with a free offset\n"
      "(a shutter event resets the camera's offsets). The frame after a shutter event is the scene's\n"
      "step response from the settled shutter: its contrast gives tau, which from then on follows\n"
      "those measurements (listed on the output and in summary.json) instead of the carry-over pairs.\n"
      "A frame identical to the one before (a camera or link sending a frame twice) is skipped (state\n"
      "'duplicate' in stats.csv, no pose) and breaks the chain for the frame after it.\n"
      "Each keyframe selects one point per 40 pixels, at most 500 (160x120: 480; 320x256 and larger:\n"
      "500), or --points-per-keyframe N.\n"
      "A live source (not a recording) is read first, to its end or --frames N (required for a camera\n"
      "that streams on; faulted frames are skipped and counted, more than --max-faults in a row give\n"
      "up), held in memory and run as a recording; frames.csv's columns are then each frame's header,\n"
      "--hfov gives the intrinsics, and summary.json names the source and its faults.\n\n"
      "Example:\n"
      "  bolo simulate out/street --scene street --trajectory drive --fps 60 --frames 300 --tau 0.012 --noise 3\n"
      "  bolo odometry out/street --out out/vo-ir --photometric ir\n"
      "  bolo odometry ../shared/data/real/lepton3-possum --out out/vo-possum --hfov 57\n"
      "  bolo odometry v4l2:/dev/video0 --frames 600 --out out/vo-lepton --hfov 57");
  app->add_option("SOURCE", o->input,
                  "Recording folder (recording.json, frames.npy, frames.csv, camera.json), file:REC, or a source "
                  "spec (flirone-log:DIR, v4l2:/dev/video0, ...)")
      ->required();
  app->add_option("--out", o->output, "Output folder (must not exist unless --overwrite)")->required();
  app->add_option("--photometric", o->photometric_name, "none, affine, ir or ir-loop (default none)");
  app->add_option("--tau-init", o->vo.tau_init_s, "Starting tau for the ir modes, seconds (default 0.010)");
  app->add_flag("--fixed-tau", [o](std::int64_t) { o->vo.estimate_tau = false; },
                "ir modes: tau is known (--tau-init) and not estimated");
  app->add_option("--hfov", o->hfov_deg,
                  "Horizontal field of view, degrees: an undistorted pinhole centred on the image, used instead "
                  "of camera.json (for recordings without one, e.g. Lepton 3: 57)");
  app->add_option("--exposure", o->exposure_s,
                  "ir modes: exposure (heating) time t_e, seconds, for frames with an empty exposure_s");
  app->add_option("--readout", o->readout_s,
                  "ir modes: readout (cooling) time t_r, seconds, for frames with an empty readout_s");
  app->add_option("--intensity-scale", o->vo.intensity_scale,
                  "Counts per count of the scale the VO's thresholds were tuned for (0, the default: from the "
                  "pixel noise, 1 up to 4 counts and noise/4 above)");
  app->add_option("--carry-coring", o->vo.carry_coring,
                  "ir modes: leave out of the tracking image the part of the carry-over correction within K "
                  "times its noise (0: the paper's full correction, whose inverse filter "
                  "multiplies the noise of still pixels)")
      ->capture_default_str();
  app->add_option("--smoothing", o->vo.smoothing,
                  "Passes of a 3x3 binomial low-pass over each tracking image, 0..3 (0: none; 1, the default, "
                  "damps the detail near the sampling limit that bilinear sampling misreads and cut "
                  "the ir modes' ATE by 40-50 % on the study's sequences: docs/odometry-study.md)")
      ->capture_default_str();
  app->add_option("--frames", o->max_frames, "Use only the first N frames (a live camera: read N frames)")
      ->check(not_negative());
  app->add_option("--max-faults", o->max_faults, "A live source's faulted frames in a row before giving up (default 50)");
  app->add_option("--max-keyframes", o->vo.max_keyframes,
                  "Keyframes in the sliding window, 2..8 (default 8; 6 is about a fifth faster and less accurate: docs/odometry-study.md)");
  app->add_option("--points-per-keyframe", o->vo.points_per_keyframe,
                  "Points each keyframe selects, 50..8000 (default 0: one per 40 pixels, at most 500; more cost "
                  "time in the depth search and the window BA, and on the study's drives bought accuracy only with "
                  "tau known: docs/odometry-study.md)");
  app->add_flag("--no-ba", [o](std::int64_t) { o->vo.window_ba = false; }, "Skip the sliding-window bundle adjustment (tracking and depth search only)");
  app->add_flag("--marginalisation-prior", o->vo.marginalisation_prior,
                "Keep a retired keyframe's information as a prior on the window (DSO's marginalisation) "
                "instead of dropping it; it needs the bundle adjustment (ignored with --no-ba)");
  app->add_option("--retirement", o->retirement_name,
                  "Which keyframe leaves a full window: spread (one much nearer its neighbours along the path than "
                  "the window's mean spacing, made for a turn; else the oldest) or oldest")
      ->capture_default_str();
  app->add_option("--keyframe-parallax", o->keyframe_parallax_name,
                  "What translation flow makes a keyframe: rms (of the newest keyframe's points) or quantile (the "
                  "flow three quarters of them stay below, or twice the threshold on the rms: for vehicles, where the "
                  "road just ahead would make a keyframe every ~0.5 m; on the study's 10-36 s drives it lowers the "
                  "ATE, on its look-around walks it raises it: docs/odometry-study.md)")
      ->capture_default_str();
  app->add_flag("--no-scale-bridge", [o](std::int64_t) { o->vo.scale_bridge = false; },
                "Keep the scale a look-around leaves the map with (by default, after a fast turn that takes the map "
                "out of view, the new view's map is scaled so that the camera's speed after the turn is its speed "
                "before: docs/odometry-study.md)");
  app->add_flag("--reverse", o->reverse,
                "Run the frames last to first (none, affine); trajectory.tum keeps the frames' times, so "
                "`bolo evaluate FORWARD --truth REVERSED/trajectory.tum` compares the two runs");
  app->add_flag("--online-poses-only", o->online_poses_only,
                "Write only the poses given as each frame came (what a live consumer gets); by default the frames "
                "the initialisation took after its solves last disagreed on the basin are posed too once it completes "
                "(their rotations, the camera centre on the way to the completing frame's), counted as "
                "posed_at_initialisation in summary.json");
  app->add_flag("--poses-at-read", o->poses_at_read,
                "ir modes: frames.csv's t_s is the instant each frame is read, the end of its exposure (bolo simulate "
                "--lag continuous): each pose, which stands for its corrected image's instant (the heating weights' "
                "centroid, 6.1 ms before the read at 60 Hz, tau 10 ms, a whole-period exposure), is carried to t_s "
                "along the camera's motion since the frame before (docs/odometry-study.md, \"A continuous lag\")");
  app->add_flag("--overwrite", o->overwrite, "Replace DIR if it exists");
  app->add_flag("--no-progress", [o](std::int64_t) { o->progress_bar = false; }, "Never draw the progress bar");
  return {app, [o](std::ostream& out) { return run_odometry(*o, out); }};
}

}  // namespace bolo::cli

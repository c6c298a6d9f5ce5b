#pragma once
// Runs the VO core over a recording, or over frames a caller read from another source and holds in
// memory (the host side of `bolo odometry`): feeds raw frames
// (resampled onto a pinhole first when camera.json has lens distortion, pinhole_remap.hpp) with
// their timing and carry-over chain state (broken where the corrector's rule breaks it,
// bolo/firmware/carry_over_rule.hpp), runs the firmware corrector in front for ir-loop with
// the VO's current tau, and writes trajectory.tum, stats.csv, points.ply, trajectory.svg and
// summary.json into the output folder (temporary folder + rename).

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <utility>
#include <vector>
#include <string>

#include "bolo/recording/recording.hpp"
#include "bolo/vo/config.hpp"

namespace bolo::odo {

// The VO's settings (vo::VoConfig, its defaults; the frame size and camera come from the input)
// and the run's own.
struct OdometryOptions {
  vo::VoConfig vo;
  std::filesystem::path recording;
  std::filesystem::path output;
  // Intrinsics from a horizontal field of view (pinhole, centred, square pixels) instead of
  // camera.json.
  std::optional<double> hfov_deg;
  // ir modes: the exposure / readout of frames whose frames.csv cell is empty (unknown). Without
  // them such a frame gets half the median frame interval for each (the simulator's default
  // split); the summary counts those frames.
  std::optional<double> exposure_s, readout_s;
  // The frames last to first (a check of the geometry without ground truth: the trajectory is
  // written at the frames' own times, to be compared with the forward run's); none and affine only,
  // since the carry-over runs forward in time.
  bool reverse = false;
  // Write only the poses the VO gave as each frame came (what a live consumer gets); by default
  // the frames an initialisation took are also posed once it completes (vo::Odometry's
  // initialisation_poses).
  bool online_poses_only = false;
  // ir modes: frames.csv's t_s is the instant each frame is read, the end of its exposure (as
  // `bolo simulate --lag continuous` writes it). A tracked pose stands for its corrected image's
  // instant, corrected_image_delay_s before that; each is carried to t_s along the camera's motion
  // since the frame before (docs/odometry-study.md, "A continuous lag").
  bool poses_at_read = false;
  bool overwrite = false;
  std::optional<std::uint64_t> max_frames;
  std::function<void(std::uint64_t done, std::uint64_t total)> progress;
};

// How long before the end of an exposure t_e the two-frame model's corrected image stands: the
// centroid of its heating weights exp(-(t_e - s) / tau_h) over the exposure (t_e / 2 for a short
// one).
double corrected_image_delay_s(double exposure_s, double tau_h_s);

// Where a run's tau comes from, and so how far to trust it: shutter_events and exposure_changes
// measure it at first order; motion only through how the points' image velocities change, which
// the frames' smoothness biases either way (docs/odometry-study.md, "τ"); fixed is --tau-init as given; none where
// the model has no tau (none, affine).
enum class TauSource { none, fixed, shutter_events, exposure_changes, motion };
const char* to_string(TauSource source);

struct OdometrySummary {
  std::uint64_t frames = 0, posed = 0, lost = 0, keyframes = 0, reinitialisations = 0;
  // Of the posed frames, those an initialisation took, posed once it completed.
  std::uint64_t posed_at_initialisation = 0;
  std::uint64_t refined_poses = 0;  // trajectory-refined.tum's poses carried on their keyframe's last pose
  std::uint64_t points = 0;  // in points.ply
  std::uint64_t duplicates = 0;  // frames repeating the previous one bit for bit (skipped by the VO)
  // ir modes: frames whose empty exposure_s / readout_s cell was filled from the options
  // (timing_from_options) or with half the frame interval (timing_assumed), and that value.
  std::uint64_t timing_from_options = 0, timing_assumed = 0;
  double assumed_half_period_s = 0;
  // camera.json has lens distortion: the frames were resampled onto a pinhole whose focal
  // lengths are the camera's times focal_scale.
  bool undistorted = false;
  double focal_scale = 1.0;
  double intensity_scale = 1.0;  // the VO's thresholds' scale, as used
  // An ir mode on tone-mapped frames (recording units counts8): the carry-over model needs the
  // sensor's linear counts (AGC breaks it).
  bool ir_on_tone_mapped = false;
  double tau_h_s = 0, tau_c_s = 0;
  double tau_c_standard_error_s = 0;  // 0: unknown (vo::Odometry::tau_standard_error)
  // Flagged shutter events (frames.csv ffc = 1 after the first frame), and for the ir modes the
  // tau each one's step response gave (time of the frame after the event, tau).
  std::uint64_t shutter_events = 0;
  std::vector<std::pair<double, double>> shutter_taus;
  // Frames after the first whose carry-over chain broke (fw::carry_over_between: shutter events,
  // skipped frame counters, time that stood still, went back or jumped over 1.5 frame periods).
  std::uint64_t carry_over_breaks = 0;
  TauSource tau_source = TauSource::none;
  // Look-arounds over which the camera centre was held on its velocity before the turn (the
  // times of the first and last held frames), and the frames held.
  std::vector<std::pair<double, double>> scale_bridges;
  std::uint64_t centre_held = 0;
  bool live = false;  // ran over LiveFrames
  double seconds = 0;        // VO time only (not I/O)
  std::size_t arena_bytes = 0;
};

// Frames of a live source (a camera, a transfer log), read whole by the caller: each frame's row as
// a recording of it would have (rec::RowClock) and its pixels, one frame after the other. There is
// no camera.json (the intrinsics come from --hfov) and no ground truth.
struct LiveFrames {
  std::string name;  // the source spec, as errors, the plot and summary.json name it
  std::uint32_t width = 0, height = 0;
  rec::Units units = rec::Units::counts;
  std::vector<rec::FrameRow> rows;
  std::vector<std::uint16_t> pixels;
  std::string faults;         // the source's fault counters, for summary.json
  std::uint64_t skipped = 0;  // frames skipped for a fault
};

// Throws Error (or bolo::rec::Error) naming the file/frame/field for bad input; nothing is
// left behind then. The first runs over options.recording, the second over the frames `read`
// returns (called once the output folder is known to be writable; options.recording and
// max_frames are not used); both run the frames the same way (the frame period, for gaps and
// assumed timing, is the median interval of the frames used).
OdometrySummary run_odometry(const OdometryOptions& options);
OdometrySummary run_odometry(const OdometryOptions& options, const std::function<LiveFrames()>& read);

}  // namespace bolo::odo

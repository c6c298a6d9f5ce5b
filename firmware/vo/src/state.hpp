#pragma once
// The VO's working state, shared by its parts (tracker, initialiser, depth search, window BA,
// tau estimator). Everything here lives in the arena.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>

#include <Eigen/Core>

#include "bolo/vo/carry_model.hpp"
#include "bolo/vo/config.hpp"
#include "bolo/vo/image.hpp"
#include "bolo/vo/odometry.hpp"
#include "bolo/vo/point_selector.hpp"
#include "bolo/vo/se3.hpp"

namespace bolo::vo {

// `leaving`: inside the window BA only, an active point its last trial found to fit most keyframes
// badly; it leaves the map if that trial is accepted.
enum class PointStatus : std::uint8_t { empty, immature, active, leaving };

struct Point {
  float u = 0, v = 0;  // host pixel, level 0
  float idepth = 1, idepth_min = 0, idepth_max = -1;  // max < 0: unbounded
  float energy = 0;      // last pattern energy when tracked
  float quality = 0;     // immature: second-best / best energy of the last search
  PointStatus status = PointStatus::empty;
  std::uint8_t good = 0, bad = 0;
  std::uint8_t still_matches = 0;  // immature: frames it matched where no baseline could place it
  bool inlier = false;   // in the last tracking
};

// A window point as the tracker sees it: reprojected into the newest keyframe (the tracking
// reference), so the patterns compared with the frame come from the keyframe nearest to it.
struct RefPoint {
  float u = 0, v = 0, idepth = 1;  // in the reference keyframe, level 0
  std::uint32_t source = 0;        // host slot << 16 | point index
  bool in_view = false;            // tracking: visible at the start of the current pyramid level
  float refv[kPattern] = {};       // the reference keyframe's pattern at the current level
};

struct Keyframe {
  bool used = false;
  std::uint32_t id = 0;
  Se3 T_cw;
  double a = 0, b = 0;  // affine brightness, absolute
  double t_s = 0, exposure_s = 0, readout_prev_s = 0;
  bool chain_ok = false;
  Pyramid pyramid;
  std::span<Point> points;
  std::uint32_t count = 0;  // points used in `points`
  bool settled = true;  // made kTimingSettleFrames or more after a change of timing (same_level)
};

// Pattern offsets in pixels (own choice: a spread diamond that samples both gradient directions).
inline constexpr float kPatternX[kPattern] = {0, 2, -2, 0, 0, 1, -1, 1};
inline constexpr float kPatternY[kPattern] = {0, 0, 0, 2, -2, 1, -1, -1};

struct Scaled {
  float fx, fy, cx, cy;
};
// The ir modes: the tracking image is the scene estimate of the two-frame carry-over model.
inline bool uses_carry_model(const VoConfig& c) {
  return c.photometric == Photometric::ir || c.photometric == Photometric::ir_loop;
}
// Frames from a change of exposure or readout (the change frame itself first) whose image holds
// part of the carry-over of the frames before the change, which the scene estimate removes right
// only at the true tau: it decays by alpha (0.4-0.6 at 60 Hz) a frame, to a few per cent of its
// first-frame share by then.
inline constexpr std::uint32_t kTimingSettleFrames = 4;
// More than 1 %: timings read from a camera's timestamps jitter.
inline bool timing_differs(double before_s, double now_s) {
  return before_s > 0 && now_s > 0 && std::abs(now_s - before_s) > 0.01 * before_s;
}

inline Scaled camera_at(const Camera& c, std::uint32_t level) {
  const float s = 1.0f / static_cast<float>(1u << level);
  return {c.fx * s, c.fy * s, (c.cx + 0.5f) * s - 0.5f, (c.cy + 0.5f) * s - 0.5f};
}
// H += w v v^T on the upper triangle, with Eigen's rankUpdate's arithmetic (a column at a time,
// w v_c first) but inline: its out-of-line call per residual was a quarter of the initialiser's
// instructions.
template <int N>
inline void add_weighted_outer_upper(Eigen::Matrix<double, N, N>& H, const Eigen::Matrix<double, N, 1>& v, double w) {
  for (int c = 0; c < N; ++c) {
    const double a = w * v[c];
    for (int r = 0; r <= c; ++r) H(r, c) += a * v[r];
  }
}

// The upper median of v[0 .. n) (0 when n is 0); reorders v.
inline float upper_median(float* v, std::size_t n) {
  if (n == 0) return 0.0f;
  std::nth_element(v, v + n / 2, v + n);
  return v[n / 2];
}
// The tracker's outlier cut on a point's pattern energy at a pyramid level (tracker.cpp); coarse
// levels start far from the optimum and cut more loosely.
// The configured thresholds in counts times the intensity scale (VoConfig::intensity_scale).
inline float huber_threshold(const State& s);
inline float gradient_weight_c(const State& s);

inline float tracking_cutoff(float huber, std::uint32_t level) {
  return static_cast<float>(kPattern) * huber * huber * (level > 0 ? 12.0f : 6.0f);
}
inline float huber_weight(float r, float k) {
  const float a = r < 0 ? -r : r;
  return a <= k ? 1.0f : k / a;
}

// A pattern's residuals against a reference pattern seen with a gain and offset,
// r = value - (gain (reference - reference_offset) + offset), their Huber-and-gradient weights
// and robust energy (summed in pattern order), four pattern pixels at a time (lane by lane the
// arithmetic of huber_weight()). value, gx, gy, r, w: 16-byte aligned, kPattern long.
inline float pattern_residuals(const float* value, const float* gx, const float* gy, const float* reference,
                               float gain, float reference_offset, float offset, float hub, float c2, float* r,
                               float* w) {
  alignas(16) float terms[kPattern];
  for (std::uint32_t h = 0; h < kPattern; h += 4) {
    using A = Eigen::Map<Eigen::Array4f, Eigen::Aligned16>;
    using C = Eigen::Map<const Eigen::Array4f, Eigen::Aligned16>;
    const Eigen::Array4f rr = C(value + h) - (gain * (Eigen::Map<const Eigen::Array4f>(reference + h) - reference_offset) + offset);
    const Eigen::Array4f ra = rr.abs();
    const Eigen::Array4f hw = (ra <= hub).select(Eigen::Array4f::Ones(), hub / ra);
    const Eigen::Array4f gxh = C(gx + h), gyh = C(gy + h);
    A(r + h) = rr;
    A(w + h) = hw * c2 / (c2 + gxh * gxh + gyh * gyh);
    A(terms + h) = hw * rr * rr * (2.0f - hw);
  }
  float energy = 0;
  for (std::uint32_t j = 0; j < kPattern; ++j) energy += terms[j];
  return energy;
}

// A point's pose block D S D^T, D = [du dv] (the centre pixel's projection Jacobian, 6 x 2) and
// S = [sxx sxy; sxy syy] (its pattern's weighted gradient structure), added to the upper triangle
// of H's leading 6 x 6 as two products: H(q, e) += du[q] m0[e] + dv[q] m1[e].
template <typename Matrix>
inline void add_pose_block_upper(Matrix& H, const float* du, const float* dv, float sxx, float sxy, float syy) {
  float m0[6], m1[6];
  for (int q = 0; q < 6; ++q) m0[q] = sxx * du[q] + sxy * dv[q], m1[q] = sxy * du[q] + syy * dv[q];
  for (int q = 0; q < 6; ++q)
    for (int e = q; e < 6; ++e) H(q, e) += du[q] * m0[e] + dv[q] * m1[e];
}

inline constexpr std::uint32_t kMaxBaParams = 8 * kMaxKeyframes;
// Per window point in the BA scratch: H_rr, g_r, backup inverse depth, coupling to kf params,
// the host pattern and two counts (window_ba.cpp lays the row out).
inline constexpr std::size_t kBaStride = 3 + kMaxBaParams + kPattern + 2;
using BaMatrix = Eigen::Matrix<double, kMaxBaParams, kMaxBaParams>;
using BaVector = Eigen::Matrix<double, kMaxBaParams, 1>;

// A posed frame as the scale bridge remembers it (scale_bridge.cpp).
struct MotionSample {
  double t_s = 0;
  Vec3 centre = Vec3::Zero();  // camera centre, world
  float rotation_rate = 0;     // rad/s since the frame before
  float rotation = 0;          // rad since the frame before
};
inline constexpr std::uint32_t kMotionHistory = 96;  // 1.6 s at 60 Hz
// The camera's velocity carried over a look-around (scale_bridge.cpp).
struct ScaleBridge {
  bool velocity_known = false;
  Vec3 velocity = Vec3::Zero();     // world, map units a second, of the last steady stretch
  Vec3 from_centre = Vec3::Zero();  // that stretch's last centre, at from_t_s
  double from_t_s = 0;
  bool after_break = false;          // the map broke in a turn: carried until the camera is steady
  double turn_start_s = 0, break_s = 0;
  bool keyframe_since_turn = false;  // a keyframe was made on a steady frame since the break
  bool suspended = false;            // a frame tracked free while held (odometry.cpp)
};

// One per VO, in the arena: its fields stay grouped by what they are for rather than ordered for
// the 32 bytes of padding that would save.
struct State {  // NOLINT(clang-analyzer-optin.performance.Padding)
  VoConfig cfg;
  Keyframe kf[kMaxKeyframes];
  std::uint32_t order[kMaxKeyframes] = {};  // slots, oldest first
  std::uint32_t kf_count = 0;
  std::uint32_t kf_created = 0;

  Pyramid frame;                    // tracking image of the current frame
  TexelImage frame_texels[8];       // the same, value and gradients interleaved (tracker, depth search)
  std::span<float> raw, raw_prev, raw_prev2;  // raw counts of this and the two previous frames
  bool have_prev = false;
  // The last frame repeated its predecessor bit for bit: the sensor frame that followed that
  // predecessor was never delivered, so the next frame has no known carry-over.
  bool predecessor_missing = false;
  std::span<std::uint8_t> occupied;
  std::span<PixelPoint> candidates;
  SelectorScratch selector;
  std::span<WorldPoint> retired;
  std::size_t retired_count = 0;
  std::span<RefPoint> ref;   // tracking reference: the window's active points in the newest keyframe
  std::uint32_t ref_count = 0;
  double ref_mean_idepth = 0;  // of the reference's points: how far a pose step moves them (tracker)
  bool ref_dirty = true;     // keyframes, poses or depths changed since it was built
  std::span<float> ba_hxr;  // per window point: coupling to the keyframe parameters (BA)
  std::span<std::uint32_t> ba_index;
  BaMatrix ba_H;
  BaVector ba_b;
  // What retired keyframes left on the window (window_ba.cpp): a Gaussian on the keyframe
  // parameters, 8 a slot, in the BA's half-gradient convention (energy/2 ~ b.d + d.H.d/2),
  // d the parameters' offsets from the linearisation point (left pose increment, a, b).
  struct MarginalPrior {
    BaMatrix H = BaMatrix::Zero();
    BaVector b = BaVector::Zero();
    Se3 T_cw[kMaxKeyframes];
    double a[kMaxKeyframes] = {}, b_offset[kMaxKeyframes] = {};
    bool in_prior[kMaxKeyframes] = {};  // the slot's rows are not all zero
    bool set = false;
  } prior;
  BaMatrix ba_prior_H;  // the prior's Hessian in the BA's window order

  // Motion
  Se3 T_cw;                    // current frame
  Se3 motion;                  // last inter-frame motion T_cur_prev, over motion_dt_s
  double motion_dt_s = 0;      // the time `motion` spans (0: unknown)
  double pose_t_s = 0;         // the time of the frame T_cw belongs to
  Se3 last_good;               // last tracked pose (restarts anchor here)
  double a = 0, b = 0;
  std::uint32_t lost_frames = 0;
  std::uint32_t frames_since_kf = 0, inliers_after_kf = 0;
  double since_kf_s = 0;   // the time those frames span
  bool initialised = false;
  std::uint32_t init_frames = 0;
  // The map began as a rotation about the camera's centre and the camera has not translated since
  // (initializer.cpp): none of its points has a depth of its own.
  bool map_without_baseline = false;
  Se3 map_origin;  // world to camera at the map's first keyframe
  std::uint32_t frames_since_timing_change = 0xffffffffu;  // 0: this frame's timing changed
  bool brightness_level_unknown = false;  // a, b are of a frame without its reference's level (same_level)
  double offset_step = 0;  // ir modes: the camera offset's change since the newest keyframe (shutter)
  float last_rms = 0;

  // The scale bridge (scale_bridge.cpp): the last posed frames, newest at motion_head - 1.
  MotionSample motion_history[kMotionHistory];
  std::uint32_t motion_head = 0, motion_count = 0;
  ScaleBridge bridge;

  Se3 T_prev;                  // the previous frame's pose, when prev_posed
  bool prev_posed = false, posed = false;

  // Tau (ir modes): estimate and the sums it is solved from (tau_estimator.cpp)
  Tau tau;
  double tau_sab = 0, tau_sbb = 0, tau_sbbr = 0;
  double tau_sbb_total = 0;  // tau_sbb before the noise correction
  bool offset_pending = false;  // ir modes: no frame was posed with a free offset since the chain broke
  std::uint32_t shutter_measurements = 0;  // shutter events whose step response gave tau
  double shutter_tau = 0;                  // their running mean (seconds)
  double noise_var = 0;      // temporal pixel noise, counts^2 (0 until measured; noise_estimator.cpp)
  std::span<float> noise_scratch;
  std::span<std::uint8_t> unchanged_frames;  // per pixel: checks its raw value stayed the same (tau estimator)
  bool stuck_check_due = false;              // the check runs every other frame
  std::uint32_t stuck_pixels = 0;            // found by the last check (none: no point is tested)
  CarryCoefficients carry;  // of the current frame
  bool chain_ok = false;       // raw_prev is this frame's predecessor on the sensor
  bool chain_ok_prev = false;  // raw_prev2 is raw_prev's predecessor
  double exposure_s = 0, readout_prev_s = 0, t_s = 0;
  double exposure_prev_s = 0;  // the previous frame's
  double readout_prev2_s = 0;  // the readout before the previous frame (its readout_prev_s)
  float intensity = 1;              // the intensity scale in use (VoConfig::intensity_scale)
  bool intensity_pending = false;   // to be measured from the pixel noise
  std::uint32_t raw_frames = 0;     // frames loaded while it is pending
  double scene_scale = 1;  // the factor the current image used
};

// The factor that takes the scene estimate u = (raw - alpha raw_prev) / beta to the raw level a
// static pixel reads at the frame's timing, beta / (1 - alpha) with the current tau: the tracking
// images then keep the keyframes' level whatever tau is and however t_e and t_r split the frame
// period (exactly 1 when they are equal, tau_h being kept equal to tau_c).
double scene_level_scale(const State& s);
// The current frame's tracking image has the level of keyframe kf's (in the ir modes whatever
// tau is): both settled, at the same timing. The ir modes' images have the raw static level of
// their timing (scene_level_scale), and the raw static levels of two timings differ by a factor
// of the true tau: across a change of timing, and on the frames right after one, the gain and
// offset are estimated (tracker, initialiser; affine's initialiser too).
bool same_level(const State& s, const Keyframe& kf);

// Sets s.intensity from the current frame's pixel noise (odometry.cpp), for
// VoConfig::intensity_scale 0; leaves it pending while the noise cannot be measured yet.
void measure_intensity_scale(State& s);

inline float huber_threshold(const State& s) { return s.cfg.huber_counts * s.intensity; }
inline float gradient_weight_c(const State& s) { return s.cfg.gradient_c * s.intensity; }

// Lays the whole state out over an arena (odometry.cpp); nullptr when it does not fit.
class Arena;
State* lay_out(const VoConfig& config, Arena& arena);

// After the frame's level 0 is filled: its pyramid, gradients and texels (odometry.cpp).
// The ir mode's tracking image: level 0 of s.frame becomes the scene estimate
// (raw - alpha raw_prev) / beta, with s.carry from s.tau and the frame's times, at the static
// level of the reference timing (times s.scene_scale = scene_level_scale(s)).
void write_scene_estimate(State& s);
void build_frame_images(State& s);

// The constant-velocity guess's step from T_cw's frame to the current one: `motion` scaled to
// the time between them when frames were dropped or repeated in between (odometry.cpp).
Se3 motion_step(const State& s);
// T_cw was just set for the current frame, from `previous` (the pose of the frame before):
// the motion model and the time it spans.
void record_motion(State& s, const Se3& previous);

// Parts (one file each).
struct TrackResult {
  Se3 T_cw;
  double a = 0, b = 0;
  float rms = 0;
  double mean_energy = 0;  // robust energy per point of the last level's point set
  std::uint32_t visible = 0, inliers = 0;
  std::uint32_t level = 0;  // the last level tracked
  bool ok = false;
};
// Coarse to fine down to `last_level` (0: the full tracking; above 0: a quick look at a guess,
// mean_energy and the pose at that level only, ok = finite). `resume`: the result of an earlier
// call with the same guess, a, b and free_offset that stopped at resume->level; the levels down
// to it are not repeated (the tracking continues from its pose: the same result as a full call).
// Brightness parameters a frame may change that the photometric mode otherwise holds (ir modes:
// a frame without its sensor predecessor has an unknown carry-over, so its raw counts are
// tracked with a free gain and offset; the frame after it, whose scene estimate has the camera's
// offset since then, with a free offset).
struct FreeBrightness {
  bool gain = false, offset = false;
};
TrackResult track_frame(State& s, Se3 guess, double a, double b, FreeBrightness free,
                        std::uint32_t last_level = 0, const TrackResult* resume = nullptr);
// Median inverse depth of the window's active points (0 when there are none; ba_hxr is its scratch).
float typical_idepth(State& s);
// The baseline a map needs, as the flow it causes at the typical depth (pixels, level 0).
double baseline_flow_needed(const State& s);
// Which keyframe leaves a full window (its position in s.order, oldest first): the oldest, unless
// a keyframe between it and the two newest lies much nearer a neighbour along the path than the
// window's mean spacing (Retirement::spread). Such a keyframe was made for a turn, not for the
// distance travelled, and adds no baseline, while the oldest holds the window's longest one and,
// after a look-around, the view the camera comes back to. The most crowded such keyframe leaves.
std::uint32_t keyframe_to_retire(State& s);
// Rebuilds the tracking reference (s.ref) from the window's active points.
void build_tracking_reference(State& s);
// Returns true once the map is initialised from the first keyframe and the current frame.
bool initialise_step(State& s);
void start_initialisation(State& s);
// Clears map_without_baseline once the tracked camera has moved as far from the map's first
// keyframe as the initialisation's baseline.
void follow_map_baseline(State& s);
// extra_margin_px widens every match's interval (scale_bridge.cpp: a held turn's frames).
void search_immature_points(State& s, float extra_margin_px = 0.0f);
void activate_mature_points(State& s, std::uint32_t tracked_points);
void window_bundle_adjustment(State& s);
// Scale bridge (VoConfig::scale_bridge): each tracked frame's centre and rotation rate, from the
// pose of the frame before (`dt_s` earlier), and the velocity of the last steady stretch; a break
// of the map (called where a keyframe places points without a baseline on a map that had depths);
// while the velocity is carried (a fast turn, and after a break until the camera is steady), the
// tracker's prior weight on the translation and a guess with the carried centre (else `normal`
// and the guess itself); whether the velocity is carried; the depth search's extra margin on the current frame (pixels: on a fast
// turn's frames, a share of the rotation since the frame before); and, after each tracked frame,
// the end of a break's carry (returns true when it ended).
void record_motion_sample(State& s, const Se3& previous, double dt_s);
void note_map_break(State& s);
double translation_prior_weight(const State& s, double normal);
Se3 held_guess(const State& s, Se3 guess);
bool centre_carried(const State& s);
float depth_search_margin(const State& s);
bool update_bridge(State& s, bool keyframe_made);
// Before the oldest keyframe leaves the window: its points' observations, the points and then
// its own parameters eliminated, join the marginalisation prior on the remaining keyframes.
void marginalise_oldest_keyframe(State& s);
void clear_marginal_prior(State& s);
// The prior's energy at the current keyframe parameters, in the photometric energy's units
// (0 without a prior); exposed for tests.
double marginal_prior_energy(const State& s);
// The window's robust photometric energy at the current parameters, with the Gauss-Newton system
// of the keyframe parameters (before the points are eliminated) left in s.ba_H (lower and upper
// blocks) and s.ba_b; keyframe k's 8 parameters (left pose increment, a, b) start at 8 * its
// place in s.order. What window_bundle_adjustment() solves, less the marginalisation prior;
// exposed for tests.
double window_system(State& s);
void refine_tau(State& s);
// A shutter event's step response gave `tau_s` (tau_estimator.cpp; 0: none in range): from the
// first such measurement on, tau follows them and the carry-over pairs no longer move it. Returns
// whether it was taken (one far from the current estimate is not).
bool take_shutter_measurement(State& s, double tau_s);
// Per pixel, the consecutive checks (every other frame) at which its raw value stayed exactly the
// same as the frame before (tau_estimator.cpp): refine_tau leaves out samples near stuck pixels.
// Called for every frame after the first.
void count_unchanged_frames(State& s);
// Updates noise_var from the current and the two previous raw frames (noise_estimator.cpp);
// noise_scratch holds noise_block_count() floats.
std::size_t noise_block_count(std::uint32_t width, std::uint32_t height);
void update_noise_variance(State& s);
// The current frame's own estimate (no averaging over frames); negative when it cannot be
// measured (too few flat blocks).
double frame_noise_variance(State& s);
std::uint32_t new_keyframe_slot(State& s);
// Appends a keyframe's active points (world coordinates) to the retired-points output.
void retire_points(State& s, const Keyframe& old);
void make_keyframe(State& s, std::uint32_t slot, bool select_points_now);

}  // namespace bolo::vo

// The frame loop of the VO and the keyframe bookkeeping; the numerical parts live in their own
// files (tracker, initializer, depth_search, window_ba, tau_estimator).

#include "bolo/vo/odometry.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <new>

#include "bolo/vo/arena.hpp"
#include "state.hpp"

namespace bolo::vo {

const char* to_string(TrackingState state) {
  switch (state) {
    case TrackingState::initialising: return "initialising";
    case TrackingState::tracking: return "tracking";
    case TrackingState::lost: return "lost";
    case TrackingState::duplicate: return "duplicate";
  }
  return "?";
}

namespace {

constexpr std::uint32_t kLostFramesBeforeRestart = 8;
constexpr double kMinKeyframeSpacingS = 3.0 / 30.0;
// The translation's parallax that makes a keyframe, as a share of (width + height) in pixels.
constexpr double kKeyframeTranslationFlow = 0.03;
constexpr double kKeyframeFullFlow = 0.08;  // ... and the whole motion's (a turn), the same share
constexpr double kMaxStepFlow = 0.06;  // median translation flow per frame, share of width + height
constexpr float kRetrackRatio = 1.5f;  // the constant-velocity guess stands if its rms is within this of the last frame's
constexpr std::uint32_t kIntensityMeasureFrames = 30;  // the intensity scale stays 1 if unmeasured by then

// The points tracked at the next keyframe if they keep leaving the view as fast as since the last.
std::uint32_t tracked_at_next_keyframe(const State& s, std::uint32_t tracked) {
  const std::uint32_t lost = s.loop.inliers_after_kf > tracked ? s.loop.inliers_after_kf - tracked : 0;
  return tracked > lost ? tracked - lost : 0;
}

std::size_t plane(const VoConfig& c) { return std::size_t{c.width} * c.height; }

}  // namespace

State* lay_out(const VoConfig& config, Arena& arena) {
  const VoConfig c = resolved(config);
  auto state = arena.take<State>(1);
  if (state.empty()) return nullptr;
  State& s = state[0];
  s.cfg = c;
  s.intensity = c.intensity_scale > 0 ? c.intensity_scale : 1.0f;
  s.intensity_pending = !(c.intensity_scale > 0);
  const std::size_t pyr = pyramid_floats(c.width, c.height, c.levels);
  const std::size_t ppk = c.points_per_keyframe;
  auto frame = arena.take<float>(pyr);
  if (!frame.empty()) s.current.frame = make_pyramid(frame, c.width, c.height, c.levels);
  auto texels = arena.take<Texel>(texel_count(c.width, c.height, c.levels));
  if (!texels.empty()) make_texels(texels, c.width, c.height, c.levels, s.current.frame_texels);
  s.current.raw = arena.take<float>(plane(c));
  s.current.raw_prev = arena.take<float>(plane(c));
  s.current.raw_prev2 = arena.take<float>(plane(c));
  s.noise.scratch = arena.take<float>(noise_block_count(c.width, c.height));
  s.tau_est.unchanged_frames = arena.take<std::uint8_t>(plane(c));
  s.selection.occupied = arena.take<std::uint8_t>(plane(c));
  s.selection.candidates = arena.take<PixelPoint>(ppk);
  s.selection.scratch.block_threshold = arena.take<float>(selector_block_count(c.width, c.height));
  s.selection.scratch.histogram = arena.take<std::uint16_t>(64);
  for (std::uint32_t k = 0; k < c.max_keyframes; ++k) {
    auto storage = arena.take<float>(pyr);
    if (!storage.empty()) s.kf[k].pyramid = make_pyramid(storage, c.width, c.height, c.levels);
    s.kf[k].points = arena.take<Point>(ppk);
  }
  s.retired.points = arena.take<WorldPoint>(std::size_t{c.max_keyframes} * ppk);  // a restart retires all
  // The window BA's rows, or the initialiser's 8 floats a point plus two depth backups.
  s.scratch = arena.take<float>(std::max(std::size_t{c.max_keyframes} * ppk * kBaStride, ppk * 10));
  s.ba.index = arena.take<std::uint32_t>(std::size_t{c.max_keyframes} * ppk);
  s.ref.points = arena.take<RefPoint>(std::size_t{c.max_keyframes} * ppk);
  s.tau_est.tau.h = s.tau_est.tau.c = c.tau_init_s;
  return arena.failed() ? nullptr : &s;
}

namespace {

void copy_pyramid(const Pyramid& from, Pyramid& to, const VoConfig& c) {
  std::memcpy(to.level[0].value.data, from.level[0].value.data,
              pyramid_floats(c.width, c.height, c.levels) * sizeof(float));
}

Vec3 world_point(const Keyframe& kf, const Point& p, const Camera& cam) {
  const Vec3 n((p.u - cam.cx) / cam.fx, (p.v - cam.cy) / cam.fy, 1.0);
  return kf.T_cw.inverse() * (n / p.idepth);
}

// Pixel flow of the latest keyframe's points to the current frame.
struct KeyframeFlow {
  double translation_rms = 0;  // of the translation alone
  double translation_p75 = 0;  // three quarters of the points stay below it (quantile rule only)
  double full_rms = 0;         // of the whole motion
};
KeyframeFlow keyframe_flow(State& s) {
  const Keyframe& kf = s.kf[s.order[s.kf_count - 1]];
  const Se3 M = s.motion.T_cw * kf.T_cw.inverse();
  const Scaled k = camera_at(s.cfg.camera, 0);
  const bool quantile = s.cfg.keyframe_parallax == KeyframeParallax::quantile;
  float* squared = s.scratch.data();  // at least ten floats a keyframe point (lay_out)
  double st = 0, srt = 0;
  std::uint32_t points = 0;
  for (std::uint32_t i = 0; i < kf.count; ++i) {
    const Point& p = kf.points[i];
    if (p.status == PointStatus::empty || p.idepth <= 0) continue;
    const Vec3 n((p.u - k.cx) / k.fx, (p.v - k.cy) / k.fy, 1.0);
    const Vec3 Xt = n + M.t * p.idepth, Xrt = M.R * n + M.t * p.idepth;
    if (Xt.z() <= 1e-6 || Xrt.z() <= 1e-6) continue;
    const double dut = k.fx * (Xt.x() / Xt.z() - n.x()), dvt = k.fy * (Xt.y() / Xt.z() - n.y());
    const double dur = k.fx * (Xrt.x() / Xrt.z() - n.x()), dvr = k.fy * (Xrt.y() / Xrt.z() - n.y());
    if (quantile) squared[points] = static_cast<float>(dut * dut + dvt * dvt);
    st += dut * dut + dvt * dvt, srt += dur * dur + dvr * dvr, ++points;
  }
  KeyframeFlow flow;
  if (points == 0) return flow;
  flow.translation_rms = std::sqrt(st / points);
  flow.full_rms = std::sqrt(srt / points);
  if (!quantile) return flow;
  float* const q75 = squared + points * 3 / 4;
  std::nth_element(squared, q75, squared + points);
  flow.translation_p75 = std::sqrt(double{*q75});
  return flow;
}

// Median pixel flow that the translation of `step` (between two frames) causes on the window's
// active points. A video-rate camera cannot make it large; a tracker that drifts towards infinite
// translation (every point collapses onto one pixel) makes it huge.
double step_translation_flow(State& s, const Se3& step) {
  const Scaled k = camera_at(s.cfg.camera, 0);
  float* flows = s.scratch.data();
  std::size_t n = 0;
  for (const Keyframe& host : s.kf) {
    if (!host.used) continue;
    const Se3 H = s.motion.T_cw * host.T_cw.inverse();
    for (std::uint32_t i = 0; i < host.count && n < s.scratch.size(); ++i) {
      const Point& p = host.points[i];
      if (p.status != PointStatus::active) continue;
      const Vec3 X = H * (Vec3((p.u - k.cx) / k.fx, (p.v - k.cy) / k.fy, 1.0) / p.idepth);
      if (X.z() <= 1e-6) continue;
      const Vec3 Y = X + step.t;
      if (Y.z() <= 1e-6) {
        flows[n++] = 1e6f;
        continue;
      }
      const double du = k.fx * (Y.x() / Y.z() - X.x() / X.z()), dv = k.fy * (Y.y() / Y.z() - X.y() / X.z());
      flows[n++] = static_cast<float>(std::sqrt(du * du + dv * dv));
    }
  }
  return upper_median(flows, n);
}

std::uint32_t active_in_window(const State& s) {
  std::uint32_t n = 0;
  for (const Keyframe& kf : s.kf)
    if (kf.used)
      for (std::uint32_t i = 0; i < kf.count; ++i) n += kf.points[i].status == PointStatus::active;
  return n;
}

}  // namespace

// A keyframe leaving the window: its last pose, and its active points as map output.
void retire_keyframe(RetiredPoints& retired, const Keyframe& old, const Camera& camera) {
  if (retired.keyframe_count < kMaxKeyframes) retired.keyframes[retired.keyframe_count++] = {old.id, old.t_s, old.T_cw.inverse()};
  for (std::uint32_t i = 0; i < old.count && retired.count < retired.points.size(); ++i) {
    const Point& p = old.points[i];
    if (p.status != PointStatus::active || p.idepth <= 0) continue;
    const Vec3 X = world_point(old, p, camera);
    retired.points[retired.count++] = {static_cast<float>(X.x()), static_cast<float>(X.y()), static_cast<float>(X.z()),
                                    old.pyramid.level[0].value.at(static_cast<std::uint32_t>(p.u), static_cast<std::uint32_t>(p.v))};
  }
}

std::uint32_t new_keyframe_slot(MapCore& s, RetiredPoints& retired, BaSystem& ba, MarginalPrior& prior) {
  if (s.kf_count == s.cfg.max_keyframes) {
    // Retire a keyframe; its active points leave the window as map output.
    if (builds_marginalisation_prior(s.cfg)) marginalise_oldest_keyframe(s, ba, prior);
    const std::uint32_t leaving = keyframe_to_retire(s);
    Keyframe& old = s.kf[s.order[leaving]];
    retire_keyframe(retired, old, s.cfg.camera);
    old.used = false;
    for (std::uint32_t k = leaving + 1; k < s.kf_count; ++k) s.order[k - 1] = s.order[k];
    --s.kf_count;
  }
  for (std::uint32_t k = 0; k < s.cfg.max_keyframes; ++k)
    if (!s.kf[k].used) return k;
  return 0;  // unreachable: kf_count < max_keyframes here
}

void make_keyframe(MapCore& s, const KeyframeParts& parts, std::uint32_t slot, bool select_points_now) {
  const CurrentFrame& f = parts.frame;
  KeyframeSelection& selection = parts.selection;
  Keyframe& kf = s.kf[slot];
  kf.used = true;
  kf.id = s.kf_created++;
  parts.ref.dirty = true;
  kf.T_cw = parts.motion.T_cw;
  kf.a = parts.brightness.a, kf.b = parts.brightness.b;
  kf.t_s = f.t_s, kf.exposure_s = f.exposure_s, kf.readout_prev_s = f.readout_prev_s;
  kf.chain_ok = f.chain_ok;
  kf.settled = f.frames_since_timing_change >= kTimingSettleFrames;
  parts.brightness.offset_step = 0;
  kf.count = 0;
  copy_pyramid(f.frame, kf.pyramid, s.cfg);
  s.order[s.kf_count++] = slot;
  if (!select_points_now) return;
  // Where the window's active points already land, no new point is needed.
  std::memset(selection.occupied.data(), 0, selection.occupied.size());
  const Scaled k = camera_at(s.cfg.camera, 0);
  const auto radius = static_cast<int>(std::sqrt(static_cast<float>(plane(s.cfg)) / static_cast<float>(s.cfg.points_per_keyframe)) * 0.5f);
  for (const Keyframe& other : s.kf) {
    if (!other.used || &other == &kf) continue;
    const Se3 M = parts.motion.T_cw * other.T_cw.inverse();
    for (std::uint32_t i = 0; i < other.count; ++i) {
      const Point& p = other.points[i];
      if (p.status != PointStatus::active) continue;
      const Vec3 X = M * (Vec3((p.u - k.cx) / k.fx, (p.v - k.cy) / k.fy, 1.0) / p.idepth);
      if (X.z() <= 1e-6) continue;
      const int u = static_cast<int>(std::lround(k.fx * X.x() / X.z() + k.cx));
      const int v = static_cast<int>(std::lround(k.fy * X.y() / X.z() + k.cy));
      for (int y = v - radius; y <= v + radius; ++y)
        for (int x = u - radius; x <= u + radius; ++x)
          if (x >= 0 && y >= 0 && x < static_cast<int>(s.cfg.width) && y < static_cast<int>(s.cfg.height))
            selection.occupied[static_cast<std::size_t>(y) * s.cfg.width + static_cast<std::size_t>(x)] = 1;
    }
  }
  const std::size_t n = select_points(f.frame.level[0], selection.occupied, s.cfg.points_per_keyframe, 4,
                                      selection.scratch, selection.candidates, s.intensity);
  for (std::size_t i = 0; i < n && kf.count < kf.points.size(); ++i) {
    Point& p = kf.points[kf.count++];
    p = Point();
    p.u = selection.candidates[i].x, p.v = selection.candidates[i].y;
    p.status = PointStatus::immature;
    p.idepth = 1.0f, p.idepth_min = 0.0f, p.idepth_max = -1.0f;
  }
}

// The thresholds in counts were tuned on frames with up to kNominalNoiseCounts of pixel noise;
// noisier frames (a larger gain, or another renderer's scale) get them in proportion. Measured
// once, from the first three frames, so that thresholds do not move under a running map.
void measure_intensity_scale(MapCore& s, NoiseEstimate& noise, const CurrentFrame& f) {
  const double var = frame_noise_variance(noise, f, s.cfg);
  if (var < 0 && s.raw_frames < kIntensityMeasureFrames) return;  // too few flat blocks: try the next frame
  s.intensity_pending = false;
  const double sigma = var > 0 ? std::sqrt(var) : 0.0;
  s.intensity = static_cast<float>(std::max(1.0, sigma / kNominalNoiseCounts));
}

namespace {
// Takes back the part of the carry-over correction (what the scene estimate adds to the raw
// frame: gain_alpha (raw_i - raw_{i-1}) at a steady timing) that its own noise could explain:
// config.hpp, carry_coring. Still pixels then keep the raw frame's noise instead of the inverse
// filter's, and moving edges (a correction far above the noise) are still deghosted. Until the
// noise is measured, nothing is taken back.
void core_carry_correction(CurrentFrame& f, double noise_var, const VoConfig& cfg, float gain_alpha) {
  if (!(cfg.carry_coring > 0) || !(noise_var > 0)) return;
  const auto limit = static_cast<float>(cfg.carry_coring * std::sqrt(2.0 * noise_var)) * gain_alpha;
  float* level0 = f.frame.level[0].value.data;
  for (std::size_t i = 0; i < plane(cfg); ++i) {
    const float correction = gain_alpha * (f.raw[i] - f.raw_prev[i]);
    level0[i] -= std::max(-limit, std::min(limit, correction));
  }
}

double mean_level(const float* image, std::size_t pixels) {
  double sum = 0;
  for (std::size_t i = 0; i < pixels; ++i) sum += image[i];
  return pixels > 0 ? sum / static_cast<double>(pixels) : 0.0;
}
}  // namespace

namespace {
double static_level_factor(Tau tau, double readout_prev_s, double exposure_s) {
  if (!(exposure_s > 0) || !(readout_prev_s > 0)) return 1.0;
  const CarryCoefficients k = carry_coefficients(tau, readout_prev_s, exposure_s);
  return k.beta / (1.0 - k.alpha);
}
}  // namespace

double scene_level_scale(Tau tau, const CurrentFrame& f) { return static_level_factor(tau, f.readout_prev_s, f.exposure_s); }

bool same_level(const CurrentFrame& f, const Keyframe& kf) {
  return f.frames_since_timing_change >= kTimingSettleFrames && kf.settled &&
         !timing_differs(kf.exposure_s, f.exposure_s) && !timing_differs(kf.readout_prev_s, f.readout_prev_s);
}

void write_scene_estimate(CurrentFrame& f, Tau tau, double noise_var, const VoConfig& cfg) {
  f.carry = carry_coefficients(tau, f.readout_prev_s, f.exposure_s);
  // The scene estimate u = (raw_i - alpha raw_{i-1}) / beta (paper Eq. 6), scaled to the level a
  // static pixel reads at this frame's timing: a static pixel keeps its value whatever tau is, so
  // a refined tau does not shift every pixel's level against the keyframes. Without the scale,
  // u's static level is (1 - alpha) / beta times the raw one, which moves with tau unless
  // t_e = t_r, and the tau fit and the tracking then chase each other. At a change of the timing the raw static level
  // itself changes (by the true tau's factor): the tracker and the initialiser free the gain and
  // offset there (same_level).
  f.scene_scale = scene_level_scale(tau, f);
  const auto alpha = static_cast<float>(f.carry.alpha);
  const auto gain = static_cast<float>(f.scene_scale / f.carry.beta);
  float* level0 = f.frame.level[0].value.data;
  for (std::size_t i = 0; i < plane(cfg); ++i) level0[i] = (f.raw[i] - alpha * f.raw_prev[i]) * gain;
  core_carry_correction(f, noise_var, cfg, alpha * gain);
}

void build_frame_images(CurrentFrame& f, const VoConfig& cfg) {
  // Level 0's gradient plane is free until build_pyramid fills it.
  for (std::uint32_t pass = 0; pass < cfg.smoothing; ++pass) smooth_binomial(f.frame.level[0].value, f.frame.level[0].gx);
  build_pyramid(f.frame);
  fill_texels(f.frame, f.frame_texels);
}

std::size_t Odometry::arena_bytes(const VoConfig& config) {
  // The sum of lay_out()'s pieces, each with its alignment slack.
  const VoConfig c = resolved(config);
  std::size_t bytes = sizeof(State) + 64;
  const std::size_t pyr = pyramid_floats(c.width, c.height, c.levels) * sizeof(float) + 16;
  const std::size_t ppk = c.points_per_keyframe;
  bytes += pyr * (1 + c.max_keyframes);
  bytes += texel_count(c.width, c.height, c.levels) * sizeof(Texel) + 16;
  bytes += 4 * (plane(c) * sizeof(float) + 16) + plane(c) + 16;
  bytes += noise_block_count(c.width, c.height) * sizeof(float) + 16;
  bytes += plane(c) + 16;
  bytes += ppk * sizeof(PixelPoint) + 16 + selector_block_count(c.width, c.height) * sizeof(float) + 16 + std::size_t{64} * 2 + 16;
  bytes += c.max_keyframes * (ppk * sizeof(Point) + 16);
  bytes += std::size_t{c.max_keyframes} * ppk * sizeof(WorldPoint) + 16;
  bytes += std::max(std::size_t{c.max_keyframes} * ppk * kBaStride, ppk * 10) * sizeof(float) + std::size_t{c.max_keyframes} * ppk * sizeof(std::uint32_t) + 32;
  bytes += std::size_t{c.max_keyframes} * ppk * sizeof(RefPoint) + 16;
  return bytes + 256 + 64;  // + the buffer's own misalignment (Arena aligns addresses)
}

Odometry::Odometry(const VoConfig& config, std::span<std::byte> arena) {
  if (invalid_reason(config) != nullptr) return;
  Arena a(arena);
  state_ = lay_out(config, a);
}

Tau Odometry::tau() const { return state_ ? state_->tau_est.tau : Tau{}; }
double Odometry::tau_standard_error() const {
  if (state_ == nullptr || !state_->cfg.estimate_tau || !uses_carry_model(state_->cfg)) return 0.0;
  return vo::tau_standard_error(state_->tau_est);
}
std::uint32_t Odometry::keyframes_created() const { return state_ ? state_->kf_created : 0; }
float Odometry::intensity_scale() const { return state_ ? state_->intensity : 1.0f; }

std::span<const TimedPose> Odometry::initialisation_poses() const {
  if (!state_ || !state_->init.completed_now) return {};
  return {state_->init.poses.data(), state_->init.pose_count};
}

std::span<const WorldPoint> Odometry::retired_points() const {
  if (!state_) return {};
  return {state_->retired.points.data(), state_->retired.count};
}

std::span<const KeyframePose> Odometry::retired_keyframes() const {
  if (!state_) return {};
  return {state_->retired.keyframes, state_->retired.keyframe_count};
}

std::size_t Odometry::window_keyframes(std::span<KeyframePose> out) const {
  std::size_t n = 0;
  if (!state_) return 0;
  for (std::uint32_t k = 0; k < state_->kf_count && n < out.size(); ++k) {
    const Keyframe& kf = state_->kf[state_->order[k]];
    out[n++] = {kf.id, kf.t_s, kf.T_cw.inverse()};
  }
  return n;
}

std::size_t Odometry::window_points(std::span<WorldPoint> out) const {
  std::size_t n = 0;
  if (!state_) return 0;
  for (const Keyframe& kf : state_->kf) {
    if (!kf.used) continue;
    for (std::uint32_t i = 0; i < kf.count && n < out.size(); ++i) {
      const Point& p = kf.points[i];
      if (p.status != PointStatus::active || p.idepth <= 0) continue;
      const Vec3 X = world_point(kf, p, state_->cfg.camera);
      out[n++] = {static_cast<float>(X.x()), static_cast<float>(X.y()), static_cast<float>(X.z()),
                  kf.pyramid.level[0].value.at(static_cast<std::uint32_t>(p.u), static_cast<std::uint32_t>(p.v))};
    }
  }
  return n;
}

Se3 motion_step(const MotionModel& m, double t_s) {
  const double dt = t_s - m.pose_t_s;
  if (!(m.step_dt_s > 0) || !(dt > 0)) return m.step;
  const double ratio = dt / m.step_dt_s;
  if (std::fabs(ratio - 1) < 0.25) return m.step;  // timing jitter: the step as measured
  // Beyond a few frames constant velocity is a poor guess anyway (the identity guess remains).
  return Se3::exp(std::min(ratio, 4.0) * m.step.log());
}

void record_motion(MotionModel& m, const Se3& previous, double t_s) {
  m.step = (m.T_cw * previous.inverse()).orthonormalised();
  m.step_dt_s = t_s - m.pose_t_s;
  m.pose_t_s = t_s;
}

namespace {
// Counts the frames since the exposure or readout last changed; at a change, the brightness starts
// where the current tau puts the raw static level of the new timing against the old one's
// (initialiser, tracker), in affine (as DSO with known exposure times) where the exposures' ratio
// puts it.
void follow_timing(State& s) {
  CurrentFrame& f = s.current;
  const bool changed = timing_differs(f.exposure_prev_s, f.exposure_s) || timing_differs(f.readout_prev2_s, f.readout_prev_s);
  if (!changed) {
    if (f.frames_since_timing_change < 0xffffffffu) ++f.frames_since_timing_change;
    return;
  }
  f.frames_since_timing_change = 0;
  if (uses_carry_model(s.cfg) && f.chain_ok) {
    const double ratio = static_level_factor(s.tau_est.tau, f.readout_prev_s, f.exposure_s) /
                         static_level_factor(s.tau_est.tau, f.readout_prev2_s, f.exposure_prev_s);
    s.brightness.a += std::log(ratio);
    // A camera's raw counts start from an offset, which stays where it is while the scene's share
    // scales by the ratio: the frame's offset starts where the mean scene levels of this frame
    // and the one before put it (3000 counts of offset lost the track at a switch otherwise).
    if (f.chain_ok_prev && f.readout_prev2_s > 0 && f.exposure_prev_s > 0 && f.readout_prev_s > 0 && f.exposure_s > 0) {
      const std::size_t n = plane(s.cfg);
      const double m0 = mean_level(f.raw.data(), n), m1 = mean_level(f.raw_prev.data(), n), m2 = mean_level(f.raw_prev2.data(), n);
      const double alpha_now = carry_coefficients(s.tau_est.tau, f.readout_prev_s, f.exposure_s).alpha;
      const double alpha_before = carry_coefficients(s.tau_est.tau, f.readout_prev2_s, f.exposure_prev_s).alpha;
      const double scene_now = (m0 - alpha_now * m1) / (1 - alpha_now), scene_before = (m1 - alpha_before * m2) / (1 - alpha_before);
      s.brightness.b = ratio * s.brightness.b + (scene_now - ratio * scene_before);
    }
    s.brightness.level_unknown = true;
  } else if (s.cfg.photometric == Photometric::affine && timing_differs(f.exposure_prev_s, f.exposure_s)) {
    s.brightness.a += std::log(f.exposure_s / f.exposure_prev_s);
  }
}

bool repeats(std::span<const std::uint16_t> raw, std::span<const float> previous) {
  for (std::size_t i = 0; i < raw.size(); ++i)
    if (static_cast<float>(raw[i]) != previous[i]) return false;  // noise: almost always at i = 0
  return true;
}
}  // namespace

namespace {

// The frame's raw counts, times and carry-over chain become the state's current frame (the ones
// before it move back); its timing, stuck-pixel, intensity-scale and noise bookkeeping follow.
// Returns whether the frame follows a repeated one (its sensor predecessor was never delivered).
bool load_frame(State& s, const FrameInput& in, bool chain_broken) {
  CurrentFrame& f = s.current;
  const VoConfig& c = s.cfg;
  std::swap(f.raw_prev, f.raw_prev2);
  std::swap(f.raw, f.raw_prev);
  for (std::size_t i = 0; i < plane(c); ++i) f.raw[i] = static_cast<float>(in.raw[i]);
  const bool had_prev = f.have_prev;
  f.have_prev = true;
  f.chain_ok_prev = f.chain_ok;
  const bool after_repeat = f.predecessor_missing && !chain_broken;
  f.predecessor_missing = false;
  f.chain_ok = had_prev && !chain_broken && !after_repeat;
  s.motion.T_prev = s.motion.T_cw;
  s.motion.prev_posed = s.motion.posed;
  s.motion.posed = false;
  f.exposure_prev_s = f.exposure_s;
  f.readout_prev2_s = f.readout_prev_s;
  f.t_s = in.t_s, f.exposure_s = in.exposure_s, f.readout_prev_s = in.readout_prev_s;
  follow_timing(s);
  f.scene_scale = 1.0;
  const bool ir = uses_carry_model(c);
  if (ir && had_prev) count_unchanged_frames(s.tau_est, s.current, s);
  if (s.intensity_pending && ++s.raw_frames >= 3) measure_intensity_scale(s, s.noise, s.current);
  // Before the tracking image: its carry-over correction is cored against this noise.
  if (ir && f.chain_ok && f.chain_ok_prev) update_noise_variance(s.noise, s.current, s.cfg);
  return after_repeat;
}

// The tracking image: what the photometric model says is comparable between frames.
void write_tracking_image(State& s, const FrameInput& in) {
  CurrentFrame& f = s.current;
  const VoConfig& c = s.cfg;
  float* level0 = f.frame.level[0].value.data;
  if (c.photometric == Photometric::ir && f.chain_ok) {
    write_scene_estimate(f, s.tau_est.tau, s.noise.var, c);
  } else if (c.photometric == Photometric::ir_loop && f.chain_ok && in.corrected.size() == plane(c)) {
    // Without its predecessor the corrector only scales the frame by 1/beta, a level the keyframes
    // do not share; the raw frame (like ir's) has their static level and is tracked with a free offset.
    // The corrector ran with this tau; its output is brought to the static level as ir's is.
    f.scene_scale = scene_level_scale(s.tau_est.tau, s.current);
    const auto scale = static_cast<float>(f.scene_scale);
    for (std::size_t i = 0; i < plane(c); ++i) level0[i] = static_cast<float>(in.corrected[i]) * scale;
    const CarryCoefficients k = carry_coefficients(s.tau_est.tau, f.readout_prev_s, f.exposure_s);
    core_carry_correction(f, s.noise.var, c, static_cast<float>(k.alpha * f.scene_scale / k.beta));
  } else {
    std::memcpy(level0, f.raw.data(), plane(c) * sizeof(float));
  }
  build_frame_images(f, c);
}

// A new map from the current frame: the old map's points retired (still output) and its prior
// dropped, the frame its first keyframe, and nothing of the old map's motion carried over (a new
// map has a scale of its own).
void restart_map(State& s) {
  for (auto& kf : s.kf) {
    if (kf.used) retire_keyframe(s.retired, kf, s.cfg.camera);
    kf.used = false, kf.count = 0;
  }
  s.kf_count = 0;
  clear_marginal_prior(s.prior);
  const std::uint32_t slot = new_keyframe_slot(s, s.retired, s.ba, s.prior);
  make_keyframe(s, keyframe_parts(s), slot, true);
  start_initialisation(s.init, s.kf[slot]);
  s.motion.step = Se3();
  s.motion.step_dt_s = 0;
  s.motion.pose_t_s = s.current.t_s;
  s.bridge.count = 0;
  s.bridge.carry = CarriedVelocity();
}

// Initialise: a frame while the map is not initialised, the initialiser's next step or its (re)start.
FrameResult initialise_phase(State& s, bool after_repeat, double frame_dt_s, FrameResult out) {
  const bool ir = uses_carry_model(s.cfg);
  // A broken carry-over chain (ir modes) gives a frame that matches nothing: wait for the next.
  if (s.kf_count == 0 || s.init.frames >= kMaxInitFrames || (ir && !s.current.chain_ok)) {
    // After a repeated frame the scene did not jump (no shutter event, no gap in time): the
    // initialisation goes on with the next frame.
    if (ir && after_repeat && s.kf_count > 0 && s.init.frames < kMaxInitFrames) return out;
    if (ir && !s.current.chain_ok) {
      s.kf_count = 0;
      for (auto& kf : s.kf) kf.used = false;
      return out;
    }
    s.brightness.a = s.brightness.b = 0;
    s.motion.T_cw = s.kf_count > 0 ? s.kf[s.order[0]].T_cw : s.motion.last_good;
    // A map lost far out (scale drift) cannot anchor a new one with any precision: restart at the origin.
    if (!s.motion.T_cw.t.allFinite() || s.motion.T_cw.t.norm() > 1e3) s.motion.T_cw = Se3();
    restart_map(s);
    return out;
  }
  if (!initialise_step(s, s.init, s.current, s.motion, s.brightness, s.ref)) return out;
  s.motion.posed = true;
  out.state = TrackingState::tracking;
  out.has_pose = true;
  out.T_wc = s.motion.T_cw.inverse();
  out.tie = tie_to(s.kf[s.order[0]], out.T_wc);
  out.tracked_points = active_in_window(s);
  s.loop.frames_since_kf = 1;
  s.loop.since_kf_s = frame_dt_s;
  s.loop.inliers_after_kf = out.tracked_points;
  return out;
}

// Where the tracking starts the frame's brightness, and which of its parameters are free.
struct BrightnessStart {
  FreeBrightness free;
  double a = 0, b = 0;
  bool level_unknown = false;  // the frame has not its reference keyframe's level (same_level)
  bool shutter_step = false;   // the frame is a shutter event's step response
};

BrightnessStart brightness_start(State& s, const FrameInput& in, const Keyframe& reference) {
  const CurrentFrame& f = s.current;
  const VoConfig& c = s.cfg;
  const bool ir = uses_carry_model(c);
  BrightnessStart start;
  // ir modes: a frame without its sensor predecessor is tracked on its raw counts with a free gain
  // and offset (after a shutter event its contrast is 1 - alpha of the keyframes', the pixels having
  // settled on the shutter; after a gap it holds the ghost of a frame never seen), and the first
  // frame after it with a free offset that is then kept: a shutter event resets the camera's
  // offsets, which the scene estimate carries from then on.
  if (ir && !f.chain_ok) s.brightness.offset_pending = true;
  // A frame without its reference keyframe's level (same_level: across a change of exposure or
  // readout) is tracked with a free gain and offset, which are kept.
  start.level_unknown = ir && f.chain_ok && !same_level(s.current, reference);
  start.free.gain = ir && (!f.chain_ok || start.level_unknown);
  start.free.offset = ir && (!f.chain_ok || s.brightness.offset_pending || start.level_unknown);
  // After a shutter event the gain starts where the current tau puts the step response, and the
  // offset where that gain puts the frame's mean level (the settled shutter's share of the counts
  // is unknown: started at the keyframes' offset, every residual would be an outlier).
  // The reference's image has the raw static level of its own timing.
  start.shutter_step = ir && in.shutter_event && reference.exposure_s > 0 && reference.readout_prev_s > 0 && in.exposure_s > 0;
  start.a = s.brightness.a, start.b = s.brightness.b;
  // Back at the reference's level after frames that were not: its gain, and its offset as the
  // camera's shutter events have moved it since.
  if (ir && f.chain_ok && !start.level_unknown && s.brightness.level_unknown)
    start.a = reference.a, start.b = reference.b + s.brightness.offset_step;
  if (start.shutter_step) {
    const double gain = shutter_step_gain(s.tau_est.tau, in.exposure_s, reference.readout_prev_s, reference.exposure_s);
    start.a = reference.a + std::log(gain);
    start.b = mean_level(f.raw.data(), plane(c)) - gain * (mean_level(reference.pyramid.level[0].value.data, plane(c)) - reference.b);
  }
  return start;
}

// A tracked pose whose step from the last moves the map's points further than a video-rate camera can.
bool too_fast(State& s, const TrackResult& r) {
  return step_translation_flow(s, r.T_cw * s.motion.T_cw.inverse()) > kMaxStepFlow * (s.cfg.width + s.cfg.height);
}

// The frame tracked from the motion model's guesses (constant velocity, none, half, double).
// The constant-velocity guess is tracked first and stands when it fits about as well as the last
// frame did (as in DSO). Otherwise every guess is ranked at the second-coarsest level (as DSO
// ranks its motion hypotheses at the coarsest), the best is tracked to the finest, the others
// only if it fails. (Ranking every guess on every frame was needed while the poses lost their
// orthonormality and a constant-velocity guess drifted off; it cost a quarter of the VO's time.)
TrackResult track_from_guesses(State& s, const Se3& step, const BrightnessStart& start) {
  const CurrentFrame& f = s.current;
  const Se3 half = Se3::exp(0.5 * step.log());
  const auto held = [&](const Se3& guess) { return held_guess(s.bridge, f.t_s, guess); };
  const Se3& T = s.motion.T_cw;
  const Se3 guesses[] = {held(step * T), held(T), held(half * T), held(step * step * T)};
  // The tracking from a guess down to `last_level`, continuing `resume` (track_frame).
  const auto track = [&](const Se3& guess, std::uint32_t last_level, const TrackResult* resume = nullptr) {
    return track_frame(s.ref, s, f, s.bridge, guess, start.a, start.b, start.free, last_level, resume);
  };
  TrackResult best;
  bool have = false;
  const std::uint32_t screen_level = f.frame.levels > 2 ? f.frame.levels - 2 : 0;
  constexpr std::size_t kGuesses = sizeof(guesses) / sizeof(guesses[0]);
  std::size_t order[kGuesses] = {0, 1, 2, 3};
  TrackResult screened[kGuesses];
  bool accepted = false;
  if (screen_level > 0) {
    screened[0] = track(guesses[0], screen_level);
    if (screened[0].ok && s.loop.last_rms > 0) {
      TrackResult r = track(guesses[0], 0, &screened[0]);
      if (r.ok && !too_fast(s, r) && r.rms <= kRetrackRatio * s.loop.last_rms) best = r, have = true, accepted = true;
    }
  }
  if (screen_level > 0 && !accepted) {
    double energy[kGuesses];
    for (std::size_t g = 0; g < kGuesses; ++g) {
      if (g > 0) screened[g] = track(guesses[g], screen_level);
      energy[g] = screened[g].ok ? screened[g].mean_energy : 1e30;
    }
    std::sort(order, order + kGuesses, [&](std::size_t x, std::size_t y) { return energy[x] < energy[y]; });
  }
  for (const std::size_t g : order) {
    if (accepted) break;
    // A screened guess continues below the screening level (its coarse levels are not repeated).
    TrackResult r = track(guesses[g], 0, screen_level > 0 && screened[g].ok ? &screened[g] : nullptr);
    if (r.ok && too_fast(s, r)) r.ok = false;
    if (!have || (r.ok && !best.ok) || (r.ok == best.ok && r.rms < best.rms)) best = r, have = true;
    if (best.ok && screen_level > 0) break;
  }
  return best;
}

// A held centre the frame cannot be tracked at (the velocity was not the camera's after all, or
// the turn's smear leaves too few points for the rotation alone): the frame is tracked free, as
// without the bridge, rather than lost; the hold goes on with the next frame. Returns whether the
// frame's pose keeps the held centre.
bool track_free_of_hold(State& s, const Se3& step, const BrightnessStart& start, TrackResult& best) {
  bool held = centre_carried(s.bridge, s.current.t_s);
  if (!best.ok && held) {
    s.bridge.carry.suspended = true;
    for (const Se3& g : {step * s.motion.T_cw, s.motion.T_cw}) {
      const TrackResult r = track_frame(s.ref, s, s.current, s.bridge, g, start.a, start.b, start.free, 0);
      if (r.ok && !too_fast(s, r) && (!best.ok || r.rms < best.rms)) best = r;
    }
    s.bridge.carry.suspended = false;
    held = !best.ok;
  }
  return held;
}

// A frame no guess tracked: the camera coasts on the motion model, and after
// kLostFramesBeforeRestart such frames the map restarts at the last tracked pose.
void coast_lost_frame(State& s, const Se3& step, FrameResult& out) {
  ++s.loop.lost_frames;
  out.state = TrackingState::lost;
  s.motion.T_cw = (step * s.motion.T_cw).orthonormalised();
  s.motion.pose_t_s = s.current.t_s;
  if (!s.motion.T_cw.R.allFinite() || !s.motion.T_cw.t.allFinite()) s.motion.T_cw = s.motion.last_good, s.motion.step = Se3();
  if (s.loop.lost_frames >= kLostFramesBeforeRestart) {
    // Restart the map here, anchored at the coasted pose.
    s.loop.lost_frames = 0;
    s.init.initialised = false;
    out.reinitialised = true;
    s.motion.T_cw = s.motion.last_good;  // the coasted pose is a guess; anchor the new map at the last fix
    if (!s.motion.T_cw.t.allFinite() || s.motion.T_cw.t.norm() > 1e3) s.motion.T_cw = Se3();
    restart_map(s);
  }
}

// The tracked pose becomes the camera's, with the motion model and the scale bridge's sample.
void adopt_pose(State& s, const TrackResult& best) {
  s.loop.lost_frames = 0;
  const Se3 pose = best.T_cw.orthonormalised();
  s.motion.last_good = pose;
  const Se3 previous = s.motion.T_cw;
  s.motion.T_cw = pose;
  record_motion(s.motion, previous, s.current.t_s);
  record_motion_sample(s.bridge, s.cfg, s.motion.T_cw, previous, s.current.t_s, s.motion.step_dt_s, s.ref.mean_idepth);
}

// The tracked brightness becomes the frame's, and a shutter event's step response gives tau.
// A frame without its predecessor (tracked on its raw counts) has an unknown gain and offset:
// the keyframes' brightness is kept. A free offset after a shutter event is the camera's only on
// a frame with the reference's level.
void adopt_brightness(State& s, const FrameInput& in, const TrackResult& best, const Keyframe& reference,
                      const BrightnessStart& start, FrameResult& out) {
  const bool ir = uses_carry_model(s.cfg);
  if (!(ir && !s.current.chain_ok)) {
    s.brightness.a = best.a, s.brightness.b = best.b;
    s.brightness.level_unknown = start.level_unknown;
    if (!start.level_unknown) {
      if (s.brightness.offset_pending) s.brightness.offset_step = best.b - reference.b;
      s.brightness.offset_pending = false;
    }
  }
  if (start.shutter_step && s.cfg.estimate_tau) {
    // The step response's contrast against the tracking reference.
    const double gain = std::exp(best.a - reference.a);
    const double tau = tau_from_shutter_step_gain(gain, in.exposure_s, reference.readout_prev_s, reference.exposure_s);
    if (take_shutter_measurement(s.tau_est, tau)) out.shutter_tau_s = tau;
  }
}

// Keyframe: enough parallax, a large rotation, or the tracked points thinning out; never two in a
// row unless tracking is about to starve. Returns whether one was made (then bundle-adjusted).
bool keyframe_if_due(State& s, const TrackResult& best, double frame_dt_s) {
  const VoConfig& c = s.cfg;
  const KeyframeFlow flow = keyframe_flow(s);
  const double size = c.width + c.height;
  const Keyframe& latest = s.kf[s.order[s.kf_count - 1]];
  if (s.loop.frames_since_kf == 1) s.loop.inliers_after_kf = best.inliers;
  ++s.loop.frames_since_kf;
  s.loop.since_kf_s += frame_dt_s;
  const bool brightness = std::fabs(s.brightness.a - latest.a) > 0.5;
  const bool thinning = best.inliers * 4 < s.loop.inliers_after_kf;
  const double threshold = kKeyframeTranslationFlow * size;
  const bool parallax = c.keyframe_parallax == KeyframeParallax::quantile
                            ? flow.translation_p75 > threshold || flow.translation_rms > 2 * threshold
                            : flow.translation_rms > threshold;
  const bool want = parallax || flow.full_rms > kKeyframeFullFlow * size || thinning || brightness;
  const bool starving = best.inliers < 40;
  // Spaced by 3 frames, or by the time 3 frames take at 30 Hz: at 9 Hz 3 frames are a third of a
  // second, over which a car has driven 3 m and the tracked points have left the keyframe.
  const bool spaced = s.loop.frames_since_kf >= 3 || (s.loop.frames_since_kf >= 1 && s.loop.since_kf_s >= kMinKeyframeSpacingS - 1e-6);
  if (!((want && spaced) || (starving && s.loop.frames_since_kf >= 2))) return false;
  if (uses_carry_model(c) && !s.current.chain_ok) return false;
  // As in DSO, immature points join the map only with a new keyframe, right before the bundle
  // adjustment refines them with everything else.
  // On a map that began as a rotation, while the camera still only turns, the tracked points
  // leave the view at the turn's rate (a 9 Hz pan at 30 deg/s takes 30-40 of them a frame), and
  // the rotation's points are all the map can get: the count the next keyframe would track
  // decides. (Not on a map with depths: there the same rule costs scale in the look-arounds of
  // walks.)
  activate_mature_points(s, s.ref, s.bridge, s.init, s.current.t_s,
                         s.init.map_without_baseline ? tracked_at_next_keyframe(s, best.inliers) : best.inliers);
  const std::uint32_t slot = new_keyframe_slot(s, s.retired, s.ba, s.prior);
  make_keyframe(s, keyframe_parts(s), slot, true);
  if (c.window_ba && s.kf_count >= 2) {
    window_bundle_adjustment(s, s.ba, s.prior, s.ref);
    // The newest keyframe is the current frame: follow its refined pose.
    const Keyframe& newest = s.kf[s.order[s.kf_count - 1]];
    s.motion.T_cw = newest.T_cw;
    s.brightness.a = newest.a, s.brightness.b = newest.b;
  }
  s.loop.frames_since_kf = 0;
  s.loop.since_kf_s = 0;
  return true;
}

// The phases of Odometry::process, in order.

// How the loaded frame follows the last one.
struct FrameArrival {
  bool after_repeat = false;  // it follows a repeated frame (its sensor predecessor was never delivered)
  double dt_s = 0;            // the time since the last frame (0 for the first)
};

// Load: the frame becomes the current one, with its tracking image; false for a repeat of the
// last frame, which is skipped (out: duplicate).
bool load_phase(State& s, const FrameInput& in, FrameArrival& arrival, FrameResult& out) {
  const bool chain_broken = in.chain_broken || in.shutter_event;
  if (s.current.have_prev && !chain_broken && repeats(in.raw.first(plane(s.cfg)), s.current.raw)) {
    // Processed as a frame it would pose the camera where it was a frame ago, at the new time,
    // and pair two identical frames as carry-over.
    s.current.predecessor_missing = true;
    out.state = TrackingState::duplicate;
    out.tau = s.tau_est.tau;
    return false;
  }
  arrival.dt_s = s.current.have_prev ? in.t_s - s.current.t_s : 0.0;
  arrival.after_repeat = load_frame(s, in, chain_broken);
  write_tracking_image(s, in);
  out.tau = s.tau_est.tau;
  return true;
}

// Track: the frame aligned against the newest keyframe from the motion model's guesses; its pose
// and brightness adopted (returns ok), or the camera coasted as lost (not ok).
TrackResult track_phase(State& s, const FrameInput& in, FrameResult& out) {
  const Keyframe& reference = s.kf[s.order[s.kf_count - 1]];  // the tracking reference
  const BrightnessStart start = brightness_start(s, in, reference);
  const Se3 step = motion_step(s.motion, s.current.t_s);
  TrackResult best = track_from_guesses(s, step, start);
  const bool held = track_free_of_hold(s, step, start, best);
  out.residual_rms = best.rms;
  out.tracked_points = best.inliers;
  if (!best.ok) {
    coast_lost_frame(s, step, out);
    return best;
  }
  adopt_pose(s, best);
  out.centre_held = held;
  adopt_brightness(s, in, best, reference, start, out);
  out.state = TrackingState::tracking;
  out.has_pose = true;
  s.motion.posed = true;
  return best;
}

// Tau: the ir modes' estimate refined from the carry-over between this posed frame and the last.
void tau_phase(State& s) {
  if (uses_carry_model(s.cfg) && s.cfg.estimate_tau) refine_tau(s.tau_est, s, s.current, s.motion, s.noise.var);
}

// Depths: what this posed frame tells about the map's depths (its baseline since a map begun
// without one, the immature points' intervals).
void depth_phase(State& s) {
  follow_map_baseline(s.init, s.motion, s.cfg);
  search_immature_points(s, s.current, s.motion, s.brightness, depth_search_margin(s.bridge, s.cfg, s.current.t_s));
}

// Bookkeeping: the scale bridge's carry, and the frame's result (pose, tau) with the residual the
// next frame's guess is judged against.
void bookkeeping_phase(State& s, const TrackResult& best, FrameResult& out) {
  update_bridge(s.bridge, s.current.t_s, out.keyframe);
  out.T_wc = s.motion.T_cw.inverse();
  out.tie = tie_to(s.kf[s.order[s.kf_count - 1]], out.T_wc);
  out.tau = s.tau_est.tau;
  s.loop.last_rms = best.rms;
}

}  // namespace

FrameResult Odometry::process(const FrameInput& in) {
  FrameResult out;
  if (!state_) return out;
  State& s = *state_;
  s.retired.count = 0;
  s.retired.keyframe_count = 0;
  s.init.completed_now = false;
  FrameArrival arrival;
  if (!load_phase(s, in, arrival, out)) return out;
  if (!s.init.initialised) return initialise_phase(s, arrival.after_repeat, arrival.dt_s, out);
  const TrackResult best = track_phase(s, in, out);
  if (!best.ok) return out;
  tau_phase(s);
  depth_phase(s);
  out.keyframe = keyframe_if_due(s, best, arrival.dt_s);  // with the window BA
  bookkeeping_phase(s, best, out);
  return out;
}

}  // namespace bolo::vo

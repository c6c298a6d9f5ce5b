#pragma once
// Configuration of the on-board visual odometry: camera, photometric model, capacities. Every
// buffer the VO uses is sized from this at construction (Odometry::arena_bytes) and never grows.

#include <cstddef>
#include <cstdint>

namespace bolo::vo {

// How the VO explains brightness changes between a keyframe and a new frame.
enum class Photometric : std::uint8_t {
  none,     // brightness constancy on raw counts
  affine,   // per-frame gain/offset (DSO's e^{-a}(I - b))
  ir,       // microbolometer carry-over: raw_i - alpha*raw_{i-1} = beta*u, tau estimated online
  ir_loop,  // the firmware corrector runs in front with the current tau; the VO refines tau
};
const char* to_string(Photometric mode);
// Returns false for an unknown name.
bool parse_photometric(const char* name, Photometric& mode);

struct Camera {
  float fx = 0, fy = 0, cx = 0, cy = 0;  // pixel units, centre of the top-left pixel at (0, 0)
};

// Temporal pixel noise (counts) up to which the thresholds in counts are used as configured.
inline constexpr float kNominalNoiseCounts = 4.0f;

// Which keyframe leaves a full window (VoConfig::retirement).
enum class Retirement : std::uint8_t { oldest, spread };
const char* to_string(Retirement rule);
// Returns false for an unknown name.
bool parse_retirement(const char* name, Retirement& rule);

// What translation flow makes a keyframe (VoConfig::keyframe_parallax): the rms over the newest
// keyframe's points, or the flow three quarters of them stay below (with the rms at twice the
// threshold still counting).
enum class KeyframeParallax : std::uint8_t { rms, quantile };
const char* to_string(KeyframeParallax rule);
// Returns false for an unknown name.
bool parse_keyframe_parallax(const char* name, KeyframeParallax& rule);

struct VoConfig {
  std::uint32_t width = 0, height = 0;
  Camera camera;
  Photometric photometric = Photometric::none;
  float tau_init_s = 0.010f;   // starting tau for ir / ir-loop (both tau_h and tau_c)
  bool estimate_tau = true;    // false: tau_init_s is known and kept
  std::uint32_t levels = 0;    // pyramid levels; 0 = until the coarsest is ~20 px high
  std::uint32_t max_keyframes = 8;
  std::uint32_t points_per_keyframe = 0;  // 0 = ~1 per 40 pixels, 100 to kMaxDefaultPointsPerKeyframe; at most kMaxPointsPerKeyframe
  float huber_counts = 16.0f;  // residual where the Huber weight starts to drop
  float gradient_c = 40.0f;    // gradient weight c^2 / (c^2 + |grad|^2)
  // The frames' counts per count of the scale the thresholds above (and the point selection's,
  // the tau fit's prior and the stuck-pixel contrast) were tuned for: every such threshold is
  // multiplied by it. 0 = measured: 1 up to kNominalNoiseCounts of temporal pixel noise, above
  // that the noise over it (from the first three frames; a camera or renderer with a larger
  // gain than the simulator's then sees the same thresholds relative to its noise).
  float intensity_scale = 0.0f;
  bool window_ba = true;       // sliding-window bundle adjustment at every keyframe
  // A retired keyframe's information stays as a prior on the window (DSO's marginalisation)
  // instead of being dropped. Off by default: it buys nothing consistent on the study's
  // sequences (docs/odometry-study.md).
  bool marginalisation_prior = false;
  // Which keyframe leaves a full window: the oldest, or (spread) a keyframe much nearer its
  // neighbours along the path than the window's mean spacing if there is one, so that the window
  // keeps its baseline through turns and look-arounds.
  Retirement retirement = Retirement::spread;
  // quantile: ahead of a car the nearest road sweeps tens of pixels in a few frames, and the rms
  // would make a keyframe every ~0.5 m, each a link the map's scale drifts along; it pays on the
  // study's drives and costs on its look-around walks (docs/odometry-study.md).
  KeyframeParallax keyframe_parallax = KeyframeParallax::rms;
  // ir modes: the carry-over correction (deghosted minus raw) is kept only where it stands out
  // of its own noise: its part within carry_coring times that noise's sigma is left out of the
  // tracking image (a soft threshold), because deghosting is an inverse filter that multiplies
  // the pixel noise where nothing moves. 0: the paper's full correction.
  float carry_coring = 1.0f;
  // Passes of a 3x3 binomial low-pass over each tracking image before its pyramid (0: none).
  // Bilinear sampling at a fraction of a pixel is least accurate where the image holds detail
  // near the sampling limit (aliased renders, the deghosted image's amplified noise and flicker);
  // one pass damps that band, and also makes fewer keyframes. Its effect on accuracy and work:
  // docs/odometry-study.md, "Accuracy".
  std::uint32_t smoothing = 1;
  // Across a fast turn that takes the map out of view (a look-around), the camera centre is held
  // on the velocity of the steady stretch before the turn until the new view's points have depths
  // of their own, so they keep the old map's scale (scale_bridge.cpp); false: the new view keeps
  // whatever scale its placeholder depths gave it.
  bool scale_bridge = true;
};

// The configuration with its 0 defaults resolved.
VoConfig resolved(const VoConfig& config);
// Whether a retiring keyframe's information stays as a prior on the window: only where the
// window is bundle-adjusted, which is what reads the prior. The oldest then has to be the one to
// leave (keyframe_to_retire), because the prior is built from it.
inline bool builds_marginalisation_prior(const VoConfig& c) { return c.window_ba && c.marginalisation_prior; }
// A configuration the VO cannot run with (sizes, camera, capacities); nullptr when fine.
const char* invalid_reason(const VoConfig& config);

inline constexpr std::uint32_t kMaxLevels = 6;
inline constexpr std::uint32_t kMaxSmoothingPasses = 3;
inline constexpr std::uint32_t kMaxKeyframes = 8;
inline constexpr std::uint32_t kPattern = 8;  // pixels in each point's residual pattern
inline constexpr std::uint32_t kMaxDefaultPointsPerKeyframe = 500;  // the cap of points_per_keyframe = 0
inline constexpr std::uint32_t kMinPointsPerKeyframe = 50;  // below, a keyframe cannot hold the tracker's least inliers
inline constexpr std::uint32_t kMaxPointsPerKeyframe = 8000;

// A tunable's accepted values, both ends included; NaN is outside every range.
template <class T>
struct Range {
  T min, max;
  constexpr bool contains(T v) const { return v >= min && v <= max; }
};
// The tunables' ranges: invalid_reason refuses a configuration outside them and `bolo odometry`
// names its flag with the same bounds.
inline constexpr Range<float> kTauInitRange{0.001f, 0.05f};  // seconds
inline constexpr Range<std::uint32_t> kKeyframesRange{2, kMaxKeyframes};
inline constexpr Range<std::uint32_t> kPointsPerKeyframeRange{kMinPointsPerKeyframe, kMaxPointsPerKeyframe};  // or 0
inline constexpr Range<float> kIntensityScaleRange{0.0f, 1e4f};  // 0: measured
inline constexpr Range<float> kCarryCoringRange{0.0f, 100.0f};   // 0: the full correction
inline constexpr Range<std::uint32_t> kSmoothingRange{0, kMaxSmoothingPasses};

}  // namespace bolo::vo

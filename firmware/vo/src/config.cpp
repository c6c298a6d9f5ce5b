#include <cmath>
#include <cstring>
#include <initializer_list>

#include "bolo/vo/config.hpp"

namespace bolo::vo {

const char* to_string(Photometric mode) {
  switch (mode) {
    case Photometric::none: return "none";
    case Photometric::affine: return "affine";
    case Photometric::ir: return "ir";
    case Photometric::ir_loop: return "ir-loop";
  }
  return "?";
}

bool parse_photometric(const char* name, Photometric& mode) {
  const Photometric all[] = {Photometric::none, Photometric::affine, Photometric::ir, Photometric::ir_loop};
  for (Photometric m : all)
    if (std::strcmp(name, to_string(m)) == 0) {
      mode = m;
      return true;
    }
  return false;
}

const char* to_string(Retirement rule) { return rule == Retirement::oldest ? "oldest" : "spread"; }

bool parse_retirement(const char* name, Retirement& rule) {
  for (Retirement r : {Retirement::oldest, Retirement::spread})
    if (std::strcmp(name, to_string(r)) == 0) {
      rule = r;
      return true;
    }
  return false;
}

VoConfig resolved(const VoConfig& config) {
  VoConfig c = config;
  if (c.levels == 0) {
    c.levels = 1;
    while (c.levels < kMaxLevels && (c.height >> c.levels) >= 20 && (c.width >> c.levels) >= 20) ++c.levels;
  }
  if (c.points_per_keyframe == 0) {
    // One per 40 pixels up to 500 a keyframe (8 keyframes: <= 4000 in the window; DSO keeps ~2000
    // active at 640x480). The cap bounds the time at the larger sizes: the window BA and the depth
    // search scale with the points, and more points bought no accuracy beyond the seeds' spread.
    const std::uint32_t n = c.width * c.height / 40;
    c.points_per_keyframe = n < 100 ? 100 : (n > kMaxDefaultPointsPerKeyframe ? kMaxDefaultPointsPerKeyframe : n);
  }
  return c;
}

const char* invalid_reason(const VoConfig& config) {
  const VoConfig c = resolved(config);
  if (c.width < 32 || c.height < 32) return "image smaller than 32x32";
  if (c.width > 4096 || c.height > 4096) return "image larger than 4096x4096";
  if (!(c.camera.fx > 0) || !(c.camera.fy > 0) || !std::isfinite(c.camera.cx) || !std::isfinite(c.camera.cy))
    return "camera intrinsics must be positive and finite";
  if (c.levels > kMaxLevels) return "too many pyramid levels";
  if (c.max_keyframes < 2 || c.max_keyframes > kMaxKeyframes) return "max_keyframes must be 2..8";
  if (!(c.tau_init_s > 0.0005f && c.tau_init_s < 0.1f)) return "tau_init_s must be within 0.5..100 ms";
  if (!(c.huber_counts > 0) || !(c.gradient_c > 0)) return "huber_counts and gradient_c must be positive";
  if (!(c.intensity_scale >= 0) || !(c.intensity_scale <= 1e4f)) return "intensity_scale must be within 0..10000";
  if (!(c.carry_coring >= 0) || !(c.carry_coring <= 100)) return "carry_coring must be within 0..100";
  if (c.smoothing > kMaxSmoothingPasses) return "smoothing must be within 0..3 passes";
  if (c.points_per_keyframe < kMinPointsPerKeyframe || c.points_per_keyframe > kMaxPointsPerKeyframe)
    return "points_per_keyframe must be within 50..8000";
  return nullptr;
}

}  // namespace bolo::vo

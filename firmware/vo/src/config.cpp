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

namespace {

// The value among `all` whose to_string() is `name`; false when none is.
template <typename Enum>
bool parse_by_name(const char* name, std::initializer_list<Enum> all, Enum& out) {
  for (const Enum value : all)
    if (std::strcmp(name, to_string(value)) == 0) {
      out = value;
      return true;
    }
  return false;
}

}  // namespace

bool parse_photometric(const char* name, Photometric& mode) {
  return parse_by_name(name, {Photometric::none, Photometric::affine, Photometric::ir, Photometric::ir_loop}, mode);
}

const char* to_string(Retirement rule) { return rule == Retirement::oldest ? "oldest" : "spread"; }

bool parse_retirement(const char* name, Retirement& rule) {
  return parse_by_name(name, {Retirement::oldest, Retirement::spread}, rule);
}

const char* to_string(KeyframeParallax rule) { return rule == KeyframeParallax::quantile ? "quantile" : "rms"; }

bool parse_keyframe_parallax(const char* name, KeyframeParallax& rule) {
  return parse_by_name(name, {KeyframeParallax::rms, KeyframeParallax::quantile}, rule);
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
  if (!kKeyframesRange.contains(c.max_keyframes)) return "max_keyframes outside kKeyframesRange";
  if (!kTauInitRange.contains(c.tau_init_s)) return "tau_init_s outside kTauInitRange";
  if (!(c.huber_counts > 0) || !(c.gradient_c > 0)) return "huber_counts and gradient_c must be positive";
  if (!kIntensityScaleRange.contains(c.intensity_scale)) return "intensity_scale outside kIntensityScaleRange";
  if (!kCarryCoringRange.contains(c.carry_coring)) return "carry_coring outside kCarryCoringRange";
  if (!kSmoothingRange.contains(c.smoothing)) return "smoothing outside kSmoothingRange";
  if (!kPointsPerKeyframeRange.contains(c.points_per_keyframe)) return "points_per_keyframe outside kPointsPerKeyframeRange";
  return nullptr;
}

}  // namespace bolo::vo

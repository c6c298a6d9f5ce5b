// Which keyframe leaves a full window.

#include <algorithm>

#include "keyframe_retirement.hpp"

#include "depth_search.hpp"
#include "initializer.hpp"
#include "map.hpp"

namespace bolo::vo {
namespace {

// A keyframe nearer than this share of the window's mean spacing to a neighbour along the path
// is crowded. Chosen on the study's walks and drives: much larger and the drives keep their
// oldest keyframes too long, whose points, far ahead, are seen zoomed.
constexpr double kCrowdedSpacing = 0.35;

double centre_distance(const Keyframe& a, const Keyframe& b) { return (a.T_cw * b.T_cw.inverse()).t.norm(); }

}  // namespace

std::uint32_t keyframe_to_retire(MapCore& s) {
  if (s.cfg.retirement == Retirement::oldest || builds_marginalisation_prior(s.cfg) || s.kf_count < 4) return 0;
  const Keyframe& oldest = s.kf[s.order[0]];
  const Keyframe& newest = s.kf[s.order[s.kf_count - 1]];
  const double span = centre_distance(oldest, newest);
  // A window without a baseline (a pan, a turn on the spot) has none to keep.
  const float typical = typical_idepth(s);
  if (!(typical > 0) || s.cfg.camera.fx * span * typical < baseline_flow_needed(s.cfg)) return 0;
  const double spacing = span / (s.kf_count - 1);
  std::uint32_t pick = 0;
  double nearest = kCrowdedSpacing * spacing;
  for (std::uint32_t k = 1; k + 2 < s.kf_count; ++k) {
    const Keyframe& kf = s.kf[s.order[k]];
    const double d = std::min(centre_distance(kf, s.kf[s.order[k - 1]]), centre_distance(kf, s.kf[s.order[k + 1]]));
    if (d < nearest) nearest = d, pick = k;
  }
  return pick;
}

}  // namespace bolo::vo

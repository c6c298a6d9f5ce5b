#pragma once
// Feeding the tau estimator with ground truth: raw frames pushed into the VO state with their
// true poses, and keyframes whose points sit at their true depth. Shared by the [tau] tests and
// the study harnesses in scripts/study/vo-experiments.

#include <algorithm>
#include <cstdint>
#include <utility>

#include "state.hpp"

namespace bolo::test {

// Approximately N(0, 1): the sum of 12 uniforms from a fixed LCG, the same on every platform.
class ApproxNormal {
 public:
  explicit ApproxNormal(std::uint32_t seed) : state_(seed) {}
  double operator()() {
    double sum = 0;
    for (int q = 0; q < 12; ++q) {
      state_ = state_ * 1664525u + 1013904223u;
      sum += static_cast<double>(state_ >> 8) / 16777216.0;
    }
    return sum - 6.0;
  }

 private:
  std::uint32_t state_;
};

// Frame k of an unbroken chain: the raw buffers move back one, fill_raw(s.current.raw) writes the new
// frame, and the frame's pose becomes T_cw (the previous one T_prev). As Odometry::process() in
// `ir` mode, the pixel noise is measured and the tracking image is the scene estimate made with
// the current tau (its carry-over correction cored against that noise).
template <typename FillRaw>
void push_truth_frame(vo::State& s, int k, double exposure_s, double readout_s, double t_s, const vo::Se3& T_cw,
                      FillRaw fill_raw) {
  std::swap(s.current.raw_prev, s.current.raw_prev2);
  std::swap(s.current.raw, s.current.raw_prev);
  fill_raw(s.current.raw);
  s.current.have_prev = k > 0;
  s.current.chain_ok_prev = k > 1;
  s.current.chain_ok = k > 0;
  s.current.exposure_prev_s = s.current.exposure_s;
  s.current.exposure_s = exposure_s, s.current.readout_prev_s = readout_s, s.current.t_s = t_s;
  s.motion.T_prev = s.motion.T_cw;
  s.motion.prev_posed = k > 0;
  s.motion.T_cw = T_cw;
  if (s.current.chain_ok && s.current.chain_ok_prev) vo::update_noise_variance(s.noise, s.current, s.cfg);
  if (s.current.chain_ok) {
    vo::write_scene_estimate(s.current, s.tau_est.tau, s.noise.var, s.cfg);
  } else {
    std::copy(s.current.raw.begin(), s.current.raw.end(), s.current.frame.level[0].value.data);
  }
  vo::build_frame_images(s.current, s.cfg);
}

// A keyframe made from the current frame's tracking image, its points active at inverse depth
// idepth_of(true depth) where depth_at(u, v) is in (0, 150) m, dropped elsewhere.
template <typename DepthAt, typename IdepthOf>
void keyframe_at_true_depth(vo::State& s, DepthAt depth_at, IdepthOf idepth_of) {
  const std::uint32_t slot = vo::new_keyframe_slot(s, s.retired, s.ba, s.prior);
  vo::make_keyframe(s, vo::keyframe_parts(s), slot, true);
  vo::Keyframe& kf = s.kf[slot];
  for (std::uint32_t i = 0; i < kf.count; ++i) {
    vo::Point& p = kf.points[i];
    const double z = depth_at(p.u, p.v);
    p.status = z > 0 && z < 150 ? vo::PointStatus::active : vo::PointStatus::empty;
    p.idepth = static_cast<float>(idepth_of(z));
    p.inlier = true;
  }
}

}  // namespace bolo::test

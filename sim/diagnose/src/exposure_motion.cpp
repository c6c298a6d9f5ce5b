#include "exposure_motion.hpp"

#include <algorithm>
#include <cmath>

#include "bolo/effects/scene_flow.hpp"
#include "bolo/effects/stats.hpp"

namespace bolo::diag {

void fill_exposure_motion(DiagnoseData& d, double tau_h) {
  const int N = d.shape.n, H = d.shape.height, W = d.shape.width;
  const std::size_t P = d.shape.pixels();
  d.exposure_motion.clear();
  if (!d.has_scene || N < 2 || !(tau_h > 0)) return;
  if (d.input_flow_dy.size() != d.shape.size()) fill_input_flow(d);
  std::vector<double> steps;
  for (int n = 1; n < N; ++n)
    if (d.t_s[n] > d.t_s[n - 1]) steps.push_back(d.t_s[n] - d.t_s[n - 1]);
  const double period = steps.empty() ? (d.fps > 0 ? 1.0 / d.fps : 0.0) : median_of(steps);
  if (!(period > 0)) return;
  constexpr int kSamples = 8;
  std::vector<float> in_dy, in_dx, out_dy, out_dx;
  std::vector<float> motion(d.shape.size(), 0.0f);
  bool any = false;
  out_dy.assign(P, 0.0f);
  out_dx.assign(P, 0.0f);
  for (int n = 0; n < N; ++n) {
    std::swap(in_dy, out_dy);
    std::swap(in_dx, out_dx);
    // The flow into the frame is frame n-1's flow out, from the step before.
    subpixel_input_flow(d, n + 1 < N ? n : -1, out_dy, out_dx);
    const bool has_in = n > 0 && !d.flagged_event[n], has_out = n + 1 < N && !d.flagged_event[n + 1];
    if (!has_in && !has_out) continue;
    const double te = d.exposure_s[n];
    if (!(te > 0)) continue;
    // Weights of the samples less the even average's, and each sample's time from mid-exposure in frames.
    double weight[kSamples], delay[kSamples], total = 0;
    for (int k = 0; k < kSamples; ++k) {
      const double s = (k + 0.5) / kSamples * te;
      weight[k] = std::exp(-(te - s) / tau_h);
      total += weight[k];
      delay[k] = (s - 0.5 * te) / period;
    }
    for (double& w : weight) w = w / total - 1.0 / kSamples;
    const float* u = d.frame(d.input, n);
    float* m = motion.data() + std::size_t(n) * P;
    auto at = [&](int r, int c) { return double(u[std::size_t(std::clamp(r, 0, H - 1)) * W + std::clamp(c, 0, W - 1)]); };
    // The flow out of the frame is measured on the next frame's pixels (where the content goes):
    // read it where this frame's content lands, found by following the flow (into the frame, or
    // out of it without one). At a moving object's trailing edge the same pixel of the next
    // frame shows the background, whose flow halved the object's motion there.
    auto landed = [&](const std::vector<float>& f, int r, int c, double vy, double vx) {
      const int rr = std::clamp(int(std::lround(r + vy)), 0, H - 1), cc = std::clamp(int(std::lround(c + vx)), 0, W - 1);
      return f[std::size_t(rr) * W + cc];
    };
    for (int r = 0; r < H; ++r)
      for (int c = 0; c < W; ++c) {
        const std::size_t p = std::size_t(r) * W + c;
        double oy = 0, ox = 0;
        if (has_out) {
          oy = has_in ? in_dy[p] : out_dy[p], ox = has_in ? in_dx[p] : out_dx[p];
          for (int pass = 0; pass < 2; ++pass) {
            const double ny = landed(out_dy, r, c, oy, ox), nx = landed(out_dx, r, c, oy, ox);
            oy = ny, ox = nx;
          }
        }
        const double vy = has_in && has_out ? 0.5 * (in_dy[p] + oy) : has_in ? in_dy[p] : oy;
        const double vx = has_in && has_out ? 0.5 * (in_dx[p] + ox) : has_in ? in_dx[p] : ox;
        if (vy == 0 && vx == 0) continue;
        double sum = 0;
        for (int k = 0; k < kSamples; ++k) {
          // The input at that time: the frame moved along the flow, input(x - v delay), bilinear.
          const double y = r - vy * delay[k], x = c - vx * delay[k];
          const int y0 = int(std::floor(y)), x0 = int(std::floor(x));
          const double fy = y - y0, fx = x - x0;
          sum += weight[k] * ((1 - fy) * ((1 - fx) * at(y0, x0) + fx * at(y0, x0 + 1)) +
                              fy * ((1 - fx) * at(y0 + 1, x0) + fx * at(y0 + 1, x0 + 1)));
        }
        m[p] = static_cast<float>(sum);
        any = any || m[p] != 0.0f;
      }
  }
  if (any) d.exposure_motion = std::move(motion);
}

}  // namespace bolo::diag

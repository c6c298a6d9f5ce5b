// The baseline model each recording is compared with (baseline.hpp).

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "bolo/diagnose/baseline.hpp"
#include "bolo/diagnose/far_off_pixels.hpp"
#include "bolo/diagnose/frame_start.hpp"
#include "bolo/sim/two_frame_sensor.hpp"
#include <Eigen/Dense>

#include "bolo/effects/stats.hpp"
#include "checkerboard.hpp"
#include "exposure_motion.hpp"

namespace bolo::diag {
namespace {

// The heating time constant the motion within the exposure is weighed with: its fitted share
// (exposure_motion) takes up the difference a sensor's own tau_h makes.
constexpr double kTypicalTauH = 0.012;
// The share of exposure_motion from which the baseline counts motion within the exposure as
// modelled (it masks the edges otherwise): 0.07-0.95 on scenes moving throughout the exposure
// (the timing shift shares its first-order part), ~0.01 where the input is constant within it or
// the flow misses the motion.
constexpr double kModelledShare = 0.05;

// Whether the frames' exposures differ: only then is tau_h more than a factor of the gain.
bool varies(const std::vector<double>& values) {
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  return *hi > *lo * (1 + 1e-9);
}
bool exposure_varies(const DiagnoseData& d) { return varies(d.exposure_s); }

// Eq. 6 with each frame's own coefficients (frames.csv's exposure and readout):
//   s_n = carry_n s_{n-1} + heat_n / heat_typ (1 - carry_typ) u_n,
// scaled to unit DC gain at the recording's median timing (typ), so the fitted gain stays the
// response of a typical frame. A frame whose timing departs from the median reads its own level.
// The first frame starts from its input, a flagged shutter frame from a uniform shutter at the
// scene's mean level (the shutter is at the camera's temperature), settled at the median timing
// (the frames before are not logged: the camera ran at its typical timing) and carried over a
// median readout into the frame's own exposure:
//   s_n = restart_n L + weight_n u_n,  restart_n = carry_typ  (L: the first frame's input, or the
// shutter's level). With `nominal_timing`, every frame has the median exposure and readout.
FrameSteps frame_steps(const DiagnoseData& d, double tau_c, double tau_h, bool nominal_timing) {
  const double exposure_median = median_of(d.exposure_s), readout_median = median_of(d.readout_s);
  auto exposure = [&](int n) { return nominal_timing ? exposure_median : d.exposure_s[n]; };
  auto readout = [&](int n) { return nominal_timing ? readout_median : d.readout_s[n]; };
  const sim::FrameCoefficients typical = sim::frame_coefficients(exposure_median, readout_median, tau_h, tau_c);
  const double scale = (1 - typical.carry) / typical.heat;
  // A pixel settled on a unit input at the median timing reads 1; without cooling (no readout)
  // there is no steady state and it starts from nothing.
  const double restart = typical.carry < 1 - 1e-12 ? typical.carry : 0.0;
  const int N = d.shape.n;
  FrameSteps f{std::vector<double>(N, 0.0), std::vector<double>(N, 0.0), std::vector<double>(N, 0.0)};
  for (int n = 0; n < N; ++n) {
    const sim::FrameCoefficients k = sim::frame_coefficients(exposure(n), readout(std::max(0, n - 1)), tau_h, tau_c);
    f.weight[n] = scale * k.heat;
    if (restarts(d, n)) f.restart[n] = restart;
    else f.carry[n] = k.carry;
  }
  return f;
}

// d(frame_steps)/d(ln tau) with both time constants scaled together (central differences).
FrameSteps frame_steps_per_ln_tau(const DiagnoseData& d, double tau_c, double tau_h) {
  constexpr double h = 1e-4;
  const double up = std::exp(h), down = std::exp(-h);
  const FrameSteps a = frame_steps(d, tau_c * up, tau_h * up, false), b = frame_steps(d, tau_c * down, tau_h * down, false);
  FrameSteps f = a;
  for (std::size_t n = 0; n < f.carry.size(); ++n) {
    f.carry[n] = (a.carry[n] - b.carry[n]) / (2 * h);
    f.weight[n] = (a.weight[n] - b.weight[n]) / (2 * h);
    f.restart[n] = (a.restart[n] - b.restart[n]) / (2 * h);
  }
  return f;
}

// Frame n's reading of a constant unit input under `f` (1 throughout at the median timing): the
// level a frame's own timing gives every pixel alike.
std::vector<double> unit_response(const FrameSteps& f) {
  std::vector<double> q(f.weight.size());
  for (std::size_t n = 0; n < q.size(); ++n)
    q[n] = f.restart[n] + f.weight[n] + (n > 0 ? f.carry[n] * q[n - 1] : 0.0);
  return q;
}

// `input` (default scene.npy) is what drives it, e.g. d.exposure_motion for that term's response.
void two_frame(const DiagnoseData& d, const FrameSteps& f, std::vector<float>& sim, const std::vector<float>* input = nullptr) {
  const std::vector<float>& in = input ? *input : d.input;
  const std::size_t P = d.shape.pixels();
  sim.resize(d.shape.size());
  for (int n = 0; n < d.shape.n; ++n) {
    const float c = static_cast<float>(f.carry[n]), w = static_cast<float>(f.weight[n]);
    const float* u = d.frame(in, n);
    float* s = d.frame(sim, n);
    const FrameStart start = frame_start(d, in, n);
    if (start.kind == FrameStart::own_input) {
      const float g = static_cast<float>(f.restart[n] + f.weight[n]);
      for (std::size_t p = 0; p < P; ++p) s[p] = g * u[p];
    } else if (start.kind == FrameStart::shutter) {
      const float shutter = static_cast<float>(start.level * f.restart[n]);
      for (std::size_t p = 0; p < P; ++p) s[p] = shutter + w * u[p];
    } else {
      const float* prev = d.frame(sim, n - 1);
      for (std::size_t p = 0; p < P; ++p) s[p] = c * prev[p] + w * u[p];
    }
  }
}
void two_frame(const DiagnoseData& d, double tau_c, double tau_h, std::vector<float>& sim, bool nominal_timing = false,
               const std::vector<float>* input = nullptr) {
  two_frame(d, frame_steps(d, tau_c, tau_h, nominal_timing), sim, input);
}

// The timing term's regressor, how the reading changes per frame as the scene changes:
//   rate_n = after_n s_{n+1} + centre_n s_n - before_n s_{n-1},
// sim's central difference (one-sided in the first and last frame) with each frame's unit
// response q divided out and put back: after_n = q_n / (2 q_{n+1}), before_n = q_n / (2 q_{n-1})
// inside: the plain difference also holds the level changes a jittered exposure or readout makes,
// which a fitted timing shift would turn into a frame-to-frame global offset.
struct RateWeights {
  std::vector<double> before, centre, after;
};
RateWeights rate_weights(const std::vector<double>& q) {
  const int N = static_cast<int>(q.size());
  RateWeights r{std::vector<double>(N, 0.0), std::vector<double>(N, 0.0), std::vector<double>(N, 0.0)};
  if (N < 2) return r;
  for (int n = 1; n + 1 < N; ++n) {
    r.before[n] = 0.5 * q[n] / q[n - 1];
    r.after[n] = 0.5 * q[n] / q[n + 1];
  }
  r.after[0] = q[0] / q[1], r.centre[0] = -1;
  r.centre[N - 1] = 1, r.before[N - 1] = q[N - 1] / q[N - 2];
  return r;
}
RateWeights rate_weights(const FrameSteps& f) { return rate_weights(unit_response(f)); }
// Frame n's neighbours for the rate (the frame itself standing in at either end).
const float* rate_before(const DiagnoseData& d, const float* s, int n) { return n > 0 ? s - d.shape.pixels() : s; }
const float* rate_after(const DiagnoseData& d, const float* s, int n) { return n + 1 < d.shape.n ? s + d.shape.pixels() : s; }
std::vector<float> scene_rate(const DiagnoseData& d, const std::vector<float>& sim, const RateWeights& w) {
  const std::size_t P = d.shape.pixels();
  std::vector<float> rate(sim.size(), 0.0f);
  for (int n = 0; n < d.shape.n; ++n) {
    const float a = static_cast<float>(w.after[n]), c = static_cast<float>(w.centre[n]), b = static_cast<float>(w.before[n]);
    const float* s = d.frame(sim, n);
    const float *before = rate_before(d, s, n), *after = rate_after(d, s, n);
    float* r = rate.data() + std::size_t(n) * P;
    for (std::size_t p = 0; p < P; ++p) r[p] = a * after[p] + c * s[p] - b * before[p];
  }
  return rate;
}

struct LinearFit {
  double gain = 1, offset = 0, sse = 0;
};

LinearFit fit_gain_offset(const DiagnoseData& d, const std::vector<float>& sim, const std::vector<std::uint8_t>& use) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
  const std::size_t P = d.shape.pixels();
  for (std::size_t first = 0; first < sim.size(); first += P) {
    const std::uint8_t* valid = d.valid.data() + first;
    const float *s = sim.data() + first, *r = d.recorded.data() + first;
    for (std::size_t p = 0; p < P; ++p) {
      if (!valid[p] || !use[p]) continue;
      const double x = s[p], y = r[p];
      n += 1; sx += x; sy += y; sxx += x * x; sxy += x * y; syy += y * y;
    }
  }
  LinearFit f;
  const double vx = sxx - sx * sx / n, cxy = sxy - sx * sy / n, vy = syy - sy * sy / n;
  f.gain = vx > 1e-9 * std::max(1.0, sxx) ? cxy / vx : 1.0;
  f.offset = (sy - f.gain * sx) / n;
  f.sse = std::max(0.0, vy - f.gain * cxy);
  return f;
}

// The normal equations of x = [sim, 1, rate, motion] and y'y, summed term by term as a rank-one
// update of the lower triangle would (x_i x_j per pixel-frame, in pixel-frame order), written out:
// the generic update of a 4x4 per pixel-frame was most of the tau searches' time. A column left
// out (kRate, kMotion false) is zero, and its sums stay 0 without being taken.
struct NormalSums {
  double s00 = 0, s10 = 0, s11 = 0, s20 = 0, s21 = 0, s22 = 0, s30 = 0, s31 = 0, s32 = 0, s33 = 0;
  double t0 = 0, t1 = 0, t2 = 0, t3 = 0, yy = 0;
};
template <bool kRate, bool kMotion>
NormalSums normal_sums(const DiagnoseData& d, const std::vector<float>& sim, const RateWeights& rate,
                       const std::vector<float>& motion, const std::vector<std::uint8_t>& use) {
  const std::size_t P = d.shape.pixels();
  NormalSums a;
  // Centred on a typical reading: the sums stay small beside the residual they are to resolve.
  const double centre = d.recorded.empty() ? 0.0 : d.recorded[d.recorded.size() / 2];
  for (int n = 0; n < d.shape.n; ++n) {
    const std::size_t first = std::size_t(n) * P;
    const std::uint8_t* valid = d.valid.data() + first;
    const float* s = sim.data() + first;
    // The frames before and after (no pointer outside the recording is formed).
    const float* s_before = kRate ? rate_before(d, s, n) : s;
    const float* s_after = kRate ? rate_after(d, s, n) : s;
    const float* y_n = d.recorded.data() + first;
    const float* m = kMotion ? motion.data() + first : nullptr;
    const double after = kRate ? rate.after[n] : 0.0, before = kRate ? rate.before[n] : 0.0;
    const double middle = kRate ? rate.centre[n] : 0.0;
    for (std::size_t p = 0; p < P; ++p) {
      if (!valid[p] || !use[p]) continue;
      const double x0 = s[p] - centre, x1 = 1.0;
      const double y = y_n[p] - centre;
      a.s00 += x0 * x0; a.s10 += x0 * x1; a.s11 += x1 * x1;
      a.t0 += x0 * y; a.t1 += x1 * y;
      double x2 = 0;
      if constexpr (kRate) {
        x2 = after * s_after[p] + middle * s[p] - before * s_before[p];
        a.s20 += x0 * x2; a.s21 += x1 * x2; a.s22 += x2 * x2; a.t2 += x2 * y;
      }
      if constexpr (kMotion) {
        const double x3 = m[p];
        a.s30 += x0 * x3; a.s31 += x1 * x3; a.s33 += x3 * x3; a.t3 += x3 * y;
        if constexpr (kRate) a.s32 += x2 * x3;
      }
      a.yy += y * y;
    }
  }
  return a;
}

// The residual of a least-squares fit of the recording on [sim, 1, its scene rate (scene_rate)
// if `shift`, motion if not empty]: gain, offset, the timing shift and the response to motion
// within the exposure (exposure_motion) as the final fit (fit_two_frame, below) has them. The tau
// searches score with it: scored on gain and offset alone, tau_c stood in for motion within the
// exposure (a shorter tau_c also reads a moving scene later) and came out up to 10 % short on a
// panning scene, and a readout jittered from frame to frame then left a global offset fluctuation
// the baseline lacked. (The exposure offset stays out: beside it tau_h, which the searches also
// set, is nearly degenerate.)
// `rate`: null for no shift.
double fit_sse(const DiagnoseData& d, const std::vector<float>& sim, const RateWeights* rate,
               const std::vector<float>& motion, const std::vector<std::uint8_t>& use) {
  const bool shift = rate != nullptr;
  if (!shift && motion.empty()) return fit_gain_offset(d, sim, use).sse;
  static const RateWeights none;
  const RateWeights& w = shift ? *rate : none;
  const NormalSums a = shift ? (motion.empty() ? normal_sums<true, false>(d, sim, w, motion, use)
                                               : normal_sums<true, true>(d, sim, w, motion, use))
                             : normal_sums<false, true>(d, sim, w, motion, use);
  Eigen::Matrix4d xtx;
  xtx << a.s00, a.s10, a.s20, a.s30, a.s10, a.s11, a.s21, a.s31, a.s20, a.s21, a.s22, a.s32, a.s30, a.s31, a.s32, a.s33;
  const Eigen::Vector4d xty(a.t0, a.t1, a.t2, a.t3);
  const double yy = a.yy;
  if (!shift) xtx(2, 2) = 1;  // columns left out: zero, solved as 0
  if (motion.empty()) xtx(3, 3) = 1;
  const Eigen::Vector4d beta = xtx.ldlt().solve(xty);
  // The final fit's own guard: a shift beyond half a frame is no timing; the fit without it stands.
  if (!beta.allFinite() || beta[0] == 0 || std::fabs(beta[2] / beta[0]) > 0.5)
    return shift ? fit_sse(d, sim, nullptr, motion, use) : fit_gain_offset(d, sim, use).sse;
  return std::max(0.0, yy - beta.dot(xty));
}

// The minimum of cost(log tau) on [lo, hi]: a coarse grid, then golden section inside the best bracket.
template <typename Cost>
double log_search(Cost cost, double lo, double hi) {
  const int grid = 16;
  int best = 0;
  std::vector<double> costs(grid + 1);
  for (int g = 0; g <= grid; ++g) {
    costs[g] = cost(lo + (hi - lo) * g / grid);
    if (costs[g] < costs[best]) best = g;
  }
  double a = lo + (hi - lo) * std::max(0, best - 1) / grid, b = lo + (hi - lo) * std::min(grid, best + 1) / grid;
  const double phi = 0.5 * (std::sqrt(5.0) - 1);
  double x1 = b - phi * (b - a), x2 = a + phi * (b - a), f1 = cost(x1), f2 = cost(x2);
  for (int it = 0; it < 14; ++it) {
    if (f1 < f2) { b = x2; x2 = x1; f2 = f1; x1 = b - phi * (b - a); f1 = cost(x1); }
    else { a = x1; x1 = x2; f1 = f2; x2 = a + phi * (b - a); f2 = cost(x2); }
  }
  return 0.5 * (a + b);
}

// `motion`: pixel-frames to leave out of the fit (mask_scene_motion), or null for none.
BaselineFit fit_two_frame(DiagnoseData& d, const std::vector<std::uint8_t>* motion = nullptr) {
  if (motion) d.valid = *motion; else d.reset_valid();
  const std::size_t P = d.shape.pixels();
  std::vector<float> sim, sim_motion;  // the responses to scene.npy and to exposure_motion
  std::vector<std::uint8_t> use(P, 1);
  // tau_h only shapes how a frame's exposure sets its level: with one exposure throughout it is
  // a factor of the gain, held at tau_c; otherwise it is searched for (below).
  const bool fit_tau_h = exposure_varies(d);
  double tau_c = 0.012, tau_h = 0.012;
  // With the timing varying from frame to frame the searches score with the timing shift in the
  // model (fit_sse): there a tau_c standing in for motion shows as a global offset
  // fluctuation. With one timing throughout they score on gain and offset, as before: the shift
  // then only trades with tau_c within the transients, and the refit after a finding, compared
  // over every pixel (stuck ones included), is sensitive to the small change in tau_c.
  const bool timing_varies = fit_tau_h || varies(d.readout_s);
  RateWeights rate_w;
  auto sse = [&] { return fit_sse(d, sim, timing_varies ? &rate_w : nullptr, sim_motion, use); };
  auto simulate = [&](double tc, double th) {
    const FrameSteps steps = frame_steps(d, tc, th, false);
    rate_w = rate_weights(steps);
    two_frame(d, steps, sim);
    if (!d.exposure_motion.empty()) two_frame(d, steps, sim_motion, &d.exposure_motion);
  };
  auto cost = [&](double log_tau) {
    simulate(std::exp(log_tau), fit_tau_h ? tau_h : std::exp(log_tau));
    return sse();
  };
  auto cost_tau_h = [&](double log_tau_h) {
    simulate(tau_c, std::exp(log_tau_h));
    return sse();
  };
  // Pixels far off the model (stuck, dead) would pull gain and tau: a first fit at a typical
  // tau finds them, and the fit proper leaves them out (they stay in the data for dead_pixels).
  {
    cost(std::log(0.012));
    const LinearFit first = fit_gain_offset(d, sim, use);
    const std::vector<std::uint8_t> far = far_off_pixels(
        d, [&](std::size_t i) { return d.recorded[i] - first.gain * sim[i] - first.offset; });
    for (std::size_t p = 0; p < P; ++p) use[p] = !far[p];
  }
  // Frames repeated bit for bit are copies, not readings of their own time: not for the fit.
  std::vector<int> repeats;
  for (int n = 1; n < d.shape.n; ++n) {
    const float *y = d.frame(d.recorded, n), *yp = d.frame(d.recorded, n - 1);
    std::size_t same = 0;
    for (std::size_t p = 0; p < P; ++p) same += y[p] == yp[p];
    if (same >= P - P / 1000) repeats.push_back(n);
  }
  if (int(repeats.size()) * 2 < d.shape.n)
    for (int n : repeats) std::fill_n(d.valid.begin() + std::size_t(n) * P, P, 0);
  auto restore_valid = [&] { if (motion) d.valid = *motion; else d.reset_valid(); };
  BaselineFit fit;
  fit.model = "two-frame";
  // tau_c and tau_h act through different frames (changes of the input, changes of the exposure):
  // one search each way, then tau_c again with tau_h in place. The refits that follow (masks,
  // findings) keep the first fit's tau_h and search tau_c alone.
  const bool search_tau_h = fit_tau_h && !(d.tau_h_s > 0);
  if (fit_tau_h && !search_tau_h) tau_h = d.tau_h_s;
  tau_c = std::exp(log_search(cost, std::log(2e-4), std::log(0.3)));
  if (search_tau_h) {
    tau_h = std::exp(log_search(cost_tau_h, std::log(2e-4), std::log(1.0)));
    tau_c = std::exp(log_search(cost, std::log(2e-4), std::log(0.3)));
    d.tau_h_s = tau_h;
  }
  fit.tau_c_s = tau_c;
  simulate(tau_c, fit_tau_h ? tau_h : tau_c);
  const LinearFit lin = fit_gain_offset(d, sim, use);
  fit.gain = lin.gain;
  fit.offset = lin.offset;
  // Motion within an exposure: the pixel weighs the late part of its exposure more, so it reads
  // the scene a little later than scene.npy's exposure average. One timing shift, in frames.
  const std::vector<float> rate = scene_rate(d, sim, rate_w);
  // A sensor whose offset moves with its exposure (a dark signal integrated over t_e): an offset
  // in proportion to the frame's departure from the median exposure, when the exposures differ.
  std::vector<double> exposure_change(d.shape.n, 0.0);
  const double typical_exposure = median_of(d.exposure_s);
  for (int n = 0; n < d.shape.n; ++n) exposure_change[n] = d.exposure_s[n] / typical_exposure - 1;
  const bool with_motion = !sim_motion.empty();
  {
    const int motion_column = fit_tau_h ? 4 : 3;
    const int k = motion_column + (with_motion ? 1 : 0);
    Eigen::MatrixXd xtx = Eigen::MatrixXd::Zero(k, k);
    Eigen::VectorXd xty = Eigen::VectorXd::Zero(k), x(k);
    for (std::size_t i = 0; i < sim.size(); ++i) {
      if (!d.valid[i] || !use[i % P]) continue;
      x[0] = sim[i], x[1] = 1.0, x[2] = rate[i];
      if (fit_tau_h) x[3] = exposure_change[i / P];
      if (with_motion) x[motion_column] = sim_motion[i];
      xtx.selfadjointView<Eigen::Lower>().rankUpdate(x);
      xty += x * double(d.recorded[i]);
    }
    xtx = xtx.selfadjointView<Eigen::Lower>();
    const Eigen::VectorXd beta = xtx.ldlt().solve(xty);
    // A pixel reads within its own exposure: a shift beyond half a frame is no timing but the
    // regressor standing in for something else (or a gain near zero); the plain fit then stands.
    if (beta.allFinite() && beta[0] != 0 && std::fabs(beta[2] / beta[0]) <= 0.5) {
      fit.gain = beta[0];
      fit.offset = beta[1];
      fit.timing_frames = beta[2] / beta[0];
      if (fit_tau_h) fit.exposure_offset = beta[3];
      if (with_motion) fit.exposure_motion = beta[motion_column] / beta[0];
    }
  }
  const double period = 1.0 / d.fps;
  const double carry = std::exp(-median_of(d.readout_s) / fit.tau_c_s);
  fit.tau_identifiable = std::exp(-period / 0.3) > 1e-3 && carry > 1e-3;
  // y = G s with s of unit DC gain: the heating fraction k = G (1 - c) if the sensor gain is 1.
  const double k = fit.gain * (1 - carry);
  const double te = median_of(d.exposure_s);
  fit.tau_h_fitted = fit_tau_h;
  fit.tau_h_s = fit_tau_h ? tau_h : (k > 0 && k < 1) ? -te / std::log(1 - k) : fit.tau_c_s;
  fit.assumption = std::string("scene.npy drives the two-frame model with each frame's exposure and readout (frames.csv; ") +
                   std::to_string(d.timing_filled) + " frame(s) with missing timing filled in); " +
                   (fit_tau_h ? "tau_h fitted to the level changes of frames with other exposures, and an offset "
                                "in proportion to the exposure's departure from the median"
                              : "one exposure throughout: tau_h from the DC gain assuming unit sensor gain");
  restore_valid();
  d.baseline.resize(d.shape.size());
  for (std::size_t i = 0; i < sim.size(); ++i)
    d.baseline[i] = float(fit.gain * (sim[i] + fit.timing_frames * rate[i] +
                                      (with_motion ? fit.exposure_motion * sim_motion[i] : 0.0)) +
                          fit.offset + fit.exposure_offset * exposure_change[i / P]);
  const double tau_h_used = fit_tau_h ? tau_h : tau_c;
  d.steps = frame_steps(d, tau_c, tau_h_used, false);
  d.steps_per_ln_tau = frame_steps_per_ln_tau(d, tau_c, tau_h_used);
  d.within_exposure.clear();
  if (fit.timing_frames != 0 || with_motion) {
    d.within_exposure.resize(d.shape.size());
    for (std::size_t i = 0; i < sim.size(); ++i)
      d.within_exposure[i] = float(fit.gain * (fit.timing_frames * rate[i] + (with_motion ? fit.exposure_motion * sim_motion[i] : 0.0)));
  }
  d.baseline_nominal.clear();
  if (varies(d.exposure_s) || varies(d.readout_s)) {
    two_frame(d, tau_c, fit_tau_h ? tau_h : tau_c, sim, true);
    if (with_motion) two_frame(d, tau_c, fit_tau_h ? tau_h : tau_c, sim_motion, true, &d.exposure_motion);
    // At the median timing every frame's unit response is 1 (the ends' too).
    const std::vector<float> nominal_rate = scene_rate(d, sim, rate_weights(std::vector<double>(d.shape.n, 1.0)));
    d.baseline_nominal.resize(d.shape.size());
    for (int n = 0; n < d.shape.n; ++n)
      for (std::size_t p = 0; p < P; ++p) {
        const std::size_t i = std::size_t(n) * P + p;
        const double slope = nominal_rate[i];
        const double motion = with_motion ? fit.exposure_motion * sim_motion[i] : 0.0;
        d.baseline_nominal[i] = float(fit.gain * (sim[i] + fit.timing_frames * slope + motion) + fit.offset);
      }
  }
  return fit;
}

BaselineFit fit_static_background(DiagnoseData& d) {
  const int N = d.shape.n;
  const std::size_t P = d.shape.pixels();
  // Frames at or right after a flagged shutter event are not scene.
  std::vector<int> scene_frames;
  for (int n = 0; n < N; ++n)
    if (!d.flagged_event[n] && !(n > 0 && d.flagged_event[n - 1])) scene_frames.push_back(n);
  if (scene_frames.empty())
    for (int n = 0; n < N; ++n) scene_frames.push_back(n);
  std::vector<float> background(P), column(scene_frames.size());
  for (std::size_t p = 0; p < P; ++p) {
    for (std::size_t i = 0; i < scene_frames.size(); ++i) column[i] = d.recorded[std::size_t(scene_frames[i]) * P + p];
    background[p] = median_in_place(column);
  }
  // Moving objects: far from the background once the frame's common shift is removed.
  std::vector<float> shift(N), dev(P);
  for (int n = 0; n < N; ++n) {
    const float* y = d.frame(d.recorded, n);
    for (std::size_t p = 0; p < P; ++p) dev[p] = y[p] - background[p];
    shift[n] = median_in_place(dev);
  }
  std::vector<float> sample;
  const std::size_t stride = std::max<std::size_t>(1, d.shape.size() / 200000);
  for (std::size_t i = 0; i < d.shape.size(); i += stride)
    sample.push_back(std::fabs(d.recorded[i] - background[i % P] - shift[i / P]));
  const double spread = std::max(1e-6, 1.4826 * median_in_place(sample));
  d.reset_valid();
  std::size_t masked = 0;
  const int H = d.shape.height, W = d.shape.width;
  for (int n = 0; n < N; ++n) {
    const float* y = d.frame(d.recorded, n);
    std::uint8_t* v = d.valid.data() + std::size_t(n) * P;
    std::vector<std::uint8_t> moving(P, 0);
    for (std::size_t p = 0; p < P; ++p) moving[p] = std::fabs(y[p] - background[p] - shift[n]) > 6 * spread;
    // One pixel of margin: the blurred edge of a moving object is below the threshold.
    for (int r = 0; r < H; ++r)
      for (int c = 0; c < W; ++c) {
        bool near = false;
        for (int dr = -1; dr <= 1 && !near; ++dr)
          for (int dc = -1; dc <= 1 && !near; ++dc) {
            const int rr = r + dr, cc = c + dc;
            near = rr >= 0 && rr < H && cc >= 0 && cc < W && moving[std::size_t(rr) * W + cc];
          }
        if (near) { v[std::size_t(r) * W + c] = 0; ++masked; }
      }
  }
  d.input.resize(d.shape.size());
  d.baseline.resize(d.shape.size());
  for (int n = 0; n < N; ++n) {
    std::copy(background.begin(), background.end(), d.frame(d.input, n));
    std::copy(background.begin(), background.end(), d.frame(d.baseline, n));
  }
  d.baseline_nominal.clear();
  d.steps = d.steps_per_ln_tau = FrameSteps{};
  d.within_exposure.clear();
  BaselineFit fit;
  fit.model = "static-background";
  fit.assumption =
      "no scene.npy: static camera assumed; the scene is the per-pixel median over frames that are not "
      "shutter events (or the frame after one), moving objects (more than 6 sigma from it after removing "
      "each frame's common shift, plus one pixel of margin) are masked out of every fit";
  fit.moving_fraction = double(masked) / double(d.shape.size());
  const double period = 1.0 / d.fps;
  fit.tau_identifiable = false;  // a static scene has no transients to fit tau on
  fit.tau_c_s = fit.tau_h_s = std::numeric_limits<double>::quiet_NaN();
  (void)period;
  return fit;
}

// scene.npy holds one image per frame (the exposure average), but a camera integrates the scene
// as it moves during the exposure, weighting the late part more (tau_h). The timing term of the
// fit models that to first order; where the scene steps between frames (a moving edge) the rest
// is a large unknown miss (hundreds of counts at an edge crossing a pixel mid-exposure) that no
// catalogue effect should be fitted to. The miss was measured at ~5 x |step| x |timing shift|
// (500 counts at the 4000-count edges of street/drive, timing 0.026 frames) and is carried into
// later frames by the cooling carry c = exp(-t_r / tau_c). A pixel-frame is masked out of every
// fit (like a moving object without a scene) while that estimate, steps n-1..n and n..n+1 plus
// the carried part, exceeds half a noise sigma. With no motion within the exposure the timing
// shift is ~0 and nothing is masked: the model is then the plain two-frame one.
double mask_scene_motion(DiagnoseData& d, const BaselineFit& fit, double sigma) {
  const int N = d.shape.n;
  const std::size_t P = d.shape.pixels();
  // Only a late reading (positive shift) is motion within the exposure: the late part weighs more.
  // A negative shift comes from something else (a tau changing with temperature) and masks nothing.
  const double per_count = 5.0 * std::max(0.0, fit.timing_frames) * std::fabs(fit.gain);
  const double carry = std::exp(-median_of(d.readout_s) / fit.tau_c_s);
  auto step = [&](int n, std::size_t p) {  // |scene step from n-1 to n|, 0 outside or at a shutter event
    if (n < 1 || n >= N || d.flagged_event[n]) return 0.0;
    return std::fabs(double(d.input[std::size_t(n) * P + p]) - d.input[std::size_t(n - 1) * P + p]);
  };
  std::size_t masked = 0;
  for (std::size_t p = 0; p < P; ++p) {
    double miss = 0;
    for (int n = 0; n < N; ++n) {
      if (d.flagged_event[n]) miss = 0;  // the shutter resets the pixel's history
      miss = std::max(carry * miss, per_count * std::max(step(n, p), step(n + 1, p)));
      std::uint8_t& v = d.valid[std::size_t(n) * P + p];
      if (miss > 0.5 * sigma) v = 0;
      masked += !v;
    }
  }
  return double(masked) / double(d.shape.size());
}

// The first-order timing term can miss motion within the exposure altogether: a sharp object
// moving many pixels per frame reads nothing like a shifted time (its fitted shift came out ~0 on
// the demo scene at 320x256, with misses of hundreds of counts at its edges and eight false
// findings). So the misses are also measured directly: pixel-frames are binned by the scene step
// to or from the frame (carried on by the cooling carry), and from the largest steps down, every
// bin whose residual RMS is above 3 noise sigma (and 3 times what the static pixels leave) is masked.
// A concealed effect (below the noise) never lifts a bin that high; the baseline's own misses at
// fast edges do.
double mask_large_misses(DiagnoseData& d, const BaselineFit& fit, double sigma) {
  const int N = d.shape.n;
  const std::size_t P = d.shape.pixels();
  const double carry = std::exp(-median_of(d.readout_s) / fit.tau_c_s);
  const double unit = std::max(1e-9, sigma / std::max(1e-9, std::fabs(fit.gain)));  // one sigma of input
  constexpr int kBins = 24;  // step / unit in powers of two, from below 1 to above 2^22
  auto bin_of = [&](double step) {
    const double x = step / unit;
    return x < 1 ? 0 : std::min(kBins - 1, 1 + static_cast<int>(std::log2(x)));
  };
  std::vector<std::uint8_t> bin(d.shape.size(), 0);
  std::vector<double> sse(kBins, 0.0), count(kBins, 0.0);
  for (std::size_t p = 0; p < P; ++p) {
    double miss = 0;
    for (int n = 0; n < N; ++n) {
      if (d.flagged_event[n]) miss = 0;
      auto step = [&](int m) {
        if (m < 1 || m >= N || d.flagged_event[m]) return 0.0;
        return std::fabs(double(d.input[std::size_t(m) * P + p]) - d.input[std::size_t(m - 1) * P + p]);
      };
      miss = std::max(carry * miss, std::max(step(n), step(n + 1)));
      const std::size_t i = std::size_t(n) * P + p;
      bin[i] = static_cast<std::uint8_t>(bin_of(miss));
      if (!d.valid[i]) continue;
      const double r = double(d.recorded[i]) - d.baseline[i];
      sse[bin[i]] += r * r;
      count[bin[i]] += 1;
    }
  }
  // A miss is relative to what the static pixels (bin 0) leave: a global effect the baseline lacks
  // (an AGC, a drift) raises every bin alike and must stay in the data for its candidate.
  const double still = count[0] > 0 ? std::sqrt(sse[0] / count[0]) : sigma;
  const double limit = std::max(3 * sigma, 3 * still);
  int lowest = kBins;  // bins from `lowest` up are masked
  for (int b = kBins - 1; b >= 1; --b) {
    if (count[b] < 50) { if (lowest == b + 1) lowest = b; continue; }  // too few to judge: with the bin above
    if (std::sqrt(sse[b] / count[b]) > limit) lowest = b;
    else break;
  }
  if (lowest >= kBins) return 0.0;
  std::size_t masked = 0;
  for (std::size_t i = 0; i < bin.size(); ++i)
    if (bin[i] >= lowest && d.valid[i]) { d.valid[i] = 0; ++masked; }
  // Nothing masked if every bin above was empty.
  return double(masked) / double(d.shape.size());
}

}  // namespace

BaselineFit fit_baseline(DiagnoseData& d) {
  // Once per recording (the refits after findings reuse it): the flow and the motion within the
  // exposure, weighed with a typical tau_h (its share is fitted, exposure_motion below).
  if (d.has_scene && d.input_flow_dy.empty()) fill_exposure_motion(d, kTypicalTauH);
  BaselineFit fit = d.has_scene ? fit_two_frame(d) : fit_static_background(d);
  if (d.has_scene) {
    const double sigma = noise_floor(d, false);
    // Unless the motion within the exposure along the flow takes a twentieth of the reading or more
    // (none within the exposure, or the flow missed it: the first-order timing shift is then all
    // the model has), the edges' misses would also pull tau, gain and timing: mask, fit again
    // without them, and mask again with the refitted timing. Where it does, the edges are
    // modelled: masked, they left only the pixels where the motion is below the noise to fit its
    // share on (0.25 where it took 0.74 on a moving null).
    // The masks for motion the term does not model (below), then the large misses (after).
    auto mask_unmodelled_motion = [&] {
      // Then the term is left out of this and every refit: the model is the one before it.
      if (!d.exposure_motion.empty()) {
        d.exposure_motion.clear();
        fit = fit_two_frame(d);
      }
      mask_scene_motion(d, fit, sigma);
      const std::vector<std::uint8_t> motion = d.valid;
      if (std::find(motion.begin(), motion.end(), 0) != motion.end()) {
        fit = fit_two_frame(d, &motion);
        d.reset_valid();
        fit.moving_fraction = mask_scene_motion(d, fit, sigma);
        // The refit says there is no motion within the exposure after all (its timing shift, free
        // of the edges, is <= 0): the unmasked fit is the consistent one.
        if (fit.moving_fraction == 0) fit = fit_two_frame(d);
      }
    };
    auto mask_large_misses_and_refit = [&] {
      // Again after each refit: the first fit, pulled by the misses, also leaves the static pixels
      // a residual that hides the smaller misses.
      for (int pass = 0; pass < 3 && mask_large_misses(d, fit, sigma) > 0; ++pass) {
        const std::vector<std::uint8_t> mask = d.valid;
        fit = fit_two_frame(d, &mask);
        std::size_t masked = 0;
        for (std::size_t i = 0; i < mask.size(); ++i) masked += !mask[i] && (d.unclipped.empty() || d.unclipped[i]);
        fit.moving_fraction = double(masked) / double(mask.size());
        fit.large_miss_mask = true;
      }
    };
    const bool modelled = fit.exposure_motion >= kModelledShare;
    if (!modelled) mask_unmodelled_motion();
    mask_large_misses_and_refit();
    // Decided on the fit that stands: a share the edges' largest misses had lifted over the line
    // and that falls under it once they are masked does not model the motion either.
    if (modelled && !(fit.exposure_motion >= kModelledShare)) {
      d.reset_valid();
      fit = fit_two_frame(d);
      mask_unmodelled_motion();
      mask_large_misses_and_refit();
    }
    fit.assumption += std::string(d.exposure_motion.empty()
                          ? "; motion within the exposure is modelled to first order (timing shift; the term along "
                            "the flow took under a twentieth of it and is left out); pixel-frames "
                            "where the rest (estimated as 5 x max(0, timing shift) x |scene step to or from the "
                            "frame|, carried on by the cooling carry) exceeds half a noise sigma are masked out of "
                            "every fit (moving_fraction); so are pixel-frames whose scene step falls in a range of "
                            "steps "
                          : "; motion within the exposure: scene.npy's frame moved along the measured flow across "
                            "each exposure and weighed by the pixel's response (exposure_motion: its share, fitted), "
                            "plus a first-order timing shift; pixel-frames whose scene step falls in a range of steps ") +
                      "where the baseline misses by more than 3 noise sigma RMS (large_miss_mask)";
  }
  double sum = 0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < d.baseline.size(); i += 7) { sum += d.baseline[i]; ++count; }
  d.level_mid = sum / double(std::max<std::size_t>(1, count));
  return fit;
}

nlohmann::json BaselineFit::to_json() const {
  nlohmann::json params = nlohmann::json::object();
  if (model == "two-frame") {
    params = {{"tau_h_s", tau_h_s}, {"tau_c_s", tau_c_s}, {"gain", gain}, {"offset", offset},
              {"tau_identifiable", tau_identifiable},
              {"timing_shift_frames", timing_frames}, {"exposure_motion", exposure_motion},
              {"moving_fraction", moving_fraction},
              {"large_miss_mask", large_miss_mask}, {"tau_h_fitted", tau_h_fitted}};
    if (tau_h_fitted) params["exposure_offset"] = exposure_offset;
  } else {
    params = {{"moving_fraction", moving_fraction}};
  }
  return {{"model", model}, {"params", params}, {"assumption", assumption}};
}

namespace {

// Subtracting the median of m white-noise samples keeps (1 - (2 - pi/2) / m) of a sample's
// variance (cov(x, median) = sigma^2 / m, var(median) = pi/2 sigma^2 / m).
double kept_by_median(std::size_t m) { return 1.0 - (2.0 - M_PI / 2) / double(m); }

// Takes the median of each line (rows, or columns with along_rows false) of a frame difference out
// of its used pixels, so a pattern along rows or columns that changes between the two frames
// (line flicker, drifting bands) does not count as pixel noise. Lines with fewer than 8 used
// pixels are left alone. `kept` is multiplied by the share of white-noise variance each pixel keeps.
void take_out_line_medians(std::vector<float>& diff, const std::vector<std::uint8_t>& used, std::vector<double>& kept,
                           int width, int height, bool along_rows) {
  const int lines = along_rows ? height : width, length = along_rows ? width : height;
  const std::size_t step_along = along_rows ? 1 : std::size_t(width), step_across = along_rows ? std::size_t(width) : 1;
  std::vector<float> values;
  for (int l = 0; l < lines; ++l) {
    values.clear();
    const std::size_t first = std::size_t(l) * step_across;
    for (int k = 0; k < length; ++k) {
      const std::size_t p = first + std::size_t(k) * step_along;
      if (used[p]) values.push_back(diff[p]);
    }
    if (values.size() < 8) continue;
    const std::size_t m = values.size();
    const float median = median_in_place(values);
    for (int k = 0; k < length; ++k) {
      const std::size_t p = first + std::size_t(k) * step_along;
      if (!used[p]) continue;
      diff[p] -= median;
      kept[p] *= kept_by_median(m);
    }
  }
}

}  // namespace

namespace {

// The RMS of samples |diff| (each a difference of two noisy readings) per reading, with the
// outliers a moving object or a spike leaves cut at five robust spreads; `kept` is the share of
// white-noise variance each sample kept through what was taken out of it.
double pixel_sigma(const std::vector<float>& diffs, const std::vector<double>& kept) {
  std::vector<float> copy = diffs;
  // Integer counts make a median-based spread biased; it only sets the outlier cut here.
  const double rough = 1.4826 * median_in_place(copy);
  double ss = 0, share = 0;
  for (std::size_t i = 0; i < diffs.size(); ++i)
    if (diffs[i] <= 5 * rough + 1) { ss += double(diffs[i]) * diffs[i]; share += kept[i]; }
  return share > 0 ? std::sqrt(ss / share / 2.0) : rough / std::sqrt(2.0);
}

}  // namespace

// The temporal pixel noise: differences of consecutive frames at pixels where the baseline holds
// still, less the frame's common change. A pattern along rows or columns that changes between
// frames (readout line noise, drifting bands) is structure for the tool to explain or report, not
// noise: left in, drifting bands of 1.5 sigma raised the floor from 2.0 to 3.5, above what any
// finding had to beat, and the tool said nothing at all. So the same is measured with each row's
// and then each column's median taken out too, and that figure is the floor when it is more than
// 5 % lower (a pattern worth at least a tenth of the noise variance). Below that the plain figure
// stands: on white noise the two agree, and the plain one is not moved by medians of whole counts.
double noise_floor(const DiagnoseData& d, bool without_line_patterns) {
  const std::size_t P = d.shape.pixels();
  const int W = d.shape.width, H = d.shape.height;
  std::vector<float> plain, lines;
  std::vector<double> lines_kept;  // per sample in lines: the white-noise variance it keeps
  const std::size_t stride = std::max<std::size_t>(1, d.shape.size() / 400000);
  std::vector<float> frame_diff(P), still;
  std::vector<std::uint8_t> used(P);
  std::vector<double> kept(P);
  // The checkerboard figure (below): per disjoint 2x2 block, half its second difference of the
  // frame difference, and the same of the still reference's change.
  std::vector<float> board, board_reference, still_change(P);
  const std::size_t board_stride = std::max<std::size_t>(1, d.shape.size() / 4 / 400000);
  std::size_t still_count = 0, valid_count = 0, block = 0;
  for (int n = 1; n < d.shape.n; ++n) {
    if (d.flagged_event[n]) continue;
    const float *y = d.frame(d.recorded, n), *y0 = d.frame(d.recorded, n - 1);
    const float *b = d.frame(d.baseline, n), *b0 = d.frame(d.baseline, n - 1);
    const float *s = d.frame(d.still_reference(), n), *s0 = d.frame(d.still_reference(), n - 1);
    const std::uint8_t *v = d.valid_frame(n), *v0 = d.valid_frame(n - 1);
    still.clear();
    for (std::size_t p = 0; p < P; ++p) {
      used[p] = v[p] && v0[p] && holds_still(s[p], s0[p]);
      // Less the baseline's own change (a frame with another exposure reads another level).
      frame_diff[p] = (y[p] - y0[p]) - (b[p] - b0[p]);
      kept[p] = 1.0;
      if (used[p]) still.push_back(frame_diff[p]);
      valid_count += v[p] && v0[p];
      if (without_line_patterns) still_change[p] = s[p] - s0[p];
    }
    still_count += still.size();
    if (without_line_patterns)
      for (int r = 0; r + 1 < H; r += 2)
        for (int c = 0; c + 1 < W; c += 2) {
          const std::size_t q[4] = {std::size_t(r) * W + c, std::size_t(r) * W + c + 1, std::size_t(r + 1) * W + c,
                                    std::size_t(r + 1) * W + c + 1};
          if (!(v[q[0]] && v[q[1]] && v[q[2]] && v[q[3]] && v0[q[0]] && v0[q[1]] && v0[q[2]] && v0[q[3]])) continue;
          if (block++ % board_stride != 0) continue;
          board.push_back(std::fabs(checkerboard_difference(frame_diff.data(), q[0], std::size_t(W))));
          board_reference.push_back(std::fabs(checkerboard_difference(still_change.data(), q[0], std::size_t(W))));
        }
    if (still.size() < 16) continue;
    const float common = median_in_place(still);
    std::size_t i = 0;
    const std::size_t phase = (std::size_t(n) * 7919u) % stride;
    for (std::size_t p = 0; p < P; ++p) {
      frame_diff[p] -= common;
      if (used[p] && i++ % stride == phase) plain.push_back(std::fabs(frame_diff[p]));
    }
    if (!without_line_patterns) continue;
    take_out_line_medians(frame_diff, used, kept, W, H, true);
    take_out_line_medians(frame_diff, used, kept, W, H, false);
    i = 0;
    for (std::size_t p = 0; p < P; ++p) {
      if (!used[p] || i++ % stride != phase) continue;
      lines.push_back(std::fabs(frame_diff[p]));
      lines_kept.push_back(kept[p]);
    }
  }
  const bool nothing_still = plain.size() < 32;
  if (nothing_still) {
    // Nothing static: fall back to all pixels (an upper bound).
    plain.clear();
    for (int n = 1; n < d.shape.n; ++n) {
      const float *y = d.frame(d.recorded, n), *y0 = d.frame(d.recorded, n - 1);
      for (std::size_t p = 0; p < P; p += stride) plain.push_back(std::fabs(y[p] - y0[p]));
    }
  }
  const double plain_sigma = pixel_sigma(plain, std::vector<double>(plain.size(), 1.0));
  if (!without_line_patterns) return plain_sigma;
  // Where few pixel-frames hold still bitwise (a pan), too few to read the floor on: the frame
  // difference's 2x2 second difference over the pixel-frames where the still reference's own
  // second difference is under a tenth of that rough figure: a change that is locally linear in the image (the scene panning
  // over a smooth background, a level step, row or column patterns) cancels, the pixel noise
  // stays (variance 8 sigma^2, halved to that of one frame difference).
  if (still_count * 10 < valid_count) {
    std::vector<float> quiet;
    for (std::size_t i = 0; i < board.size(); ++i)
      if (board_reference[i] <= 0.1 * plain_sigma) quiet.push_back(board[i]);
    if (quiet.size() >= 1000) return pixel_sigma(quiet, std::vector<double>(quiet.size(), 1.0));
  }
  if (nothing_still) return plain_sigma;
  const double lines_sigma = pixel_sigma(lines, lines_kept);
  return lines_sigma < 0.95 * plain_sigma ? lines_sigma : plain_sigma;
}

}  // namespace bolo::diag

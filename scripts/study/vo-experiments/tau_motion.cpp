// Study harness (not a test): the tau estimate with true geometry on
// frames whose exposure integrates K scene samples; every option from the environment:
//   TAU, START (s); K sub-steps; TE_FRAC, TR_FRAC; WEIGHT exp|box; MODE both|camera|scene|between|constblur;
//   BLUR_SCALE (camera path within the exposure scaled about its middle); POSE_DT (s added to the
//   frame time for the truth pose and depth, "eff" = the exposure's weighted mean time);
//   NOISE (counts); SIZE (WxH, default 160x120); TRAJ drive|handheld|side|forward|yaw (SPEED m/s, RATE rad/s for the synthetic
//   constant-velocity ones); SS rays per axis; FRAMES; T0 (s); BLUR (px, fixed horizontal box);
//   IDEPTH_NOISE (relative), ROT_NOISE (rad per frame) on the truth geometry; GAUSS (px, sigma of a
//   Gaussian low-pass on every frame, so that nothing above the interpolators' reach is left);
//   ROBUST (counts: the plain fit again with Huber weights on A - alpha B at that threshold).
// Besides the estimator's tau it prints a plain least-squares fit over the same pairs (no pose or
// depth elimination) with: its scene-difference term (A - alpha B = beta D exactly), the fit with
// each frame's samples smeared along the other frame's exposure path, per sub-pixel phase
// difference bins, with INTERP bilinear|cubic|equal|lanczosN and SYM=1 (mirrored phases), DEPTHCHECK=1
// (pattern pixels on the centre's surface only), and EXACT=m: frames rendered at m x m the pixels
// (one ray each) whose box means are the frames and whose box-filtered image gives area means at
// any sub-pixel position (the fit without interpolation error); PWARP=1 projects every pattern
// pixel on its own instead of shifting the pattern. It also prints an instrumental-variable fit
// sum A Z / sum B Z with Z the gradient along the change of image velocity, GRAD y1|u (the raw
// previous frame's or the noise-free scene's gradient), the per-point fits' medians (plain and
// B^2-weighted), and the pairs taken against the host keyframe (frame i and its predecessor at
// p_i against the keyframe and its predecessor at the host pixel) instead of frame i - 1, the
// estimator's per-frame fits (batch-means standard error), B^2 / (A - alpha B)^2, and the plain
// fit over the points whose pattern energy is within GATE times the frame's median, judged at
// GATE_TAU (s; default the truth) or with GATE_OWN=1 at each point's own best alpha. FREEZE=1
// renders the world as at t = 0 in every frame (moving cars stand still). SMEAR_SRC u|y: the plain fit
// with the change of the within-period smear at each point subtracted, predicted from frame i's
// noise-free scene (u) or its estimate from the raw frames (y) and the points' image velocities;
// SMEAR_SCALE scales the sub-steps' ages; and the same with each frame's own smear at its own
// point (frame i - 1's image and velocity for its part), less its unsmeared value.
//   TAU=0.008 K=4 build/tests/vo/vo_tau_motion_experiment

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "bolo/vo/arena.hpp"
#include "rendered_pair.hpp"
#include "state.hpp"
#include "tau_truth_feed.hpp"

using namespace bolo;

namespace {

double env_num(const char* name, double fallback) {
  const char* v = std::getenv(name);
  return v != nullptr && *v != 0 ? std::atof(v) : fallback;
}
std::string env_str(const char* name, const char* fallback) {
  const char* v = std::getenv(name);
  return v != nullptr && *v != 0 ? v : fallback;
}

double bilin(const std::vector<double>& img, std::uint32_t w, double x, double y) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const double fx = x - x0, fy = y - y0;
  const auto at = [&](int xx, int yy) { return img[static_cast<std::size_t>(yy) * w + static_cast<std::size_t>(xx)]; };
  return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) + fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
}

// Keys' cubic convolution (a = -0.5), 4 x 4 pixels.
double keys(double t) {
  t = std::fabs(t);
  if (t < 1) return (1.5 * t - 2.5) * t * t + 1;
  if (t < 2) return ((-0.5 * t + 2.5) * t - 4) * t + 2;
  return 0;
}
double bicubic(const std::vector<double>& img, std::uint32_t w, double x, double y) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  double sum = 0;
  for (int j = -1; j <= 2; ++j)
    for (int i = -1; i <= 2; ++i)
      sum += keys(x - (x0 + i)) * keys(y - (y0 + j)) * img[static_cast<std::size_t>(y0 + j) * w + static_cast<std::size_t>(x0 + i)];
  return sum;
}

// Lanczos-a (a lobes), 2a x 2a pixels, the weights normalised per axis.
double lanczos(const std::vector<double>& img, std::uint32_t w, double x, double y, int a) {
  const auto kernel = [a](double t) {
    if (std::fabs(t) < 1e-12) return 1.0;
    if (std::fabs(t) >= a) return 0.0;
    const double pt = M_PI * t;
    return a * std::sin(pt) * std::sin(pt / a) / (pt * pt);
  };
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  double wx[16], wy[16], sx = 0, sy = 0;
  for (int i = 0; i < 2 * a; ++i) sx += wx[i] = kernel(x - (x0 - a + 1 + i)), sy += wy[i] = kernel(y - (y0 - a + 1 + i));
  double sum = 0;
  for (int j = 0; j < 2 * a; ++j)
    for (int i = 0; i < 2 * a; ++i)
      sum += wx[i] * wy[j] * img[static_cast<std::size_t>(y0 - a + 1 + j) * w + static_cast<std::size_t>(x0 - a + 1 + i)];
  return sum / (sx * sy);
}

// Bilinear followed by a 3-tap [c, 1 - 2c, c] per axis with c = (1/4 - phi (1 - phi)) / 2: every
// sample, whatever its phase, is smoothed like a half-pixel bilinear sample (kernel variance 1/4).
void equal_taps(double phi, double tap[4]) {
  const double c = 0.5 * (0.25 - phi * (1 - phi));
  const double b[2] = {1 - phi, phi}, k3[3] = {c, 1 - 2 * c, c};
  for (int i = 0; i < 4; ++i) tap[i] = 0;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 3; ++j) tap[i + j] += b[i] * k3[j];
}
double equalised(const std::vector<double>& img, std::uint32_t w, double x, double y) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  double tx[4], ty[4];
  equal_taps(x - x0, tx), equal_taps(y - y0, ty);
  double sum = 0;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i)
      sum += tx[i] * ty[j] * img[static_cast<std::size_t>(y0 - 1 + j) * w + static_cast<std::size_t>(x0 - 1 + i)];
  return sum;
}

}  // namespace

int main() {
  const double tau = env_num("TAU", 0.008), start = env_num("START", 0.010);
  const int substeps = static_cast<int>(env_num("K", 4));
  const std::string weight = env_str("WEIGHT", "exp"), mode = env_str("MODE", "both"),
                    traj = env_str("TRAJ", "drive"), pose_dt_s = env_str("POSE_DT", "0");
  const double noise_sigma = env_num("NOISE", 0);
  const auto ss = static_cast<unsigned>(env_num("SS", 3));
  const int frames = static_cast<int>(env_num("FRAMES", 120));

  const bool synthetic = traj == "side" || traj == "forward" || traj == "yaw";
  const std::string size = env_str("SIZE", "160x120");
  unsigned width = 0, height = 0;
  if (std::sscanf(size.c_str(), "%ux%u", &width, &height) != 2 || width < 32 || height < 32) {
    std::fprintf(stderr, "vo_tau_motion_experiment: SIZE '%s' is not WxH (at least 32x32)\n", size.c_str());
    return 1;
  }
  test::RenderedSequence seq{"street", synthetic ? "drive" : traj.c_str(), width, height, ss};
  if (synthetic) {
    // Constant-velocity motions from the drive's pose at t = 1 s: every scene point's image velocity
    // is constant in time for "side" (lateral translation), not for "forward" (zoom) or "yaw".
    const sim::scene::Pose p0 = seq.trajectory.pose(1.0);
    const double speed = env_num("SPEED", 10.0), rate = env_num("RATE", 0.5);
    seq.trajectory = sim::scene::Trajectory(traj, "street", 10.0, [=](double t) {
      sim::scene::Pose p = p0;
      const Eigen::Vector3d axis = p0.orientation * (traj == "side" ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitZ());
      if (traj == "yaw")
        p.orientation = p0.orientation * Eigen::AngleAxisd(rate * (t - 1.0), Eigen::Vector3d::UnitY());
      else
        p.position = p0.position + speed * (t - 1.0) * axis;
      return p;
    });
  }
  // EXACT m : render m x m times the pixels with one ray each; the frames are their m x m
  // box means (as SS m), and the plain fit is repeated on the box-filtered high-resolution images,
  // whose bilinear interpolation at a sub-pixel position is the area mean there to 1/m pixel.
  const int m = static_cast<int>(env_num("EXACT", 0));
  const std::uint32_t W = seq.width * static_cast<std::uint32_t>(std::max(1, m)), H = seq.height * static_cast<std::uint32_t>(std::max(1, m));
  test::RenderedSequence hseq{"street", synthetic ? "drive" : traj.c_str(), W, H, 1};
  if (synthetic) hseq.trajectory = seq.trajectory;
  const auto box_filter = [&](const std::vector<double>& hi) {
    // Output c (x) is the mean over hi-res pixels c - m/2 + 1 .. c + m/2 (rows likewise), clamped.
    std::vector<double> tmp(hi.size()), out(hi.size());
    for (std::uint32_t r = 0; r < H; ++r)
      for (std::uint32_t c = 0; c < W; ++c) {
        double sum = 0;
        for (int q = -((m - 1) / 2); q <= m - 1 - (m - 1) / 2; ++q)
          sum += hi[std::size_t{r} * W + static_cast<std::size_t>(std::clamp(static_cast<int>(c) + q, 0, static_cast<int>(W) - 1))];
        tmp[std::size_t{r} * W + c] = sum / m;
      }
    for (std::uint32_t r = 0; r < H; ++r)
      for (std::uint32_t c = 0; c < W; ++c) {
        double sum = 0;
        for (int q = -((m - 1) / 2); q <= m - 1 - (m - 1) / 2; ++q)
          sum += tmp[static_cast<std::size_t>(std::clamp(static_cast<int>(r) + q, 0, static_cast<int>(H) - 1)) * W + c];
        out[std::size_t{r} * W + c] = sum / m;
      }
    return out;
  };
  vo::VoConfig cfg;
  cfg.width = seq.width, cfg.height = seq.height;
  cfg.camera = seq.intrinsics();
  cfg.photometric = vo::Photometric::ir;
  cfg.tau_init_s = static_cast<float>(start);
  std::vector<std::byte> memory(vo::Odometry::arena_bytes(cfg));
  vo::Arena arena(memory);
  vo::State* s = vo::lay_out(cfg, arena);
  if (s == nullptr) {
    std::fprintf(stderr, "vo_tau_motion_experiment: the VO state does not fit its arena\n");
    return 1;
  }

  // TE_FRAC, TR_FRAC: exposure and readout as fractions of the period; TE_FRAC=1 TR_FRAC=1 is the
  // continuous lag (bolo simulate --lag continuous), read at the period's end (POSE_DT=0.016667).
  const double fps = 60, te = env_num("TE_FRAC", 0.5) / fps, tr = env_num("TR_FRAC", 0.5) / fps;
  const double alpha = std::exp(-tr / tau), beta = 1 - std::exp(-te / tau);
  const std::size_t n = std::size_t{seq.width} * seq.height;
  const std::uint32_t w = seq.width;
  // Sub-step weights as the bolometer array integrates them (exponential heating), normalised.
  const double d = te / substeps, keep = std::exp(-d / tau);
  std::vector<double> wk(static_cast<std::size_t>(substeps));
  double wsum = 0, tmean = 0;
  for (int k = 0; k < substeps; ++k) {
    wk[static_cast<std::size_t>(k)] = weight == "box" ? 1.0 : (1 - keep) * std::pow(keep, substeps - 1 - k);
    wsum += wk[static_cast<std::size_t>(k)];
  }
  for (int k = 0; k < substeps; ++k) {
    wk[static_cast<std::size_t>(k)] /= wsum;
    tmean += wk[static_cast<std::size_t>(k)] * (k + 0.5) * d;
  }
  const double pose_dt = pose_dt_s == "eff" ? tmean : std::atof(pose_dt_s.c_str());

  // The exposure-weighted scene of the frame starting at t.
  const double blur_scale = env_num("BLUR_SCALE", 1);
  const bool freeze = env_num("FREEZE", 0) != 0;  // the world at t = 0 in every frame (parked cars only)
  const Eigen::Vector3d const_velocity = (seq.trajectory.pose(1.001).position - seq.trajectory.pose(0.999).position) / 0.002;
  std::vector<double> hb;  // the latest exposure's box-filtered high-resolution image (EXACT)
  const auto exposure = [&](double t) {
    std::vector<double> u(n, 0.0);
    if (m > 0) {
      std::vector<double> hi(std::size_t{W} * H, 0.0);
      for (int k = 0; k < substeps; ++k) {
        const double ts = t + (k + 0.5) * d;
        const double t_cam = mode == "scene" || mode == "between" ? t + te / 2 : ts;
        const double t_scene = mode == "camera" ? t + te / 2 : ts;
        const std::vector<float> kel = hseq.renderer.render(hseq.trajectory.pose(t_cam), t_scene);
        for (std::size_t i = 0; i < hi.size(); ++i) hi[i] += wk[static_cast<std::size_t>(k)] * (8000.0 + 40.0 * (kel[i] - 300.0));
      }
      hb = box_filter(hi);
      for (std::uint32_t r = 0; r < seq.height; ++r)
        for (std::uint32_t c = 0; c < seq.width; ++c)
          u[std::size_t{r} * seq.width + c] = hb[static_cast<std::size_t>(r * m + (m - 1) / 2) * W + c * m + (m - 1) / 2];
      return u;
    }
    for (int k = 0; k < substeps; ++k) {
      const double ts = t + (k + 0.5) * d;
      const double t_cam = mode == "scene" || mode == "between" ? t + te / 2 : t + te / 2 + blur_scale * (ts - t - te / 2);
      const double t_scene = mode == "camera" ? t + te / 2 : ts;
      sim::scene::Pose pose = seq.trajectory.pose(t_cam);
      if (mode == "constblur") {
        // The camera at mid-exposure, moved within the exposure by one fixed velocity (every frame
        // the same blur).
        pose = seq.trajectory.pose(t + te / 2);
        pose.position += const_velocity * (ts - t - te / 2);
      }
      const std::vector<float> kel = seq.renderer.render(pose, freeze ? 0.0 : t_scene);
      for (std::size_t i = 0; i < n; ++i) u[i] += wk[static_cast<std::size_t>(k)] * (8000.0 + 40.0 * (kel[i] - 300.0));
    }
    // BLUR px: a fixed horizontal box blur of that width on every frame (no change between frames).
    const int blur = static_cast<int>(env_num("BLUR", 0));
    if (blur > 1) {
      std::vector<double> b(n);
      for (std::uint32_t r = 0; r < seq.height; ++r)
        for (std::uint32_t c = 0; c < w; ++c) {
          double sum = 0;
          for (int q = 0; q < blur; ++q) {
            const int cc = std::min<int>(static_cast<int>(w) - 1, std::max(0, static_cast<int>(c) + q - blur / 2));
            sum += u[std::size_t{r} * w + static_cast<std::size_t>(cc)];
          }
          b[std::size_t{r} * w + c] = sum / blur;
        }
      u = b;
    }
    // GAUSS sigma px: a separable Gaussian low-pass on every frame (the estimator's prefilter test).
    const double gauss = env_num("GAUSS", 0);
    if (gauss > 0) {
      const int rad = static_cast<int>(std::ceil(3 * gauss));
      std::vector<double> kern(static_cast<std::size_t>(2 * rad + 1));
      double ks = 0;
      for (int q = -rad; q <= rad; ++q) ks += kern[static_cast<std::size_t>(q + rad)] = std::exp(-0.5 * q * q / (gauss * gauss));
      for (double& v : kern) v /= ks;
      const int hh = static_cast<int>(seq.height), ww = static_cast<int>(w);
      std::vector<double> t1(n), t2(n);
      for (int r = 0; r < hh; ++r)
        for (int c = 0; c < ww; ++c) {
          double sum = 0;
          for (int q = -rad; q <= rad; ++q) sum += kern[static_cast<std::size_t>(q + rad)] * u[static_cast<std::size_t>(r * ww + std::clamp(c + q, 0, ww - 1))];
          t1[static_cast<std::size_t>(r * ww + c)] = sum;
        }
      for (int r = 0; r < hh; ++r)
        for (int c = 0; c < ww; ++c) {
          double sum = 0;
          for (int q = -rad; q <= rad; ++q) sum += kern[static_cast<std::size_t>(q + rad)] * t1[static_cast<std::size_t>(std::clamp(r + q, 0, hh - 1) * ww + c)];
          t2[static_cast<std::size_t>(r * ww + c)] = sum;
        }
      u = t2;
    }
    return u;
  };

  std::vector<double> y(n), y1(n), y2(n), u(n), u1(n);
  vo::Se3 T_prev2;
  std::vector<double> hy, hy1, hy2;  // the chain on the box-filtered high-resolution images
  const double t0 = env_num("T0", 1.0);
  {
    const auto us = exposure(t0 - 1 / fps);
    for (std::size_t i = 0; i < n; ++i) y[i] = us[i];
    u = us;
    hy = hb;
  }
  if (m > 0) {
    const std::vector<float> ref = test::RenderedSequence{"street", "drive", seq.width, seq.height, static_cast<unsigned>(m)}.renderer.render(seq.trajectory.pose(t0), t0);
    const std::vector<float> hr = hseq.renderer.render(seq.trajectory.pose(t0), t0);
    std::vector<double> hd(hr.begin(), hr.end());
    const auto hbx = box_filter(hd);
    double worst = 0;
    for (std::uint32_t r = 0; r < seq.height; ++r)
      for (std::uint32_t c = 0; c < seq.width; ++c)
        worst = std::max(worst, std::fabs(40.0 * (hbx[static_cast<std::size_t>(r * m + (m - 1) / 2) * W + c * m + (m - 1) / 2] - ref[std::size_t{r} * seq.width + c])));
    std::printf("EXACT %d: box means against the %d x %d-ray render: worst %.3g counts\n", m, m, m, worst);
  }
  double eab = 0, ebb = 0, err_bb = 0, err_ab = 0, err_aa = 0;
  test::ApproxNormal pixel_noise(12345);
  const std::string interp = env_str("INTERP", "bilinear");
  const bool symmetric = env_num("SYM", 0) != 0;
  const bool depth_check = env_num("DEPTHCHECK", 0) != 0;
  const double robust_k = env_num("ROBUST", 0);
  const bool pattern_warp = env_num("PWARP", 0) != 0;
  // ANCHOR=1: every frame's samples moved by p_i's sub-pixel part, so that frame i (A's first
  // sample, B's first) is read at whole pixels and only frame i - 1's and i - 2's are interpolated.
  const bool anchor = env_num("ANCHOR", 0) != 0;
  // LAG=L: also a plain fit over pairs between frames i and i - L (L = 1 is the estimator's):
  // A = y_i(p_i) - y_{i-L}(p_{i-L}), B = y_{i-1}(p_i) - y_{i-L-1}(p_{i-L}); for L >= 2 no frame is
  // in both A and B.
  const int lag = static_cast<int>(env_num("LAG", 0));
  // PHASE_TOL t (px): with LAG, pairs at every lag 1..LAG, only pattern samples whose displacement
  // between the two frames is within t of whole pixels (their resampling errors alike).
  const double phase_tol = env_num("PHASE_TOL", 0);
  double lag_n = 0;
  std::vector<std::vector<double>> history;  // raw frames, newest first (LAG)
  std::vector<vo::Se3> pose_history;        // their poses
  double lab = 0, lbb = 0, ldb = 0;
  std::vector<std::vector<double>> scene_history;
  std::map<std::uint32_t, double> host_times;  // keyframe id -> its (truth) time
  const bool true_pattern_depth = env_num("TRUEPW", 0) != 0;  // LAG: each pattern pixel at its true depth
  const std::string grad_src = env_str("GRAD", "y1");
  std::vector<double> pairs_a, pairs_b;
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::pair<double, double>> per_point;  // (AB, BB)
  struct HostImages {
    std::vector<double> y, y1, u;
  };
  std::map<std::uint32_t, HostImages> host_images;  // by keyframe id: its raw frame, the one before, its scene
  double kab = 0, kbb = 0, kdb = 0;
  const auto sample = [&](const std::vector<double>& img, double x, double yy) {
    if (interp.rfind("lanczos", 0) == 0) return lanczos(img, w, x, yy, std::atoi(interp.c_str() + 7));
    return interp == "cubic" ? bicubic(img, w, x, yy) : interp == "equal" ? equalised(img, w, x, yy) : bilin(img, w, x, yy);
  };
  double disp_sum = 0, disp_n = 0, disp_bb = 0;
  double bin_ab[3] = {}, bin_bb[3] = {}, bin_n[3] = {};
  double saa = 0, sab = 0, sbb = 0, sdb = 0, xab = 0, xbb = 0, xdb = 0, zab = 0, zbb = 0, zdb = 0;
  const double xsign = env_num("XSIGN", 1), xscale = env_num("XSCALE", 1);
  // Centred exposure offsets (fractions of the frame period) and their weights.
  std::vector<double> xoff(static_cast<std::size_t>(substeps));
  for (int q = 0; q < substeps; ++q) xoff[static_cast<std::size_t>(q)] = ((q + 0.5) * d - tmean) * fps * xscale;
  const auto smear = [&](const std::vector<double>& img, double x, double yy, double mx, double my) {
    double sum = 0;
    for (int q = 0; q < substeps; ++q) {
      const double o = xsign * xoff[static_cast<std::size_t>(q)];
      sum += wk[static_cast<std::size_t>(q)] * sample(img, x - mx * o, yy - my * o);
    }
    return sum;
  };
  // The smear-change correction (SMEAR_SRC u|y, SMEAR_SCALE: the ages scaled, 0 = none).
  const std::string smear_src = env_str("SMEAR_SRC", "u");
  const double smear_scale = env_num("SMEAR_SCALE", 1);
  std::vector<double> age(static_cast<std::size_t>(substeps));
  for (int q = 0; q < substeps; ++q) age[static_cast<std::size_t>(q)] = (pose_dt - (q + 0.5) * d) * fps;
  std::vector<double> scene_est(n), scene_est_prev(n);
  double cab = 0, cdb = 0, oab = 0, odb = 0;
  const double idepth_noise = env_num("IDEPTH_NOISE", 0), rot_noise = env_num("ROT_NOISE", 0);
  test::ApproxNormal noise_unit(777);
  bool have_keyframe = false;
  const double gate = env_num("GATE", 9);
  const bool gate_own = env_num("GATE_OWN", 0) != 0;
  const double gate_alpha = std::exp(-tr / env_num("GATE_TAU", tau));  // the alpha the energies are judged at
  double gab = 0, gbb = 0, gkept = 0, gall = 0;
  std::vector<std::pair<double, double>> frame_fits;  // the estimator's per-frame alpha and its information
  const vo::Scaled kc = vo::camera_at(cfg.camera, 0);
  for (int k = 0; k <= frames; ++k) {
    const double t = t0 + k / fps;
    y2 = y1, y1 = y, u1 = u;
    u = exposure(t);
    if (m > 0) {
      hy2 = hy1, hy1 = hy;
      for (std::size_t i = 0; i < hy.size(); ++i) hy[i] = alpha * hy[i] + beta * hb[i];
    }
    T_prev2 = s->motion.T_prev;
    test::push_truth_frame(*s, k, te, tr, t, seq.T_cw(t + pose_dt), [&](std::span<float> raw) {
      for (std::size_t i = 0; i < n; ++i) {
        y[i] = alpha * y[i] + beta * u[i];
        raw[i] = static_cast<float>(y[i] + noise_sigma * pixel_noise());
      }
    });
    if (lag > 0) {
      history.insert(history.begin(), y);
      scene_history.insert(scene_history.begin(), u);
      pose_history.insert(pose_history.begin(), s->motion.T_cw);
      if (history.size() > static_cast<std::size_t>(lag + 2)) history.pop_back(), pose_history.pop_back(), scene_history.pop_back();
    }
    if (rot_noise > 0) {
      // Tracking-like pose errors: a small random rotation per frame (rad, per axis).
      const Eigen::Vector3d w(rot_noise * noise_unit(), rot_noise * noise_unit(), rot_noise * noise_unit());
      s->motion.T_cw.R = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() * s->motion.T_cw.R;
      s->motion.T_cw.t = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() * s->motion.T_cw.t;
    }
    if (k % 12 == 0) {
      test::keyframe_at_true_depth(*s, [&](double pu, double pv) { return seq.depth(t + pose_dt, pu, pv); },
                                   [&](double z) { return (1 / z) * (1 + idepth_noise * noise_unit()); });
      have_keyframe = true;
      std::uint32_t newest = 0;
      for (const vo::Keyframe& kf : s->kf)
        if (kf.used) newest = std::max(newest, kf.id);
      host_images[newest] = {y, y1, u};
      host_times[newest] = t + pose_dt;
    }
    if (smear_src == "y") {
      scene_est_prev.swap(scene_est);
      for (std::size_t i = 0; i < n; ++i) scene_est[i] = (s->current.raw[i] - alpha * s->current.raw_prev[i]) / beta;
    }
    if (!have_keyframe) continue;
    {
      const double sab0 = s->tau_est.sab, sbb0 = s->tau_est.sbb;
      vo::refine_tau(s->tau_est, *s, s->current, s->motion, s->noise.var);
      const double fab = s->tau_est.sab - 0.995 * sab0, fbb = s->tau_est.sbb - 0.995 * sbb0;
      if (fbb > 0) frame_fits.push_back({fab / fbb, fbb});
    }
    if (k < 2) continue;
    struct PointPairs {
      double ab, bb, energy, aa = 0;
    };
    std::vector<PointPairs> frame_points;
    // The plain fit over the same pairs, noise-free images, and its scene-difference term
    // D = u_i(p_i) - u_{i-1}(p_{i-1}) (A - alpha B = beta D exactly).
    for (std::uint32_t slot = 0; slot < vo::kMaxKeyframes; ++slot) {
      const vo::Keyframe& host = s->kf[slot];
      if (!host.used) continue;
      const vo::Se3 Mi = s->motion.T_cw * host.T_cw.inverse(), Mp = s->motion.T_prev * host.T_cw.inverse();
      const vo::Se3 Mq = T_prev2 * host.T_cw.inverse();
      for (std::uint32_t i = 0; i < host.count; ++i) {
        const vo::Point& p = host.points[i];
        PointPairs here{0, 0, 0};
        struct Flush {
          std::vector<PointPairs>& to;
          PointPairs& what;
          bool gate_own;
          ~Flush() {
            if (what.bb <= 0) return;
            // GATE_OWN: judged at the point's own best alpha (no lean towards any alpha).
            if (gate_own) what.energy = what.aa - what.ab * what.ab / what.bb;
            to.push_back(what);
          }
        } flush{frame_points, here, gate_own};
        if (p.status != vo::PointStatus::active) continue;
        const Eigen::Vector3d nrm((p.u - kc.cx) / kc.fx, (p.v - kc.cy) / kc.fy, 1.0);
        const Eigen::Vector3d Xi = Mi.R * nrm + Mi.t * p.idepth, Xp = Mp.R * nrm + Mp.t * p.idepth;
        if (Xi.z() <= 1e-4 || Xp.z() <= 1e-4) continue;
        const double ui = kc.fx * Xi.x() / Xi.z() + kc.cx, vi = kc.fy * Xi.y() / Xi.z() + kc.cy;
        const double up = kc.fx * Xp.x() / Xp.z() + kc.cx, vp = kc.fy * Xp.y() / Xp.z() + kc.cy;
        for (int L = phase_tol > 0 ? 1 : lag; lag > 0 && L <= lag; ++L) {
          if (history.size() < static_cast<std::size_t>(L + 2)) break;
          const vo::Se3 Ml = pose_history[static_cast<std::size_t>(L)] * host.T_cw.inverse();
          const Eigen::Vector3d Xl = Ml.R * nrm + Ml.t * p.idepth;
          const double ul = kc.fx * Xl.x() / Xl.z() + kc.cx, vl = kc.fy * Xl.y() / Xl.z() + kc.cy;
          if (Xl.z() > 1e-4 && ul >= 4 && vl >= 4 && ul <= w - 5 && vl <= seq.height - 5 && ui >= 4 && vi >= 4 && ui <= w - 5 && vi <= seq.height - 5)
            for (std::uint32_t j = 0; j < vo::kPattern; ++j) {
              double xi = ui + vo::kPatternX[j], yi = vi + vo::kPatternY[j];
              double xl = ul + vo::kPatternX[j], yl = vl + vo::kPatternY[j];
              if (pattern_warp) {
                const Eigen::Vector3d nj((p.u + vo::kPatternX[j] - kc.cx) / kc.fx, (p.v + vo::kPatternY[j] - kc.cy) / kc.fy, 1.0);
                const auto proj = [&](const vo::Se3& M, double& px, double& py) {
                  double id = p.idepth;
                  if (true_pattern_depth) {
                    const double z = seq.depth(host_times[host.id], p.u + vo::kPatternX[j], p.v + vo::kPatternY[j]);
                    if (z > 0) id = 1 / z;
                  }
                  const Eigen::Vector3d X = M.R * nj + M.t * id;
                  px = kc.fx * X.x() / X.z() + kc.cx, py = kc.fy * X.y() / X.z() + kc.cy;
                };
                proj(Mi, xi, yi), proj(Ml, xl, yl);
              }
              if (phase_tol > 0) {
                const auto wrap = [](double a) { return a - std::round(a); };
                if (std::fabs(wrap(xi - xl)) > phase_tol || std::fabs(wrap(yi - yl)) > phase_tol) continue;
              }
              const auto Ls = static_cast<std::size_t>(L);
              const double A = sample(history[0], xi, yi) - sample(history[Ls], xl, yl);
              const double B = sample(history[1], xi, yi) - sample(history[Ls + 1], xl, yl);
              const double D = sample(scene_history[0], xi, yi) - sample(scene_history[Ls], xl, yl);
              lag_n += 1;
              lab += A * B, lbb += B * B, ldb += beta * D * B;
            }
        }
        const Eigen::Vector3d Xq = Mq.R * nrm + Mq.t * p.idepth;
        const double uq = kc.fx * Xq.x() / Xq.z() + kc.cx, vq = kc.fy * Xq.y() / Xq.z() + kc.cy;
        if (ui < 8 || vi < 8 || up < 8 || vp < 8 || ui > w - 9 || up > w - 9 || vi > seq.height - 9 || vp > seq.height - 9) continue;
        if (ui < 4 || vi < 4 || up < 4 || vp < 4 || ui > w - 5 || up > w - 5 || vi > seq.height - 5 || vp > seq.height - 5) continue;
        // SYM: both frames' samples moved by the same sub-pixel shift so that their phases mirror
        // (phi_i + phi_{i-1} = 1): bilinear interpolation then smooths both alike.
        double sx = 0, sy = 0;
        if (anchor) sx = std::round(ui) - ui, sy = std::round(vi) - vi;
        if (symmetric) {
          const auto mirror_shift = [](double a, double b) {
            double d = 0.5 * (1 - (a - std::floor(a)) - (b - std::floor(b)));
            return d - 0.5 * std::round(2 * d);  // |d| <= 1/4; a shift by 1/2 keeps the mirror
          };
          sx = mirror_shift(ui, up), sy = mirror_shift(vi, vp);
        }
        for (std::uint32_t j = 0; j < vo::kPattern; ++j) {
          double xi = ui + sx + vo::kPatternX[j], yi = vi + sy + vo::kPatternY[j];
          double xp = up + sx + vo::kPatternX[j], yp = vp + sy + vo::kPatternY[j];
          double xq = uq + vo::kPatternX[j], yq = vq + vo::kPatternY[j];
          if (pattern_warp) {
            // Each pattern pixel projected on its own (the host's inverse depth at the offset).
            const Eigen::Vector3d nj((p.u + vo::kPatternX[j] - kc.cx) / kc.fx, (p.v + vo::kPatternY[j] - kc.cy) / kc.fy, 1.0);
            const auto proj = [&](const vo::Se3& M, double& px, double& py) {
              const Eigen::Vector3d X = M.R * nj + M.t * p.idepth;
              px = kc.fx * X.x() / X.z() + kc.cx, py = kc.fy * X.y() / X.z() + kc.cy;
            };
            proj(Mi, xi, yi), proj(Mp, xp, yp), proj(Mq, xq, yq);
          }
          if (depth_check) {
            // Only pattern pixels on the centre's surface (no occlusion edge within the pattern).
            const double zc = 1.0 / p.idepth, zj = seq.depth(t + pose_dt, xi, yi);
            if (!(zj > 0) || std::fabs(zj / zc - 1) > 0.05) continue;
          }
          const double A = sample(y, xi, yi) - sample(y1, xp, yp);
          const double B = sample(y1, xi, yi) - sample(y2, xp, yp);
          const double D = sample(u, xi, yi) - sample(u1, xp, yp);
          sab += A * B, sbb += B * B, sdb += beta * D * B, saa += A * A;
          here.ab += A * B, here.bb += B * B, here.energy += (A - gate_alpha * B) * (A - gate_alpha * B), here.aa += A * A;
          if (const auto hi = host_images.find(host.id); hi != host_images.end() && k > 1) {
            // Against the host keyframe: A' - alpha B' = beta (u_i(p_i) - u_k(q)), q the host pixel.
            const double qx = p.u + vo::kPatternX[j], qy = p.v + vo::kPatternY[j];
            const double A2 = sample(y, xi, yi) - sample(hi->second.y, qx, qy);
            const double B2 = sample(y1, xi, yi) - sample(hi->second.y1, qx, qy);
            const double D2 = sample(u, xi, yi) - sample(hi->second.u, qx, qy);
            kab += A2 * B2, kbb += B2 * B2, kdb += beta * D2 * B2;
          }
          {
            auto& pp = per_point[{host.id, i}];
            pp.first += A * B, pp.second += B * B;
          }
          {
            // Instrument: the gradient along the change of image velocity (odd in the texture).
            const double ddx = (xi - xp) - (xp - xq), ddy = (yi - yp) - (yp - yq);
            const std::vector<double>& gimg = grad_src == "u" ? u1 : y1;
            const double gx = 0.5 * (sample(gimg, xi + 1, yi) - sample(gimg, xi - 1, yi));
            const double gy = 0.5 * (sample(gimg, xi, yi + 1) - sample(gimg, xi, yi - 1));
            const double Z = gx * ddx + gy * ddy;
            zab += A * Z, zbb += B * Z, zdb += beta * D * Z;
          }
          if (robust_k > 0) pairs_a.push_back(A), pairs_b.push_back(B);
          const double disp = std::hypot(ui - up, vi - vp);
          disp_sum += disp, disp_n += 1, disp_bb += disp * B * B;
          if (m > 0 && k > 2) {
            const auto hx = [&](double x) { return x * m + (m - 1) / 2; };
            const double eA = bilin(hy, W, hx(xi), hx(yi)) - bilin(hy1, W, hx(xp), hx(yp));
            const double eB = bilin(hy1, W, hx(xi), hx(yi)) - bilin(hy2, W, hx(xp), hx(yp));
            eab += eA * eB, ebb += eB * eB;
            err_bb += (B - eB) * (B - eB), err_aa += (A - eA) * (A - eA), err_ab += (A - eA) * (B - eB);
          }
          const auto wrap = [](double a) { return a - std::round(a); };
          const double dphi = std::max(std::fabs(wrap(ui - up)), std::fabs(wrap(vi - vp)));
          const int bin = dphi < 0.1 ? 0 : dphi < 0.25 ? 1 : 2;
          bin_ab[bin] += A * B, bin_bb[bin] += B * B, bin_n[bin] += 1;
          const double XA = smear(y, xi, yi, up - uq, vp - vq) - smear(y1, xp, yp, ui - up, vi - vp);
          const double XB = smear(y1, xi, yi, up - uq, vp - vq) - smear(y2, xp, yp, ui - up, vi - vp);
          const double XD = smear(u, xi, yi, up - uq, vp - vq) - smear(u1, xp, yp, ui - up, vi - vp);
          xab += XA * XB, xbb += XB * XB, xdb += beta * XD * XB;
          {
            // The change of the within-period smear at the point, predicted from one scene image
            // (SMEAR_SRC u: the noise-free scene of frame i; y: its estimate from the raw frames):
            // beta D ~ beta sum_k w_k [L(p_i + v_i o_k) - L(p_i + v_{i-1} o_k)], o_k the sub-step's
            // age in frames at the pose's time, v the point's image velocity (px per frame).
            const double vix = xi - xp, viy = yi - yp, vpx = xp - xq, vpy = yp - yq;
            const std::vector<double>& L = smear_src == "u" ? u : scene_est;
            double pred = 0;
            for (int q = 0; q < substeps; ++q) {
              const double o = smear_scale * age[static_cast<std::size_t>(q)];
              pred += wk[static_cast<std::size_t>(q)] * (sample(L, xi + vix * o, yi + viy * o) - sample(L, xi + vpx * o, yi + vpy * o));
            }
            cab += (A - beta * pred) * B, cdb += beta * pred * B;
            // Each frame's own smear at the point (its image's curvature, its velocity), less the
            // other's: under a zoom the content's scale changes between the frames as well.
            const std::vector<double>& L1 = smear_src == "u" ? u1 : scene_est_prev;
            double own = sample(L1, xp, yp) - sample(L, xi, yi);  // the unsmeared values (the weights sum to 1)
            for (int q = 0; q < substeps; ++q) {
              const double o = smear_scale * age[static_cast<std::size_t>(q)];
              own += wk[static_cast<std::size_t>(q)] * (sample(L, xi + vix * o, yi + viy * o) - sample(L1, xp + vpx * o, yp + vpy * o));
            }
            oab += (A - beta * own) * B, odb += beta * own * B;
          }
        }
      }
    }
    {
      // Points whose pattern energy of A - alpha B exceeds GATE times the frame's median are left
      // out (moving objects, occlusions).
      std::vector<double> e;
      for (const auto& q : frame_points) e.push_back(q.energy);
      if (!e.empty()) {
        std::nth_element(e.begin(), e.begin() + static_cast<long>(e.size() / 2), e.end());
        const double med = e[e.size() / 2];
        for (const auto& q : frame_points)
          if (q.energy <= gate * med) gab += q.ab, gbb += q.bb, gkept += 1;
        gall += static_cast<double>(frame_points.size());
      }
    }
  }
  const double a_plain = sab / sbb;
  if (robust_k > 0) {
    // ROBUST k: the plain fit reweighted by Huber weights of A - alpha B at threshold k (counts).
    double a = a_plain;
    for (int it = 0; it < 10; ++it) {
      double wab = 0, wbb = 0;
      for (std::size_t i = 0; i < pairs_a.size(); ++i) {
        const double r = std::fabs(pairs_a[i] - a * pairs_b[i]);
        const double wt = r <= robust_k ? 1.0 : robust_k / r;
        wab += wt * pairs_a[i] * pairs_b[i], wbb += wt * pairs_b[i] * pairs_b[i];
      }
      a = wab / wbb;
    }
    std::printf("ROBUST %.1f: plain fit with Huber weights %.2f ms\n", robust_k, -tr / std::log(a) * 1e3);
  }
  {
    // Per-point fits, pooled by their B^2-weighted median (a point over a depth edge is one vote).
    std::vector<std::pair<double, double>> fits;
    double total = 0;
    for (const auto& [key, ab] : per_point)
      if (ab.second > 0) fits.push_back({ab.first / ab.second, ab.second}), total += ab.second;
    std::sort(fits.begin(), fits.end());
    double acc = 0, med = 0;
    for (const auto& [a, wgt] : fits)
      if ((acc += wgt) >= 0.5 * total) {
        med = a;
        break;
      }
    std::vector<double> plain_alphas;
    for (const auto& f : fits) plain_alphas.push_back(f.first);
    std::nth_element(plain_alphas.begin(), plain_alphas.begin() + static_cast<long>(plain_alphas.size() / 2), plain_alphas.end());
    std::printf("per-point fits (%zu points): weighted median %.2f ms, median %.2f ms\n", fits.size(), -tr / std::log(med) * 1e3,
                -tr / std::log(plain_alphas[plain_alphas.size() / 2]) * 1e3);
  }
  {
    // Batch means: each frame's eliminated fit as one observation (its pairs' errors are alike).
    double sw = 0, swa = 0, sw2 = 0;
    for (const auto& [a, wgt] : frame_fits) sw += wgt, swa += wgt * a;
    const double mean = swa / sw;
    double var = 0;
    for (const auto& [a, wgt] : frame_fits) var += wgt * wgt * (a - mean) * (a - mean), sw2 += wgt * wgt;
    const double se = std::sqrt(var) / sw, se_naive = 0;
    (void)se_naive;
    std::printf("per-frame fits (%zu): alpha %.4f, batch-means SE %.4f, effective frames %.1f, info %.3g\n", frame_fits.size(), mean, se,
                sw * sw / sw2, sw);
  }
  std::printf("plain sums: B^2 / (A - alpha B)^2 at the true alpha %.3f, at the fit %.3f\n", sbb / (saa - 2 * alpha * sab + alpha * alpha * sbb),
              sbb / (saa - sab * sab / sbb));
  std::printf("gated at %.0f x the median point energy: %.2f ms (%.1f %% of points kept)\n", gate, -tr / std::log(gab / gbb) * 1e3, 100 * gkept / gall);
  std::printf("against the host keyframe: %.2f ms (dalpha %.4f)\n", -tr / std::log(kab / kbb) * 1e3, kdb / kbb);
  std::printf("displacement between frames: mean %.2f px, B^2-weighted %.2f px\n", disp_sum / disp_n, disp_bb / sbb);
  if (m > 0)
    std::printf("EXACT %d: sum B^2 (bilinear) %.3g, (area) %.3g, of the bilinear error %.3g; error A.B / B.B %.3f, error corr %.3f\n", m, sbb, ebb, err_bb,
                err_ab / err_bb, err_ab / std::sqrt(err_aa * err_bb));
  if (m > 0) std::printf("EXACT %d: plain fit on area means at the sub-pixel positions: %.2f ms\n", m, -tr / std::log(eab / ebb) * 1e3);
  for (int b = 0; b < 3; ++b)
    std::printf("phase-diff bin %d (%.0f pairs, B^2 share %.2f): plain %.2f ms\n", b, bin_n[b], bin_bb[b] / sbb, -tr / std::log(bin_ab[b] / bin_bb[b]) * 1e3);
  if (lag > 0) std::printf("LAG %d (phase tol %.2f, %.0f samples): plain fit: %.2f ms (bias term dalpha %.4f)\n", lag, phase_tol, lag_n, -tr / std::log(lab / lbb) * 1e3, ldb / lbb);
  std::printf("instrument (gradient . velocity change): %.2f ms (dalpha %.4f)\n", -tr / std::log(zab / zbb) * 1e3, zdb / zbb);
  std::printf("smear-change corrected plain %.2f ms (predicted dalpha %.4f of %.4f)\n", -tr / std::log(cab / sbb) * 1e3, cdb / sbb, sdb / sbb);
  std::printf("each frame's own smear corrected plain %.2f ms (predicted dalpha %.4f)\n", -tr / std::log(oab / sbb) * 1e3, odb / sbb);
  std::printf("cross-smeared plain %.2f ms (dalpha %.4f); ", -tr / std::log(xab / xbb) * 1e3, xdb / xbb);
  std::printf("tau %.1f K %d %s mode %s pose_dt %.2f ms traj %s noise %.1f ss %u: estimator %.2f ms, plain %.2f ms (bias term dalpha %.4f, alpha %.4f)\n",
              tau * 1e3, substeps, weight.c_str(), mode.c_str(), pose_dt * 1e3, traj.c_str(), noise_sigma, ss,
              s->tau_est.tau.c * 1e3, -tr / std::log(a_plain) * 1e3, sdb / sbb, alpha);
  return s->tau_est.tau.c > 0 ? 0 : 1;
}

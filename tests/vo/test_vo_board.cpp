// VO core tests that run on the boards too (no host libraries): SE(3) maps, configuration
// checks, and tracking of an analytic scene: a textured wall (sum of sinusoids) the camera
// approaches and pans along, rendered by exact ray-plane intersection.

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include <catch2/catch.hpp>

#include "bolo/vo/image.hpp"
#include "bolo/vo/odometry.hpp"

using namespace bolo;

namespace {

constexpr std::uint32_t kW = 128, kH = 96;

vo::Camera camera() { return {110.0f, 110.0f, 63.5f, 47.5f}; }

// Wall z = 6 m in the world; camera-to-world pose: translation (0.4 t, 0, 1.2 t), small yaw.
vo::Se3 pose_wc(double t) {
  vo::Se3 T;
  T.R = vo::so3_exp(vo::Vec3(0, 0.05 * std::sin(t), 0));
  T.t = vo::Vec3(0.4 * t, 0.05 * std::sin(3 * t), 1.2 * t);
  return T;
}

double texture(double x, double y) {
  return 6000 + 900 * std::sin(2.1 * x) * std::cos(1.7 * y) + 500 * std::sin(5.3 * x + 1.1 * y) +
         300 * std::cos(9.1 * y - 2.3 * x) + 200 * std::sin(13.7 * x + 7.9 * y);
}

std::vector<std::uint16_t> render(double t) {
  const vo::Se3 T = pose_wc(t);
  const vo::Camera c = camera();
  std::vector<std::uint16_t> img(std::size_t{kW} * kH);
  for (std::uint32_t v = 0; v < kH; ++v)
    for (std::uint32_t u = 0; u < kW; ++u) {
      double sum = 0;
      for (int s = 0; s < 4; ++s) {  // 2x2 rays per pixel: no aliasing to speak of
        const vo::Vec3 d = T.R * vo::Vec3((u - c.cx + 0.25 + 0.5 * (s % 2) - 0.5) / c.fx,
                                           (v - c.cy + 0.25 + 0.5 * (s / 2) - 0.5) / c.fy, 1.0);
        const double k = (6.0 - T.t.z()) / d.z();
        sum += texture(T.t.x() + k * d.x(), T.t.y() + k * d.y());
      }
      img[std::size_t{v} * kW + u] = static_cast<std::uint16_t>(std::lround(sum / 4));
    }
  return img;
}

// The wall through the two-frame model, y_i = alpha_i y_{i-1} + beta_i u with alpha_i from the
// previous frame's readout and beta_i from this frame's exposure; u is scaled so that a static
// scene at the reference timing reads its rendered level.
class CarriedWall {
 public:
  CarriedWall(double tau, double reference_exposure_s, double reference_readout_s)
      : tau_(tau), u_per_level_((1 - std::exp(-reference_readout_s / tau)) / (1 - std::exp(-reference_exposure_s / tau))) {}

  // Frame i's counts from its rendered levels K. `settled` (a shutter event before this frame):
  // the pixels start from K's mean level instead of the previous frame; `offset` counts are added
  // to what the camera reports.
  const std::vector<std::uint16_t>& next(const std::vector<std::uint16_t>& K, double exposure_s, double readout_prev_s,
                                          bool settled = false, double offset = 0) {
    if (y_.empty()) y_.assign(K.begin(), K.end()), frame_.resize(K.size());
    else {
      const double alpha = std::exp(-readout_prev_s / tau_), beta = 1 - std::exp(-exposure_s / tau_);
      double level = 0;
      for (const std::uint16_t k : K) level += k;
      level /= static_cast<double>(K.size());
      for (std::size_t p = 0; p < K.size(); ++p) y_[p] = alpha * (settled ? level : y_[p]) + beta * u_per_level_ * K[p];
    }
    for (std::size_t p = 0; p < K.size(); ++p) frame_[p] = static_cast<std::uint16_t>(std::lround(y_[p] + offset));
    return frame_;
  }

 private:
  double tau_, u_per_level_;
  std::vector<double> y_;
  std::vector<std::uint16_t> frame_;
};

// A VO for the wall's camera, with its arena.
struct WallOdometry {
  vo::VoConfig config = [] {
    vo::VoConfig c;
    c.width = kW, c.height = kH, c.camera = camera();
    return c;
  }();
  std::vector<std::byte> arena = std::vector<std::byte>(vo::Odometry::arena_bytes(config));
  vo::Odometry odometry{config, arena};
};

}  // namespace

TEST_CASE("SE(3) exp and log are inverse", "[vo][board]") {
  vo::Vec6 xi;
  xi << 0.3, -0.2, 1.1, 0.4, -0.7, 0.25;
  const vo::Se3 T = vo::Se3::exp(xi);
  CHECK((T.log() - xi).norm() < 1e-9);
  CHECK((T * T.inverse()).t.norm() < 1e-12);
  const Eigen::Vector4d q = vo::to_quaternion(T.R);
  CHECK((vo::from_quaternion(q.x(), q.y(), q.z(), q.w()) - T.R).norm() < 1e-9);
}

TEST_CASE("the default point budget is one per 40 pixels, 100 to 500 a keyframe", "[vo][board]") {
  // The cap bounds the window BA's and the depth search's time at the larger sizes (config.cpp);
  // 160x120 keeps its 480.
  const auto points = [](std::uint32_t w, std::uint32_t h) {
    vo::VoConfig c;
    c.width = w, c.height = h, c.camera = camera();
    return vo::resolved(c).points_per_keyframe;
  };
  CHECK(points(64, 48) == 100);
  CHECK(points(160, 120) == 480);
  CHECK(points(320, 256) == 500);
  CHECK(points(640, 512) == 500);
  vo::VoConfig explicit_budget;
  explicit_budget.width = 320, explicit_budget.height = 256, explicit_budget.points_per_keyframe = 800;
  CHECK(vo::resolved(explicit_budget).points_per_keyframe == 800);
}

TEST_CASE("the thresholds follow the pixel noise above 4 counts", "[vo][board]") {
  // Noise of a set standard deviation (Irwin-Hall, from an LCG: the same on every architecture)
  // on the wall's first three frames; the scale is measured once, at the third.
  const auto measured_scale = [](double sigma, float configured) {
    vo::VoConfig config;
    config.width = kW, config.height = kH, config.camera = camera();
    config.intensity_scale = configured;
    std::vector<std::byte> arena(vo::Odometry::arena_bytes(config));
    vo::Odometry odometry(config, arena);
    std::uint32_t lcg = 12345;
    const auto uniform = [&] {
      lcg = lcg * 1664525u + 1013904223u;
      return static_cast<double>(lcg >> 8) / 16777216.0;
    };
    for (int i = 0; i < 3; ++i) {
      std::vector<std::uint16_t> frame = render(i / 60.0);
      for (std::uint16_t& v : frame) {
        double n = -6;
        for (int k = 0; k < 12; ++k) n += uniform();
        v = static_cast<std::uint16_t>(std::lround(v + sigma * n));
      }
      vo::FrameInput in;
      in.raw = frame;
      in.t_s = i / 60.0;
      in.chain_broken = i == 0;
      odometry.process(in);
      if (i < 2) CHECK(odometry.intensity_scale() == (configured > 0 ? configured : 1.0f));
    }
    return odometry.intensity_scale();
  };
  CHECK(measured_scale(2.0, 0.0f) == 1.0f);
  CHECK(measured_scale(12.0, 0.0f) == Approx(3.0).epsilon(0.12));
  CHECK(measured_scale(30.0, 0.0f) == Approx(7.5).epsilon(0.12));
  CHECK(measured_scale(12.0, 2.0f) == 2.0f);  // configured: kept
  vo::VoConfig c;
  c.width = kW, c.height = kH, c.camera = camera();
  c.intensity_scale = -1;
  CHECK(vo::invalid_reason(c) != nullptr);
}

TEST_CASE("configurations the VO cannot run with are refused", "[vo][board]") {
  vo::VoConfig c;
  c.width = kW, c.height = kH, c.camera = camera();
  CHECK(vo::invalid_reason(c) == nullptr);
  vo::VoConfig small = c;
  small.width = 16;
  CHECK(vo::invalid_reason(small) != nullptr);
  vo::VoConfig nocam = c;
  nocam.camera.fx = 0;
  CHECK(vo::invalid_reason(nocam) != nullptr);
  std::vector<std::byte> tiny(64);
  CHECK_FALSE(vo::Odometry(c, tiny).ok());
  vo::VoConfig rough = c;
  rough.smoothing = vo::kMaxSmoothingPasses + 1;
  CHECK(vo::invalid_reason(rough) != nullptr);
  // Each tunable's range, both ends in, a step beyond either out (the CLI refuses the same values).
  const auto refused_tau = [&](float tau) {
    vo::VoConfig t = c;
    t.tau_init_s = tau;
    return vo::invalid_reason(t) != nullptr;
  };
  CHECK_FALSE(refused_tau(vo::kTauInitRange.min));
  CHECK_FALSE(refused_tau(vo::kTauInitRange.max));
  CHECK(refused_tau(0.0009f));
  CHECK(refused_tau(0.051f));
  CHECK(refused_tau(std::numeric_limits<float>::quiet_NaN()));
  vo::VoConfig keyframes = c;
  keyframes.max_keyframes = vo::kKeyframesRange.max + 1;
  CHECK(vo::invalid_reason(keyframes) != nullptr);
  keyframes.max_keyframes = vo::kKeyframesRange.min;
  CHECK(vo::invalid_reason(keyframes) == nullptr);
  vo::Photometric m;
  CHECK(vo::parse_photometric("ir-loop", m));
  CHECK(m == vo::Photometric::ir_loop);
  CHECK_FALSE(vo::parse_photometric("dso", m));
  vo::Retirement r = vo::Retirement::spread;
  CHECK(vo::parse_retirement("oldest", r));
  CHECK(r == vo::Retirement::oldest);
  CHECK(std::string(vo::to_string(vo::Retirement::spread)) == "spread");
  CHECK_FALSE(vo::parse_retirement("newest", r));
}

TEST_CASE("the tracking image's binomial low-pass", "[vo][board]") {
  constexpr std::uint32_t w = 9, h = 7;
  std::vector<float> pixels(w * h), scratch(w * h);
  vo::Image image{pixels.data(), w, h}, tmp{scratch.data(), w, h};
  const auto fill = [&](auto f) {
    for (std::uint32_t y = 0; y < h; ++y)
      for (std::uint32_t x = 0; x < w; ++x) pixels[y * w + x] = static_cast<float>(f(x, y));
  };
  SECTION("a plane is kept inside the border, a constant everywhere") {
    fill([](std::uint32_t x, std::uint32_t y) { return 1000.0 + 4.0 * x - 2.0 * y; });
    const std::vector<float> before = pixels;
    vo::smooth_binomial(image, tmp);
    for (std::uint32_t y = 1; y + 1 < h; ++y)
      for (std::uint32_t x = 1; x + 1 < w; ++x) CHECK(pixels[y * w + x] == before[y * w + x]);
    fill([](std::uint32_t, std::uint32_t) { return 777.0; });
    vo::smooth_binomial(image, tmp);
    for (const float v : pixels) CHECK(v == 777.0f);
  }
  SECTION("the checkerboard at the sampling limit is removed") {
    fill([](std::uint32_t x, std::uint32_t y) { return 500.0 + ((x + y) % 2 ? 50.0 : -50.0); });
    vo::smooth_binomial(image, tmp);
    for (std::uint32_t y = 1; y + 1 < h; ++y)
      for (std::uint32_t x = 1; x + 1 < w; ++x) CHECK(pixels[y * w + x] == 500.0f);
  }
  SECTION("an impulse spreads as [1 2 1] x [1 2 1] / 16, its sum kept; at a corner the border is replicated") {
    fill([](std::uint32_t x, std::uint32_t y) { return x == 4 && y == 3 ? 16.0 : 0.0; });
    vo::smooth_binomial(image, tmp);
    const float kernel[3] = {1, 2, 1};
    float sum = 0;
    for (std::uint32_t y = 0; y < h; ++y)
      for (std::uint32_t x = 0; x < w; ++x) {
        const bool near = x >= 3 && x <= 5 && y >= 2 && y <= 4;
        CHECK(pixels[y * w + x] == (near ? kernel[x - 3] * kernel[y - 2] : 0.0f));
        sum += pixels[y * w + x];
      }
    CHECK(sum == 16.0f);
    fill([](std::uint32_t x, std::uint32_t y) { return x == 0 && y == 0 ? 16.0 : 0.0; });
    vo::smooth_binomial(image, tmp);
    CHECK(pixels[0] == 9.0f);      // 16 * 0.75 * 0.75
    CHECK(pixels[1] == 3.0f);      // 16 * 0.25 * 0.75
    CHECK(pixels[w + 1] == 1.0f);  // 16 * 0.25 * 0.25
  }
}

TEST_CASE("the VO tracks an analytic wall and the result is deterministic", "[vo][board]") {
  vo::VoConfig c;
  c.width = kW, c.height = kH, c.camera = camera();
  c.smoothing = GENERATE(0u, 1u);  // the tracking images as they are, and low-passed once
  INFO("smoothing " << c.smoothing);
  std::vector<std::vector<std::uint16_t>> frames;
  const int n = 40;
  for (int i = 0; i < n; ++i) frames.push_back(render(i / 30.0));
  std::vector<vo::FrameResult> first_run;
  for (int run = 0; run < 2; ++run) {
    std::vector<std::byte> arena(vo::Odometry::arena_bytes(c));
    vo::Odometry odometry(c, arena);
    REQUIRE(odometry.ok());
    std::vector<vo::Vec3> est, truth;
    std::vector<vo::FrameResult> results;
    for (int i = 0; i < n; ++i) {
      vo::FrameInput in;
      in.raw = frames[static_cast<std::size_t>(i)];
      in.t_s = i / 30.0, in.chain_broken = i == 0;
      const vo::FrameResult r = odometry.process(in);
      results.push_back(r);
      if (r.has_pose) est.push_back(r.T_wc.t), truth.push_back(pose_wc(i / 30.0).t);
    }
    REQUIRE(est.size() >= 20);
    // Direction of travel (monocular: up to scale) against the truth, relative to the first pose.
    const vo::Vec3 de = est.back() - est.front(), dt = truth.back() - truth.front();
    const double angle = std::acos(de.normalized().dot(dt.normalized())) * 180 / M_PI;
    INFO("posed " << est.size() << " of " << n << ", direction error " << angle << " deg");
    CHECK(angle < 10.0);
    if (run == 0) {
      first_run = results;
      continue;
    }
    // Deterministic: the second run gives every frame's result bit for bit (the whole pose,
    // rotation and translation, and what the frame did).
    REQUIRE(results.size() == first_run.size());
    for (std::size_t k = 0; k < results.size(); ++k) {
      const vo::FrameResult &a = first_run[k], &b = results[k];
      INFO("frame " << k);
      CHECK(b.state == a.state);
      CHECK(b.has_pose == a.has_pose);
      CHECK(b.T_wc.R == a.T_wc.R);
      CHECK(b.T_wc.t == a.T_wc.t);
      CHECK(b.keyframe == a.keyframe);
      CHECK(b.reinitialised == a.reinitialised);
      CHECK(b.tracked_points == a.tracked_points);
      CHECK(b.residual_rms == a.residual_rms);
      CHECK(b.tau.h == a.tau.h);
      CHECK(b.tau.c == a.tau.c);
      CHECK(b.centre_held == a.centre_held);
    }
  }
}

TEST_CASE("poses stay rigid motions over a long run", "[vo][board]") {
  // The constant-velocity guess composes a pose with the inverse of the previous one; with the
  // transpose standing in for the inverse, a rotation that is not quite orthonormal doubles its
  // error every frame, until the poses shear the scene and no new map can be started.
  WallOdometry wall;
  vo::Odometry& odometry = wall.odometry;
  REQUIRE(odometry.ok());
  const int n = 150;
  int posed = 0;
  double worst = 0;
  for (int i = 0; i < n; ++i) {
    const std::vector<std::uint16_t> frame = render(i / 60.0);
    vo::FrameInput in;
    in.raw = frame;
    in.t_s = i / 60.0, in.chain_broken = i == 0;
    const vo::FrameResult r = odometry.process(in);
    if (!r.has_pose) continue;
    ++posed;
    worst = std::max(worst, (r.T_wc.R * r.T_wc.R.transpose() - vo::Mat3::Identity()).norm());
  }
  INFO("posed " << posed << " of " << n << ", worst |R R^T - I| " << worst);
  CHECK(posed >= n / 2);
  CHECK(worst < 1e-9);
}

TEST_CASE("a repeated frame is skipped and tracking goes on after it", "[vo][board]") {
  // Every 8th frame repeats its predecessor bit for bit (a USB core or a frame-rate converter
  // sending a frame twice). Processed as a new frame it would put the camera where it was a frame
  // ago, at the new time.
  WallOdometry wall;
  vo::Odometry& odometry = wall.odometry;
  REQUIRE(odometry.ok());
  const int n = 64;
  std::vector<std::uint16_t> frame;
  int posed = 0, repeats = 0, repeats_reported = 0;
  std::vector<vo::Vec3> est, truth;
  for (int i = 0; i < n; ++i) {
    const bool repeat = i % 8 == 7;
    if (!repeat) frame = render(i / 60.0);
    repeats += repeat;
    vo::FrameInput in;
    in.raw = frame;
    in.t_s = i / 60.0, in.chain_broken = i == 0;
    const vo::FrameResult r = odometry.process(in);
    if (repeat) {
      repeats_reported += r.state == vo::TrackingState::duplicate;
      CHECK_FALSE(r.has_pose);
      continue;
    }
    CHECK(r.state != vo::TrackingState::duplicate);
    CHECK(r.state != vo::TrackingState::lost);
    if (r.has_pose) ++posed, est.push_back(r.T_wc.t), truth.push_back(pose_wc(i / 60.0).t);
  }
  CHECK(repeats_reported == repeats);
  INFO("posed " << posed << " of " << n - repeats);
  CHECK(posed >= (n - repeats) / 2);
  REQUIRE(est.size() >= 2);
  const vo::Vec3 de = est.back() - est.front(), dt = truth.back() - truth.front();
  CHECK(std::acos(de.normalized().dot(dt.normalized())) * 180 / M_PI < 10.0);
}

TEST_CASE("the shutter step gain is 1 - alpha for an even split and inverts to its tau", "[vo][board]") {
  const double period = 1 / 60.0;
  for (const double tau : {0.002, 0.008, 0.012, 0.040}) {
    const double even = vo::shutter_step_gain({tau, tau}, 0.5 * period, 0.5 * period, 0.5 * period);
    CHECK(even == Approx(1 - std::exp(-0.5 * period / tau)));
    CHECK(vo::tau_from_shutter_step_gain(even, 0.5 * period, 0.5 * period, 0.5 * period) == Approx(tau).epsilon(1e-9));
    // An uneven split, and a frame whose exposure differs from the reference's.
    const double te = 0.0125, tr = period - te;
    for (const double exposure : {te, 0.8 * te}) {
      const double g = vo::shutter_step_gain({tau, tau}, exposure, tr, te);
      CHECK(vo::tau_from_shutter_step_gain(g, exposure, tr, te) == Approx(tau).epsilon(1e-9));
    }
  }
  // Gains no tau within 1..100 ms gives.
  CHECK(vo::tau_from_shutter_step_gain(1.0, 0.5 * period, 0.5 * period, 0.5 * period) == 0);
  CHECK(vo::tau_from_shutter_step_gain(0.01, 0.5 * period, 0.5 * period, 0.5 * period) == 0);
}

TEST_CASE("a shutter event's step response measures tau and its offset step is followed", "[vo][board]") {
  // The wall through the two-frame model (tau 10 ms, 60 Hz, exposure = readout), in frames.csv's
  // terms: y_i = alpha y_{i-1} + (1 - alpha) K_i, K the static level. At frame 40 a shutter event:
  // the pixels settled on the shutter (at the scene's mean level), and the camera's offset jumped
  // by 25 counts for every frame from then on (what a flat-field correction does).
  const double tau = 0.010, period = 1 / 60.0;
  // A second event at frame 55 whose frame the camera delivers settled (no step response, as a
  // camera that shows frames again only once the shutter has been open a while): not taken.
  const int n = 70, event = 40, settled_event = 55;
  const double offset_step = 25;
  vo::VoConfig c;
  c.width = kW, c.height = kH, c.camera = camera();
  c.photometric = vo::Photometric::ir;
  c.tau_init_s = 0.015f;  // far off: only the step response can bring it to 10 ms by frame 40
  std::vector<std::byte> arena(vo::Odometry::arena_bytes(c));
  vo::Odometry odometry(c, arena);
  REQUIRE(odometry.ok());
  CarriedWall wall(tau, 0.5 * period, 0.5 * period);
  double measured = 0, rms_before = 0, rms_after = 0;
  int lost_after = 0, posed_after = 0;
  for (int i = 0; i < n; ++i) {
    // settled_event: the chain goes on (the camera's frame is already settled).
    const std::vector<std::uint16_t>& frame =
        wall.next(render(i * period), 0.5 * period, 0.5 * period, i == event, i >= event ? offset_step : 0.0);
    vo::FrameInput in;
    in.raw = frame;
    in.t_s = i * period, in.exposure_s = 0.5 * period, in.readout_prev_s = i > 0 ? 0.5 * period : 0.0;
    in.chain_broken = i == 0;
    in.shutter_event = i == event || i == settled_event;
    const vo::FrameResult r = odometry.process(in);
    if (i == event) measured = r.shutter_tau_s;
    if (i != event) CHECK(r.shutter_tau_s == 0);
    if (i >= event) lost_after += r.state == vo::TrackingState::lost, posed_after += r.has_pose;
    // The residuals of the frames after the event against those before: the scene estimate carries
    // the new offset, which the keyframes made before the event do not have.
    if (i >= event - 20 && i < event) rms_before += r.residual_rms / 20;
    if (i > event && i <= event + 14) rms_after += r.residual_rms / 14;
    if (i > event) CHECK(r.tau.c == Approx(measured));
  }
  INFO("tau from the step response " << measured * 1e3 << " ms; after the event " << posed_after << " posed, " << lost_after
                                       << " lost; residual rms " << rms_before << " before, " << rms_after << " after");
  // The keyframes it is measured against were made with the pairs' estimate, still high here, and
  // keep a little of the ghost (10.16 ms; from a 10 ms start 10.04).
  CHECK(measured == Approx(tau).epsilon(0.02));
  CHECK(lost_after == 0);
  CHECK(posed_after == n - event);
  CHECK(rms_after < 1.5 * rms_before);
}

namespace {

struct SwitchingWall {
  int frames = 0, posed = 0;
  double tau_end = 0;
};

// The wall through the two-frame model (tau 10 ms, 60 Hz) with the exposure switching between 45
// and 55 % of the period every `period_frames` frames (readout: the rest), in the ir mode with
// tau started at `tau_init_s` (and held there unless `estimate_tau`); the camera adds `offset`
// counts. 90 frames (1.5 s).
SwitchingWall run_switching_wall(int period_frames, float tau_init_s, double offset = 0, bool estimate_tau = true) {
  const double tau = 0.010, period = 1 / 60.0;
  const auto exposure = [&](int i) { return ((i / period_frames) % 2 == 0 ? 0.45 : 0.55) * period; };
  vo::VoConfig c;
  c.width = kW, c.height = kH, c.camera = camera();
  c.photometric = vo::Photometric::ir;
  c.tau_init_s = tau_init_s;
  c.estimate_tau = estimate_tau;
  std::vector<std::byte> arena(vo::Odometry::arena_bytes(c));
  vo::Odometry odometry(c, arena);
  SwitchingWall out;
  if (!odometry.ok()) return out;
  CarriedWall wall(tau, exposure(0), period - exposure(0));
  out.frames = 90;
  for (int i = 0; i < out.frames; ++i) {
    const double te = exposure(i), tr_prev = period - exposure(std::max(i - 1, 0));
    const std::vector<std::uint16_t>& frame = wall.next(render(i * period), te, tr_prev, false, offset);
    vo::FrameInput in;
    in.raw = frame;
    in.t_s = i * period, in.exposure_s = te, in.readout_prev_s = i > 0 ? tr_prev : 0.0;
    in.chain_broken = i == 0;
    const vo::FrameResult r = odometry.process(in);
    out.posed += r.has_pose;
    out.tau_end = r.tau.c;
  }
  return out;
}

}  // namespace

TEST_CASE("frames whose exposure changes keep the carry-over fit unbiased", "[vo][board]") {
  // The pairs assumed beta_i = beta_{i-1}: at each switch A - alpha B was (beta_i - beta_{i-1}) u,
  // a first-order error. With rho = beta_i / beta_{i-1} in the pairs the switch is a step response
  // instead, which measures alpha at first order, once d r / d alpha takes in that rho and kappa
  // move with tau too.
  const SwitchingWall run = run_switching_wall(12, 0.015f);
  INFO("tau after 1.5 s " << run.tau_end * 1e3 << " ms; " << run.posed << " of " << run.frames << " posed");
  CHECK(run.tau_end == Approx(0.010).epsilon(0.05));
  // 13 frames initialise the map; the first switch comes right after, with tau still at 15 ms,
  // and the brightness must follow it without losing the track.
  CHECK(run.posed >= run.frames - 15);
}

TEST_CASE("a change of exposure at a wrong tau does not lose the track", "[vo][board][slow-emulated]") {
  // The raw static level of a timing differs from another's by a factor of the true tau, and the
  // scene estimate removes the frames before a change rightly only at the true tau: across a
  // change (and in the initialisation) the ir modes estimate the gain and offset. Before they did,
  // tau started at 20 ms for 10 posed 0 of 90 frames with a switch every 8 or 10 frames (the
  // initialisation never got through one) and 1 with one every 12; after, 73-77. Once the
  // tracking image was low-passed (VoConfig::smoothing 1) the initialisation with a switch every
  // 12 frames waited out the basin comparison past the first switch, lost the frame after it and
  // started again (61 posed), until the offset at a change started where the frames' mean levels
  // put it: 77 with a switch every 8 or 12 frames.
  for (const int period_frames : {8, 12}) {
    const SwitchingWall run = run_switching_wall(period_frames, 0.020f);
    INFO("a switch every " << period_frames << " frames: " << run.posed << " of " << run.frames
                           << " posed, tau after 1.5 s " << run.tau_end * 1e3 << " ms");
    CHECK(run.posed >= run.frames - 15);
    CHECK(run.tau_end == Approx(0.010).epsilon(0.05));
  }
}

TEST_CASE("a camera offset across changes of exposure is estimated with the gain", "[vo][board][slow-emulated]") {
  // The raw counts of a camera start from what a pixel reads at the substrate's temperature, not
  // from 0: between two timings the level then changes by a gain and an offset. With tau given
  // (held at the truth or at twice it) the track holds. The offset at a change starts where the
  // frames' mean scene levels put it: 77 of 90 posed, where starting at the last frame's offset
  // the first initialisation restarted across the first switch (62-63; before the brightness
  // was freed there 1-2). With tau estimated as well: the next test.
  for (const float tau_s : {0.010f, 0.020f}) {
    const SwitchingWall run = run_switching_wall(12, tau_s, 3000.0, false);
    INFO("camera offset 3000, tau held at " << tau_s * 1e3 << " ms: " << run.posed << " of " << run.frames << " posed");
    CHECK(run.posed >= run.frames - 15);
  }
}

TEST_CASE("a camera offset across changes of exposure does not bias the tau estimate", "[vo][board][slow-emulated]") {
  // Across a change of timing the offset leaves A - alpha B a constant at every pixel, which the
  // pairs read as part of the step response until the fit gave such a frame a constant of its
  // own: 3000 counts drove tau from 15 and 20 ms to 19.8 and 15.7 ms after 1.5 s (the truth 10);
  // with the constant 10.05-10.06 ms from 10, 15 and 20.
  for (const float tau_init_s : {0.010f, 0.015f, 0.020f}) {
    const SwitchingWall run = run_switching_wall(12, tau_init_s, 3000.0, true);
    INFO("camera offset 3000, tau started at " << tau_init_s * 1e3 << " ms: " << run.tau_end * 1e3 << " ms after 1.5 s, "
                                                << run.posed << " of " << run.frames << " posed");
    CHECK(run.tau_end == Approx(0.010).epsilon(0.05));
    CHECK(run.posed >= run.frames - 15);
  }
}

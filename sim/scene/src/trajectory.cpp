#include "bolo/sim/scene/trajectory.hpp"

#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "bolo/sim/scene/scene.hpp"
#include "path.hpp"
#include "random.hpp"

namespace bolo::sim::scene {
namespace {

namespace L = street_layout;
using detail::PlanarPath;
using detail::Rng;

constexpr double kDeg = std::numbers::pi / 180.0;

double smootherstep01(double x) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  return x * x * x * (x * (x * 6.0 - 15.0) + 10.0);
}

double softplus(double x) { return x > 0.0 ? x + std::log1p(std::exp(-x)) : std::log1p(std::exp(x)); }

// Sum of sines with random frequencies and phases: a smooth, deterministic jitter.
struct Wobble {
  double amp[3], freq[3], phase[3];
  Wobble(Rng& rng, double amplitude, double f_lo, double f_hi) {
    const double share[3] = {1.0, 0.55, 0.3};
    for (int i = 0; i < 3; ++i) {
      amp[i] = amplitude * share[i];
      freq[i] = rng.uniform(f_lo, f_hi) * (1.0 + 0.7 * i);
      phase[i] = rng.uniform(0.0, 2.0 * std::numbers::pi);
    }
  }
  double operator()(double t) const {
    double v = 0.0;
    for (int i = 0; i < 3; ++i) v += amp[i] * std::sin(2.0 * std::numbers::pi * freq[i] * t + phase[i]);
    return v;
  }
};

// --- drive ---------------------------------------------------------------------------------

Trajectory make_drive(std::uint64_t seed) {
  Rng rng(seed ^ 0xD21FEull);
  const double lane = L::kLaneOffset, cx = L::kCrossX;
  const double turn_len = 16.0;
  const Eigen::Vector2d a = detail::turn_displacement(turn_len, -std::numbers::pi / 2.0);  // (forward, -right)
  const double x_turn = cx - lane - a.x();
  auto path = std::make_shared<const PlanarPath>(
      Eigen::Vector2d(0.0, -lane), 0.0,
      std::vector<PlanarPath::Segment>{{x_turn, 0.0}, {turn_len, -std::numbers::pi / 2.0}, {900.0, 0.0}});
  const double y_after = -lane + a.y();
  const double s_stop = x_turn + turn_len + (y_after - (L::kCrossSouth + 25.0));
  const double s_mid = x_turn + 0.5 * turn_len;

  const double v_cruise = rng.uniform(9.5, 10.5), v_turn = 5.0, dip_w = 2.5;
  const double amp = 1.5, omega = 2.0 * std::numbers::pi / rng.uniform(12.0, 18.0), phi = rng.uniform(0.0, 2.0 * std::numbers::pi);
  const double dv = v_cruise - v_turn, k = dv * dip_w * std::sqrt(std::numbers::pi) / 2.0;
  auto u_of = [=](double t, double tc) {
    return v_cruise * t - k * (std::erf((t - tc) / dip_w) + std::erf(tc / dip_w)) +
           amp * (std::sin(omega * t + phi) - std::sin(phi));
  };
  // Time of the slowest point, placed at the middle of the turn.
  double lo = 0.0, hi = 1000.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (u_of(mid, mid) < s_mid ? lo : hi) = mid;
  }
  const double tc = 0.5 * (lo + hi);
  const double stop_d = 6.0;
  auto s_of = [=](double t) { return s_stop - stop_d * softplus((s_stop - u_of(t, tc)) / stop_d); };

  const Wobble bounce(rng, 0.012, 1.2, 1.8), roll_w(rng, 0.4 * kDeg, 0.6, 1.1), pitch_w(rng, 0.3 * kDeg, 1.0, 1.6),
      yaw_w(rng, 0.2 * kDeg, 0.3, 0.7);
  auto pose = [=](double t) {
    const double s = s_of(t);
    const auto st = path->at(s);
    const double h = 1e-3;
    const double v = (s_of(t + h) - s_of(t - h)) / (2.0 * h);
    const double lateral_acc = v * v * path->curvature_at(s);
    const double shake = 1.0 - std::exp(-v / 2.0);  // road-induced: fades out at standstill
    const double roll = shake * roll_w(t) + 0.006 * lateral_acc;  // the body leans out of the turn
    const double pitch = -1.5 * kDeg + shake * pitch_w(t);
    const double yaw = st.heading + shake * yaw_w(t);
    return camera_pose(Eigen::Vector3d(st.p.x(), st.p.y(), 1.4 + shake * bounce(t)), yaw, pitch, roll);
  };
  return Trajectory("drive", "street", 90.0, pose);
}

// --- handheld --------------------------------------------------------------------------------

struct LookEvent {
  double start, rise, hold, back, yaw, pitch;
};

// Three quick look-arounds in each 30 s cycle; zero at the cycle boundaries (continuous).
void look_offsets(std::uint64_t seed, double t, double& yaw, double& pitch) {
  constexpr double kCycle = 30.0;
  const double c = std::floor(t / kCycle);
  const double tc = t - c * kCycle;
  Rng rng(detail::hash(seed, static_cast<std::uint64_t>(static_cast<std::int64_t>(c)), 0x100Cull));
  yaw = pitch = 0.0;
  for (int k = 0; k < 3; ++k) {
    LookEvent e;
    e.start = 10.0 * k + rng.uniform(1.0, 5.5);
    e.rise = rng.uniform(0.3, 0.5);
    e.hold = rng.uniform(0.8, 2.0);
    e.back = rng.uniform(0.35, 0.7);
    const bool is_yaw = rng.chance(0.7);
    const double sign = rng.chance(0.5) ? 1.0 : -1.0;
    const double a_yaw = sign * rng.uniform(40.0, 90.0) * kDeg;
    const double a_pitch = rng.uniform(15.0, 35.0) * kDeg;
    const double b = smootherstep01((tc - e.start) / e.rise) -
                     smootherstep01((tc - e.start - e.rise - e.hold) / e.back);
    if (is_yaw)
      yaw += a_yaw * b;
    else
      pitch += a_pitch * b;
  }
}

Trajectory make_handheld(std::uint64_t seed) {
  Rng rng(seed ^ 0x4A2D4E1Dull);
  const double y0 = -7.8, x0 = 40.0, run = 200.0, uturn = 1.6;
  auto path = std::make_shared<const PlanarPath>(
      Eigen::Vector2d(x0, y0), 0.0,
      std::vector<PlanarPath::Segment>{{run, 0.0}, {uturn, std::numbers::pi}, {run, 0.0}, {uturn, std::numbers::pi}});
  const double loop = path->length();
  const double speed = rng.uniform(1.25, 1.45);
  const double step_hz = rng.uniform(1.7, 1.95);
  const double eye = L::kSidewalkHeight + 1.5;
  const Wobble sx(rng, 0.004, 2.0, 4.0), sy(rng, 0.004, 2.0, 4.0), sz(rng, 0.004, 2.0, 4.0);
  const Wobble ryaw(rng, 0.35 * kDeg, 0.5, 2.5), rpitch(rng, 0.35 * kDeg, 0.5, 2.5), rroll(rng, 0.25 * kDeg, 0.5, 2.5);
  const Wobble tremor(rng, 0.08 * kDeg, 6.0, 9.0);
  const std::uint64_t look_seed = rng.next();
  auto pose = [=](double t) {
    double s = std::fmod(speed * t + 0.03 * std::sin(2.0 * std::numbers::pi * step_hz * t), loop);
    if (s < 0.0) s += loop;
    const auto st = path->at(s);
    const Eigen::Vector2d fwd(std::cos(st.heading), std::sin(st.heading));
    const Eigen::Vector2d left(-fwd.y(), fwd.x());
    const double bob = 0.02 * std::sin(2.0 * std::numbers::pi * step_hz * t);
    const double sway = 0.015 * std::sin(std::numbers::pi * step_hz * t);  // one sway per two steps
    const Eigen::Vector2d xy = st.p + sway * left;
    const Eigen::Vector3d p(xy.x() + sx(t), xy.y() + sy(t), eye + bob + sz(t));
    double look_yaw, look_pitch;
    look_offsets(look_seed, t, look_yaw, look_pitch);
    const double yaw = st.heading + look_yaw + ryaw(t) + tremor(t);
    const double pitch = -4.0 * kDeg + look_pitch + rpitch(t) + tremor(t + 0.37);
    const double roll = 0.8 * kDeg * std::sin(std::numbers::pi * step_hz * t) + rroll(t);
    return camera_pose(p, yaw, pitch, roll);
  };
  return Trajectory("handheld", "street", 60.0, pose);
}

// --- flyover --------------------------------------------------------------------------------

// A drone along the main street at roof height, the camera pitched down at the road: image motion
// mostly parallel to the image plane over a near-planar ground, unlike the drive's forward motion.
Trajectory make_flyover(std::uint64_t seed) {
  Rng rng(seed ^ 0xF1E0Dull);
  const double speed = rng.uniform(5.5, 6.5), x0 = -100.0;
  const double altitude = rng.uniform(11.0, 13.0), pitch0 = -rng.uniform(40.0, 50.0) * kDeg;
  const Wobble climb(rng, 0.8, 0.05, 0.12), drift(rng, 1.5, 0.03, 0.08);
  const Wobble yaw_w(rng, 3.0 * kDeg, 0.05, 0.2), pitch_w(rng, 2.0 * kDeg, 0.1, 0.3), roll_w(rng, 1.5 * kDeg, 0.1, 0.4);
  const Wobble gust(rng, 0.05, 1.0, 2.5);
  auto pose = [=](double t) {
    const Eigen::Vector3d p(x0 + speed * t + gust(t), drift(t), altitude + climb(t) + gust(t + 0.5));
    return camera_pose(p, yaw_w(t), pitch0 + pitch_w(t), roll_w(t));
  };
  return Trajectory("flyover", "street", 80.0, pose);
}

}  // namespace

Trajectory::Trajectory(std::string name, std::string scene, double duration_s, std::function<Pose(double)> pose)
    : name_(std::move(name)), scene_(std::move(scene)), duration_s_(duration_s), pose_(std::move(pose)) {
  if (!pose_) throw std::invalid_argument("trajectory '" + name_ + "': empty pose function");
}

std::vector<std::string> trajectory_names() { return {"drive", "handheld", "flyover", "static", "pan", "blackbody"}; }

Trajectory make_trajectory(const std::string& name, std::uint64_t seed) {
  if (name == "drive") return make_drive(seed);
  if (name == "handheld") return make_handheld(seed);
  if (name == "flyover") return make_flyover(seed);
  if (name == "static") {
    const Pose p = camera_pose(Eigen::Vector3d(150.0, -7.2, L::kSidewalkHeight + 1.5), std::numbers::pi / 3.0, -3.0 * kDeg);
    return Trajectory("static", "street", 30.0, [p](double) { return p; });
  }
  if (name == "pan") {
    const Eigen::Vector3d eye(L::kCrossX, 7.5, L::kSidewalkHeight + 1.5);
    const double rate = 30.0 * kDeg;
    return Trajectory("pan", "street", 24.0,
                      [eye, rate](double t) { return camera_pose(eye, -std::numbers::pi / 2.0 + rate * t, -2.0 * kDeg); });
  }
  if (name == "blackbody") {
    const Pose p = camera_pose(Eigen::Vector3d(0.0, 0.0, 1.2), 0.0, 0.0);
    return Trajectory("blackbody", "lab", BlackbodySchedule{}.period_s(), [p](double) { return p; });
  }
  std::string valid;
  for (const auto& n : trajectory_names()) valid += (valid.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown trajectory '" + name + "' (valid trajectories: " + valid + ")");
}

std::string to_tum(const Trajectory& trajectory, std::span<const double> times) {
  std::string out;
  out.reserve(times.size() * 100);
  for (double t : times) out += to_tum(t, trajectory.pose(t));
  return out;
}

}  // namespace bolo::sim::scene

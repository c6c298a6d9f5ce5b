// Study harness (not a test): the full VO on frames rendered
// in-process with Gaussian pixel noise and no sensor model, and after every keyframe the median
// ratio of each window keyframe's active inverse depths to the true ones (1 / the map's scale
// there). Options from the environment: TRAJ, SEED, NOISE (counts), SS rays per axis, FRAMES,
// MODE none|affine, TAU (s, the two-frame model's carry-over; 0: none), NOISE_SEED, RENDER_DT (s
// added to the render time), NOBA=1 (no window BA), REC (a recording's frames.npy instead), ACT=1
// (every activation), VERBOSE=1 (every frame's rotation and translation-direction error).
//   TRAJ=flyover SEED=3 NOISE=6 build/tests/vo/vo_scale_drift_experiment

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <cstdint>
#include "bolo/vo/odometry.hpp"
#include "rendered_pair.hpp"
#include "state.hpp"
#include "tau_truth_feed.hpp"

using namespace bolo;

namespace {
double env_or(const char* name, double fallback) {
  const char* v = std::getenv(name);
  return v ? std::atof(v) : fallback;
}
}  // namespace

int main() {
  const char* traj_env = std::getenv("TRAJ");
  const std::string traj = traj_env ? traj_env : "flyover";
  const auto seed = static_cast<std::uint64_t>(env_or("SEED", 3));
  const double noise = env_or("NOISE", 6);
  const int frames = static_cast<int>(env_or("FRAMES", 240));
  test::RenderedSequence seq{"street", traj.c_str(), 160, 120, static_cast<unsigned>(env_or("SS", 3)), seed};
  vo::VoConfig cfg;
  cfg.width = seq.width, cfg.height = seq.height, cfg.camera = seq.intrinsics();
  const char* mode = std::getenv("MODE");
  cfg.photometric = mode && std::string(mode) == "affine" ? vo::Photometric::affine : vo::Photometric::none;
  cfg.window_ba = env_or("NOBA", 0) == 0;
  std::vector<std::byte> memory(vo::Odometry::arena_bytes(cfg));
  vo::Odometry odometry(cfg, memory);
  if (!odometry.ok()) {
    std::fprintf(stderr, "vo_scale_drift_experiment: invalid VO configuration\n");
    return 1;
  }
  // The state the constructor laid out: the arena's first piece (Arena::take's alignment).
  const std::uintptr_t align = std::max<std::uintptr_t>(16, alignof(vo::State));
  const auto base = reinterpret_cast<std::uintptr_t>(memory.data());
  const vo::State& s = *reinterpret_cast<const vo::State*>((base + align - 1) / align * align);
  test::ApproxNormal gauss(static_cast<std::uint32_t>(env_or("NOISE_SEED", 4242)));
  std::uint32_t last_created = 0;
  std::map<std::pair<std::uint32_t, std::uint32_t>, bool> active_before;
  double activation_log = 0, activation_n = 0;
  const double fps = 60;
  const double tau = env_or("TAU", 0);
  const double alpha = tau > 0 ? std::exp(-0.5 / fps / tau) : 0.0;
  std::vector<double> carry;
  // REC dir: frames.npy of a `bolo simulate` recording of the same trajectory and seed instead
  // (uint16, 160 x 120); its truth poses are at mid-exposure, half a readout after t.
  std::vector<std::uint16_t> recorded;
  const std::size_t plane = std::size_t{seq.width} * seq.height;
  double truth_dt = 0;
  if (const char* rec = std::getenv("REC")) {
    std::ifstream f(std::string(rec) + "/frames.npy", std::ios::binary);
    if (!f) {
      std::fprintf(stderr, "vo_scale_drift_experiment: cannot read %s/frames.npy\n", rec);
      return 1;
    }
    std::vector<char> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    const std::size_t header = 10 + static_cast<std::uint8_t>(bytes[8]) + 256u * static_cast<std::uint8_t>(bytes[9]);
    recorded.resize((bytes.size() - header) / 2);
    std::memcpy(recorded.data(), bytes.data() + header, recorded.size() * 2);
    truth_dt = 0.5 / fps / 2;
  }
  for (int i = 0; i < frames; ++i) {
    const double t = i / fps;
    std::vector<std::uint16_t> raw;
    if (!recorded.empty()) {
      raw.assign(recorded.begin() + static_cast<long>(i * plane), recorded.begin() + static_cast<long>((i + 1) * plane));
    } else {
      raw = seq.frame(t + env_or("RENDER_DT", 0));
      // TAU s: the two-frame model's carry-over (exposure = readout = half the period) before the noise.
      if (carry.empty()) carry.assign(raw.begin(), raw.end());
      for (std::size_t q = 0; q < raw.size(); ++q) carry[q] = alpha * carry[q] + (1 - alpha) * raw[q];
      for (std::size_t q = 0; q < raw.size(); ++q)
        raw[q] = static_cast<std::uint16_t>(std::clamp(std::lround(carry[q] + noise * gauss()), 0L, 65535L));
    }
    vo::FrameInput in;
    in.raw = raw;
    in.t_s = t, in.chain_broken = i == 0;
    const vo::FrameResult r = odometry.process(in);
    if (std::getenv("VERBOSE") && r.has_pose && s.kf_count > 0) {
      // Against the oldest window keyframe: rotation error, and the translation direction's error.
      const vo::Keyframe& o = s.kf[s.order[0]];
      const vo::Mat3 R_est = s.motion.T_cw.R * o.T_cw.R.transpose();
      const vo::Mat3 R_tru = seq.T_cw(t + truth_dt).R * seq.T_cw(o.t_s + truth_dt).R.transpose();
      const vo::Vec3 d_est = (s.motion.T_cw * o.T_cw.inverse()).t, d_tru = (seq.T_cw(t + truth_dt) * seq.T_cw(o.t_s + truth_dt).inverse()).t;
      const double dir = std::acos(std::clamp(d_est.normalized().dot(d_tru.normalized()), -1.0, 1.0)) * 180 / M_PI;
      std::printf("frame %d (kf %u at %.2f s) rotation %.2f deg off of %.2f; translation direction %.1f deg off; est rot axis %.2f %.2f %.2f true %.2f %.2f %.2f\n", i, o.id, o.t_s,
                  Eigen::AngleAxisd(R_est * R_tru.transpose()).angle() * 180 / M_PI, Eigen::AngleAxisd(R_tru).angle() * 180 / M_PI, dir,
                  Eigen::AngleAxisd(R_est).axis().x(), Eigen::AngleAxisd(R_est).axis().y(), Eigen::AngleAxisd(R_est).axis().z(),
                  Eigen::AngleAxisd(R_tru).axis().x(), Eigen::AngleAxisd(R_tru).axis().y(), Eigen::AngleAxisd(R_tru).axis().z());
    }
    {
      // Points activated by this frame: their idepth ratio against the window's older points'.
      std::vector<double> fresh, settled, fresh_mid, fresh_lo, fresh_hi;
      for (std::uint32_t o = 0; o < s.kf_count; ++o) {
        const vo::Keyframe& kf = s.kf[s.order[o]];
        for (std::uint32_t j = 0; j < kf.count; ++j) {
          const vo::Point& p = kf.points[j];
          const auto key = std::make_pair(kf.id, j);
          const bool was_active = active_before.count(key) > 0;
          if (p.status != vo::PointStatus::active || p.idepth <= 0) {
            active_before.erase(key);
            continue;
          }
          active_before.insert({key, true});
          const double z = seq.depth(kf.t_s + truth_dt, p.u, p.v);
          if (!(z > 0)) continue;
          (was_active ? settled : fresh).push_back(p.idepth * z);
          if (!was_active) fresh_mid.push_back(0.5 * (p.idepth_min + p.idepth_max) * z), fresh_lo.push_back(p.idepth_min * z), fresh_hi.push_back(p.idepth_max * z);
        }
      }
      if (!fresh.empty() && !settled.empty()) {
        std::sort(fresh.begin(), fresh.end());
        std::sort(settled.begin(), settled.end());
        const double ratio = fresh[fresh.size() / 2] / settled[settled.size() / 2];
        activation_log += ratio;
        activation_n += 1;
        const auto med = [](std::vector<double> v) {
          std::sort(v.begin(), v.end());
          return v[v.size() / 2];
        };
        // The tracked motion from the oldest window keyframe to this frame against the truth, times
        // the settled map's q: 1 when the poses agree with the map's scale.
        const vo::Keyframe& oldest = s.kf[s.order[0]];
        const double est_t = (oldest.T_cw.inverse().t - s.motion.T_cw.inverse().t).norm();
        const double tru_t = (seq.T_cw(oldest.t_s + truth_dt).inverse().t - seq.T_cw(t + truth_dt).inverse().t).norm();
        // The rotation from the oldest window keyframe to this frame: its error against the truth.
        const vo::Mat3 R_est = s.motion.T_cw.R * oldest.T_cw.R.transpose();
        const vo::Mat3 R_tru = seq.T_cw(t + truth_dt).R * seq.T_cw(oldest.t_s + truth_dt).R.transpose();
        const double rot_err = Eigen::AngleAxisd(R_est * R_tru.transpose()).angle() * 180 / M_PI;
        const double rot_tru = Eigen::AngleAxisd(R_tru).angle() * 180 / M_PI;
        if (std::getenv("ACT"))
          std::printf("   pose scale x settled q: %.3f, rotation %.2f deg off of %.2f  ", est_t / tru_t * settled[settled.size() / 2], rot_err, rot_tru);
        if (std::getenv("ACT"))
          std::printf("frame %d: %zu activated, median q %.2f (interval %.2f .. %.2f, middle %.2f) against %.2f (x%.3f)\n", i, fresh.size(),
                      fresh[fresh.size() / 2], med(fresh_lo), med(fresh_hi), med(fresh_mid), settled[settled.size() / 2], ratio);
      }
    }
    if (s.kf_created == last_created) continue;
    last_created = s.kf_created;
    // Per window keyframe (oldest first): id, frame time, active points, median idepth ratio.
    std::printf("frame %3d (%s):", i, r.has_pose ? "posed" : "-");
    for (std::uint32_t o = 0; o < s.kf_count; ++o) {
      const vo::Keyframe& kf = s.kf[s.order[o]];
      std::vector<double> q;
      for (std::uint32_t j = 0; j < kf.count; ++j) {
        const vo::Point& p = kf.points[j];
        if (p.status != vo::PointStatus::active || p.idepth <= 0) continue;
        const double z = seq.depth(kf.t_s + truth_dt, p.u, p.v);
        if (z > 0) q.push_back(p.idepth * z);
      }
      if (q.empty()) continue;
      std::nth_element(q.begin(), q.begin() + static_cast<long>(q.size() / 2), q.end());
      std::printf(" [%u %.2fs n%zu %.3f]", kf.id, kf.t_s, q.size(), q[q.size() / 2]);
    }
    // The scale of the newest keyframe's pose against the oldest: |t| estimated / true.
    const vo::Keyframe& a = s.kf[s.order[0]];
    const vo::Keyframe& b = s.kf[s.order[s.kf_count - 1]];
    const double est = (a.T_cw.inverse().t - b.T_cw.inverse().t).norm();
    const double tru = (seq.T_cw(a.t_s + truth_dt).inverse().t - seq.T_cw(b.t_s + truth_dt).inverse().t).norm();
    std::printf("  window baseline scale %.3f\n", tru > 0 ? est / tru : 0.0);
  }
  std::printf("activations: mean ratio of fresh to settled median q %.3f over %.0f frames\n", activation_log / activation_n, activation_n);
  return 0;
}

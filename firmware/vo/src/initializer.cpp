// Monocular initialisation without outside help: the first frame becomes a keyframe whose
// points all start at inverse depth 1; every following frame refines the relative pose and every
// point's inverse depth jointly (Gauss-Newton, Schur complement over the points, coarse to fine),
// with a weak prior pulling each inverse depth towards the mean while the baseline is too small
// to tell. Once the baseline (translation over mean depth) is large enough and a solve from
// scratch agrees with the running one on the basin (or 30 frames have passed), the points become
// active and tracking takes over. The mean inverse depth is kept at 1, which fixes the map's scale.
// A frame that a rotation alone explains as well ends the initialisation as that rotation, with
// the map flat (a pan, a turn on the spot: explained_by_rotation).

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

#include "state.hpp"

namespace bolo::vo {
namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;

constexpr double kDepthPrior = 100;  // per point, pulls towards the mean inverse depth
constexpr std::uint32_t kMinInitFrames = 10;
constexpr double kMinInitSeconds = 10.0 / 30.0;  // or as long as kMinInitFrames take at 30 Hz
constexpr std::uint32_t kGiveUp = 1000;  // >= the frame loop's restart limit
constexpr std::uint32_t kMinInitPoints = 20;  // the tracker's least inliers
// Baseline needed, as the flow it would cause at the mean depth across the view (f |t| with the
// mean inverse depth at 1), share of width + height; not the points' median translation flow,
// which under forward motion is radial and small near the focus of expansion, so it would be
// reached only after the first keyframe's patterns had changed too much to match.
constexpr double kInitFlow = 0.02;

struct InitSystem {
  Mat6 H = Mat6::Zero();
  Vec6 g = Vec6::Zero();
  double energy = 0;
  std::uint32_t inliers = 0;
  // The brightness block (gain, offset), solved on its own beside the pose: sum w z z^T and
  // sum w r z with z = (reference - host offset, 1).
  double h_gg = 0, h_go = 0, h_oo = 0, g_g = 0, g_o = 0;
};

Keyframe& init_host(MapCore& s) { return s.kf[s.order[0]]; }

// The frame's brightness against the host, as the tracker has it (value = e^(a - a_host)
// (reference - b_host) + b). Free only where the frame does not have the host's level
// (same_level: across a change of exposure or readout), in the ir modes and in affine; otherwise
// the frames are compared as they are.
struct Brightness {
  double a = 0, b = 0;
  bool free = false;  // brightness_free() for this frame
};
bool brightness_free(const MapCore& s, const CurrentFrame& f) {
  const Keyframe& host = s.kf[s.order[0]];
  return (uses_carry_model(s.cfg) || s.cfg.photometric == Photometric::affine) && !same_level(f, host);
}

constexpr std::uint32_t kCells = 8;  // prior target: the mean inverse depth of the point's cell

// Mean inverse depth per cell of a kCells x kCells grid (falling back to the global mean), so
// the prior keeps the depth map locally smooth instead of flat.
void cell_means(const MapCore& s, const Keyframe& host, double* means) {
  double sum[kCells * kCells] = {}, count[kCells * kCells] = {};
  double total = 0, n = 0;
  for (std::uint32_t i = 0; i < host.count; ++i) {
    const Point& p = host.points[i];
    if (p.status != PointStatus::immature) continue;
    const auto cx = static_cast<std::uint32_t>(p.u) * kCells / s.cfg.width;
    const auto cy = static_cast<std::uint32_t>(p.v) * kCells / s.cfg.height;
    sum[cy * kCells + cx] += p.idepth, count[cy * kCells + cx] += 1, total += p.idepth, n += 1;
  }
  for (std::uint32_t c = 0; c < kCells * kCells; ++c)
    means[c] = count[c] >= 3 ? sum[c] / count[c] : (n > 0 ? total / n : 1.0);
}

double mean_idepth(const Keyframe& host) {
  double sum = 0;
  std::uint32_t n = 0;
  for (std::uint32_t i = 0; i < host.count; ++i)
    if (host.points[i].status == PointStatus::immature) sum += host.points[i].idepth, ++n;
  return n ? sum / n : 1.0;
}

// Per point, in s.scratch (stride 8): coupling to the pose (6), H_rr, g_r. kFree: the brightness
// is free (a compile-time choice: the frames without it are most of the initialiser's time).
template <bool kFree>
InitSystem accumulate_with(MapCore& s, const CurrentFrame& f, std::uint32_t level, const Se3& M, const Brightness& br, bool with_jacobians) {
  InitSystem sys;
  Keyframe& host = init_host(s);
  const auto gain = kFree ? static_cast<float>(std::exp(br.a - host.a)) : 1.0f;
  const auto host_b = static_cast<float>(host.b), offset = static_cast<float>(br.b);
  const Level& cur = f.frame.level[level];
  const Level& ref = host.pyramid.level[level];
  const Scaled k = camera_at(s.cfg.camera, level), k0 = camera_at(s.cfg.camera, 0);
  const float scale = 1.0f / static_cast<float>(1u << level);
  const float hub = huber_threshold(s), c2 = gradient_weight_c(s) * gradient_weight_c(s);
  const float cutoff = kPattern * hub * hub * (level > 0 ? 24.0f : 12.0f);
  const Eigen::Matrix3f R = M.R.cast<float>();
  const Eigen::Vector3f t = M.t.cast<float>();
  double means[kCells * kCells];
  cell_means(s, host, means);
  for (std::uint32_t i = 0; i < host.count; ++i) {
    Point& p = host.points[i];
    const double mean = means[(static_cast<std::uint32_t>(p.v) * kCells / s.cfg.height) * kCells +
                              static_cast<std::uint32_t>(p.u) * kCells / s.cfg.width];
    float* row = s.scratch.data() + std::size_t{i} * 8;
    for (int q = 0; q < 8; ++q) row[q] = 0;
    if (p.status != PointStatus::immature) continue;
    const Eigen::Vector3f n((p.u - k0.cx) / k0.fx, (p.v - k0.cy) / k0.fy, 1.0f);
    const Eigen::Vector3f X = R * n + t * p.idepth;
    const double prior_r = p.idepth - mean;
    row[6] = static_cast<float>(kDepthPrior);
    row[7] = static_cast<float>(kDepthPrior * prior_r);
    sys.energy += kDepthPrior * prior_r * prior_r;
    // A point that leaves the view costs as much as an outlier, so no step gains by that.
    if (X.z() <= 1e-4f) {
      sys.energy += cutoff;
      continue;
    }
    const float x = X.x() / X.z(), y = X.y() / X.z(), iz = p.idepth / X.z();
    const float u = k.fx * x + k.cx, v = k.fy * y + k.cy;
    const float hu = (p.u + 0.5f) * scale - 0.5f, hv = (p.v + 0.5f) * scale - 0.5f;
    if (!inside(cur.value, u, v, 3.0f) || !inside(ref.value, hu, hv, 3.0f)) {
      sys.energy += cutoff;
      continue;
    }
    float energy = 0;
    float r[kPattern], w[kPattern], gx[kPattern], gy[kPattern], z[kPattern];
    for (std::uint32_t j = 0; j < kPattern; ++j) {
      const Sample c = bilinear_with_gradient(f.frame_texels[level], u + kPatternX[j], v + kPatternY[j]);
      const float reference = bilinear(ref.value, hu + kPatternX[j], hv + kPatternY[j]);
      if constexpr (kFree) {
        z[j] = reference - host_b;
        r[j] = c.value - (gain * z[j] + offset);
      } else {
        r[j] = c.value - reference;
      }
      const float hw = huber_weight(r[j], hub);
      w[j] = hw * c2 / (c2 + c.gx * c.gx + c.gy * c.gy);
      gx[j] = c.gx, gy[j] = c.gy;
      energy += hw * r[j] * r[j] * (2.0f - hw);
    }
    p.energy = energy;
    if (energy > cutoff) {
      sys.energy += cutoff;
      continue;
    }
    ++sys.inliers;
    sys.energy += energy;
    if (!with_jacobians) continue;
    const float du[6] = {k.fx * iz, 0, -k.fx * x * iz, -k.fx * x * y, k.fx * (1 + x * x), -k.fx * y};
    const float dv[6] = {0, k.fy * iz, -k.fy * y * iz, -k.fy * (1 + y * y), k.fy * x * y, k.fy * x};
    const float dud = k.fx * (t.x() - x * t.z()) / X.z(), dvd = k.fy * (t.y() - y * t.z()) / X.z();
    // Pixel j's pose row is J_j = gx_j du + gy_j dv and its inverse-depth derivative
    // gx_j dud + gy_j dvd, so the pattern's sums over w (gx, gy)^T (gx, gy) and w r (gx, gy) give
    // the point's pose block, gradient and coupling (the tracker's per-point 2x2 sums).
    float sxx = 0, sxy = 0, syy = 0, rx = 0, ry = 0;
    for (std::uint32_t j = 0; j < kPattern; ++j) {
      const float wx = w[j] * gx[j], wy = w[j] * gy[j];
      sxx += wx * gx[j], sxy += wx * gy[j], syy += wy * gy[j], rx += wx * r[j], ry += wy * r[j];
    }
    add_pose_block_upper(sys.H, du, dv, sxx, sxy, syy);
    for (int q = 0; q < 6; ++q) sys.g[q] += rx * du[q] + ry * dv[q];
    const float depth0 = sxx * dud + sxy * dvd, depth1 = sxy * dud + syy * dvd;
    for (int q = 0; q < 6; ++q) row[q] = du[q] * depth0 + dv[q] * depth1;
    row[6] += dud * depth0 + dvd * depth1;
    row[7] += dud * rx + dvd * ry;
    if constexpr (kFree)
      for (std::uint32_t j = 0; j < kPattern; ++j) {
        // d r / d a = -gain z, d r / d b = -1.
        const double ja = -double{gain} * z[j], wj = w[j];
        sys.h_gg += wj * ja * ja, sys.h_go -= wj * ja, sys.h_oo += wj;
        sys.g_g += wj * ja * r[j], sys.g_o -= wj * r[j];
      }
  }
  sys.H = sys.H.selfadjointView<Eigen::Upper>();
  return sys;
}

InitSystem accumulate(MapCore& s, const CurrentFrame& f, std::uint32_t level, const Se3& M, const Brightness& br, bool with_jacobians) {
  return br.free ? accumulate_with<true>(s, f, level, M, br, with_jacobians)
                            : accumulate_with<false>(s, f, level, M, br, with_jacobians);
}

struct Solved {
  double energy = 0;  // finest level, after the last accepted step
  std::uint32_t inliers = 0;
};

// The brightness step of a free brightness (none otherwise), damped as the pose's.
Brightness brightness_step(const InitSystem& sys, const Brightness& br, double lambda) {
  if (!br.free) return br;
  Eigen::Matrix2d H;
  H << sys.h_gg * (1 + lambda) + 1e-6, sys.h_go, sys.h_go, sys.h_oo * (1 + lambda) + 1e-6;
  const Eigen::Vector2d d = -H.ldlt().solve(Eigen::Vector2d(sys.g_g, sys.g_o));
  if (!d.allFinite()) return br;
  return {br.a + d[0], br.b + d[1], true};
}

// Levenberg-Marquardt, coarse to fine, from M (and the brightness, when it is free). At each
// iteration `propose(sys, lambda, M, M_new)` writes the trial pose, and may move the host's
// inverse depths with it; it returns the step's norm, or a negative number for a step that is not
// finite. A rejected step calls `undo()`, which puts the depths back and returns whether it did
// (the system is then accumulated again: its per-point rows hold the trial's).
template <class Propose, class Undo>
Solved coarse_to_fine(MapCore& s, const CurrentFrame& f, Se3& M, Brightness& br, Propose propose, Undo undo) {
  Solved out;
  for (int level = static_cast<int>(f.frame.levels) - 1; level >= 0; --level) {
    const auto l = static_cast<std::uint32_t>(level);
    double lambda = 0.1;
    InitSystem sys = accumulate(s, f, l, M, br, true);
    for (int it = 0; it < 6; ++it) {
      Se3 M_new;
      const double step = propose(sys, lambda, M, M_new);
      if (!(step >= 0)) break;
      const Brightness br_new = brightness_step(sys, br, lambda);
      InitSystem next = accumulate(s, f, l, M_new, br_new, true);
      if (next.energy < sys.energy) {
        M = M_new, br = br_new, sys = next;
        lambda = std::max(lambda * 0.5, 1e-4);
        if (step < 1e-6) break;
      } else {
        if (undo()) sys = accumulate(s, f, l, M, br, true);
        lambda *= 4;
        if (lambda > 1e3) break;
      }
    }
    if (level == 0) out.energy = sys.energy, out.inliers = sys.inliers;
  }
  return out;
}

// Joint pose + inverse-depth refinement, coarse to fine, from M and the host's current depths
// (and the brightness, when it is free).
Solved refine(MapCore& s, const CurrentFrame& f, Se3& M, Brightness& br) {
  Keyframe& host = init_host(s);
  const auto propose = [&](const InitSystem& sys, double lambda, const Se3& from, Se3& to) {
    // Schur complement: eliminate every inverse depth (diagonal block) onto the pose.
    Mat6 Hs = sys.H;
    Vec6 gs = sys.g;
    for (std::uint32_t i = 0; i < host.count; ++i) {
      const float* row = s.scratch.data() + std::size_t{i} * 8;
      if (host.points[i].status != PointStatus::immature || row[6] <= 0) continue;
      const double hrr = row[6] * (1 + lambda);
      Vec6 hpr;
      for (int q = 0; q < 6; ++q) hpr[q] = row[q];
      Hs -= hpr * hpr.transpose() / hrr;
      gs -= hpr * (row[7] / hrr);
    }
    for (int q = 0; q < 6; ++q) Hs(q, q) += lambda * sys.H(q, q) + 1e-6;
    const Vec6 dx = -Hs.ldlt().solve(gs);
    if (!dx.allFinite()) return -1.0;
    // Back-substitute the inverse depths into the point array itself, the previous ones kept in
    // idepth_min (free while the points are immature) for undo.
    to = Se3::exp(dx) * from;
    for (std::uint32_t i = 0; i < host.count; ++i) {
      Point& p = host.points[i];
      const float* row = s.scratch.data() + std::size_t{i} * 8;
      if (p.status != PointStatus::immature || row[6] <= 0) continue;
      double hpr_dx = 0;
      for (int q = 0; q < 6; ++q) hpr_dx += row[q] * dx[q];
      const double dr = -(row[7] + hpr_dx) / (row[6] * (1 + lambda));
      p.idepth_min = p.idepth;  // backup
      p.idepth = static_cast<float>(std::min(std::max(p.idepth + dr, 1e-3), 20.0));
    }
    return dx.norm();
  };
  const auto undo = [&] {
    for (std::uint32_t i = 0; i < host.count; ++i)
      if (host.points[i].status == PointStatus::immature) host.points[i].idepth = host.points[i].idepth_min;
    return true;
  };
  return coarse_to_fine(s, f, M, br, propose, undo);
}

// The rotation that explains the frame best with no translation (the depths then do not
// matter), coarse to fine from M's rotation and the current depths (whose prior terms it leaves
// as they are, so its energy compares with refine()'s).
Solved refine_rotation(MapCore& s, const CurrentFrame& f, Se3& M, Brightness& br) {
  M.t.setZero();
  const auto propose = [](const InitSystem& sys, double lambda, const Se3& from, Se3& to) {
    Eigen::Matrix3d H = sys.H.bottomRightCorner<3, 3>();
    for (int q = 0; q < 3; ++q) H(q, q) += lambda * H(q, q) + 1e-6;
    const Vec3 dw = -H.ldlt().solve(sys.g.tail<3>());
    if (!dw.allFinite()) return -1.0;
    Vec6 xi;
    xi << 0, 0, 0, dw;
    to = Se3::exp(xi) * from;
    return dw.norm();
  };
  return coarse_to_fine(s, f, M, br, propose, [] { return false; });
}

// Two sets of inverse depths (the warm solve's, then the fresh solve's) while another solve runs:
// BA scratch past the rows that accumulate() writes (odometry.cpp sizes MapCore::scratch for all three).
float* warm_depths(MapCore& s) { return s.scratch.subspan(std::size_t{s.cfg.points_per_keyframe} * 8).data(); }
float* fresh_depths(MapCore& s) { return s.scratch.subspan(std::size_t{s.cfg.points_per_keyframe} * 9).data(); }
void save_depths(const Keyframe& host, float* to) {
  for (std::uint32_t i = 0; i < host.count; ++i) to[i] = host.points[i].idepth;
}
void restore_depths(Keyframe& host, const float* from) {
  for (std::uint32_t i = 0; i < host.count; ++i) host.points[i].idepth = from[i];
}

// Under a rotation about the camera's centre the joint solve explains the frame's motion with a
// translation and depths fitted to it (across a narrow field of view a turn moves the image as a
// sideways step does), and the basins never agree: the initialisation waited out kBasinWaitFrames
// while the host turned out of the view (a 9 Hz pan at 30 deg/s), and its map then held that
// translation. When a rotation alone fits the frame about as well, M and the brightness become the
// rotation's, with the point energies of that fit (the outlier test at the end); otherwise the
// point energies are put back as they were. The ratio separates pans (below it) from the study's
// street sequences with a translation (well above it); scripts/study/pans.sh exercises it.
constexpr double kRotationEnergyRatio = 1.05;
bool explained_by_rotation(MapCore& s, const CurrentFrame& f, Se3& M, Brightness& br) {
  Keyframe& host = init_host(s);
  // A point outside the view keeps the energy of the last fit that saw it: keep the joint
  // solve's, in scratch that is free outside solve_afresh_if_better.
  float* energies = fresh_depths(s);
  for (std::uint32_t i = 0; i < host.count; ++i) energies[i] = host.points[i].energy;
  const double joint = accumulate(s, f, 0, M, br, false).energy;
  // The translation's flow at the mean inverse depth (1) as a turn: a start in the rotation's basin.
  Se3 M_rot{so3_exp(Vec3(-M.t.y(), M.t.x(), 0.0)) * M.R, Vec3::Zero()};
  Brightness br_rot = br;
  const Solved rotation = refine_rotation(s, f, M_rot, br_rot);
  if (rotation.energy > kRotationEnergyRatio * joint) {
    for (std::uint32_t i = 0; i < host.count; ++i) host.points[i].energy = energies[i];
    return false;
  }
  accumulate(s, f, 0, M_rot, br_rot, false);
  M = M_rot, br = br_rot;
  return true;
}

// Refines a solve kSolvePasses - 1 more times: one coarse-to-fine pass leaves the depths short of
// converged, and the comparison below is only fair between solves that went equally far.
constexpr int kSolvePasses = 3;
Solved converge(MapCore& s, const CurrentFrame& f, Se3& M, Brightness& br, Solved solved) {
  for (int pass = 1; pass < kSolvePasses; ++pass) solved = refine(s, f, M, br);
  return solved;
}

Solved solve_from_flat_depths(MapCore& s, const CurrentFrame& f, Se3& M, Brightness& br) {
  Keyframe& host = init_host(s);
  for (std::uint32_t i = 0; i < host.count; ++i) host.points[i].idepth = 1.0f;
  return refine(s, f, M, br);
}

// Two solves found the same basin when their camera centres (host coordinates) point the same
// way: the wrong basins seen were 30-75 degrees off the true direction.
constexpr double kSameBasinCos = 0.985;  // 10 degrees
bool same_basin(const Se3& a, const Se3& b) {
  const Vec3 ca = -(a.R.transpose() * a.t), cb = -(b.R.transpose() * b.t);
  const double na = ca.norm(), nb = cb.norm();
  return na > 0 && nb > 0 && ca.dot(cb) >= kSameBasinCos * na * nb;
}

// The warm start (last solution, constant velocity) keeps whatever basin the first frames chose,
// when the translation was not observable yet: with forward motion and hand shake it often
// settles on a lateral translation whose flow a wrong rotation cancels, with depths fitted to it
// (the translation direction tens of degrees off, and a map that then keeps turning).
// A solve from scratch (no motion, flat depths) on the same frame finds the true basin once the
// baseline is there. Fitting better than the warm solve, it replaces it. But fitting worse does
// not make it wrong: the warm solve's depths were refined over every earlier frame, which can
// make a wrong warm basin fit better than a right fresh one. So when the two disagree on the basin,
// both are solved again from flat depths to the same convergence, and the fresh basin wins if
// it fits better by kBasinMargin. The margin keeps a planar scene, where both basins explain the
// frames (the two-fold ambiguity of a plane), on the basin it started in (test_vo_board's wall).
constexpr double kBasinMargin = 0.01;
// The comparison runs only on a frame the warm solve fits well (4 in 5 of the host's points
// inliers): on a frame that matches poorly (heavy aliasing; the IR modes after an exposure change
// at a wrong tau, before the brightness was freed there) both energies are mostly outliers and the
// choice is noise (it made the board tests' wall differ between architectures).
bool fits_well(const Solved& solved, const Keyframe& host) { return solved.inliers * 5 >= host.count * 4; }
// Returns whether the two solves ended in different basins.
// The brightness is the frame's whatever the basin: the fresh solves start from the warm one's.
bool solve_afresh_if_better(MapCore& s, const CurrentFrame& f, Se3& M, Brightness& br, Solved& solved) {
  Keyframe& host = init_host(s);
  float* warm = warm_depths(s);
  float* fresh_solution = fresh_depths(s);
  save_depths(host, warm);
  Se3 M_fresh;
  Brightness br_fresh = br;
  Solved fresh = solve_from_flat_depths(s, f, M_fresh, br_fresh);
  bool take_fresh = fresh.energy < solved.energy;
  const bool basins_differ = !same_basin(M, M_fresh);
  if (!take_fresh && basins_differ && fits_well(solved, host)) {
    fresh = converge(s, f, M_fresh, br_fresh, fresh);
    save_depths(host, fresh_solution);
    Se3 M_warm_basin = M;
    Brightness br_warm_basin = br;
    const Solved warm_basin =
        converge(s, f, M_warm_basin, br_warm_basin, solve_from_flat_depths(s, f, M_warm_basin, br_warm_basin));
    take_fresh = fresh.energy < (1.0 - kBasinMargin) * warm_basin.energy;
    if (take_fresh) restore_depths(host, fresh_solution);
  }
  if (take_fresh) {
    M = M_fresh, br = br_fresh, solved = fresh;
  } else {
    restore_depths(host, warm);
  }
  accumulate(s, f, 0, M, br, false);  // the chosen solution's point energies (outlier test at the end)
  return basins_differ;
}

// While the fresh and the warm solve still disagree on the basin, the initialisation goes on, up
// to kBasinWaitFrames: with more baseline the true basin comes to fit better (the figures:
// docs/odometry-study.md, "Accuracy").
constexpr std::uint32_t kBasinWaitFrames = 30;
bool keep_waiting_for_the_basin(const InitialiserState& init, bool basins_differ) {
  return basins_differ && init.frames < kBasinWaitFrames;
}

// The first keyframe and the frames solved before `completing`, as world poses (init.poses;
// completing < kMaxInitFrames leaves a slot for the keyframe). Each keeps the rotation its step
// solved, which the frames show from the start; its camera centre lies on the way to the
// completing frame's in proportion to its time, since the translation was not yet observable when
// it was solved (that is what the initialisation waits for). Only frames solved after the warm and
// the fresh solve last disagreed on the basin: before, a wrong basin's rotation (the one that
// cancels its lateral translation's flow) may stand in a frame's pose.
void publish_initialisation_poses(InitialiserState& init, const Keyframe& host, std::uint32_t completing) {
  const SolvedFrame& last = init.solved[completing];
  const Vec3 final_centre = -(last.M.R.transpose() * last.M.t);
  const double span_s = last.t_s - host.t_s;
  init.poses[0] = {host.t_s, host.T_cw.inverse(), tie_to(host, host.T_cw.inverse())};
  std::uint32_t n = 1;
  for (std::uint32_t i = init.agreed_since; i < completing && span_s > 0; ++i) {
    const SolvedFrame& frame = init.solved[i];
    const Vec3 centre = final_centre * ((frame.t_s - host.t_s) / span_s);
    const Se3 M{frame.M.R, -(frame.M.R * centre)};
    const Se3 T_wc = (M * host.T_cw).inverse();
    init.poses[n++] = {frame.t_s, T_wc, tie_to(host, T_wc)};
  }
  init.pose_count = n;
  init.completed_now = true;
}

}  // namespace

double baseline_flow_needed(const VoConfig& cfg) { return kInitFlow * (cfg.width + cfg.height); }

void start_initialisation(InitialiserState& init, Keyframe& host) {
  for (std::uint32_t i = 0; i < host.count; ++i) host.points[i].idepth = 1.0f;
  init.initialised = false;
  init.frames = 0;
  init.map_without_baseline = false;
  init.pose_count = 0;
  init.agreed_since = 0;
}

void follow_map_baseline(InitialiserState& init, const MotionModel& motion, const VoConfig& cfg) {
  if (!init.map_without_baseline) return;
  const Se3 M = motion.T_cw * init.map_origin.inverse();
  if (cfg.camera.fx * M.t.norm() >= baseline_flow_needed(cfg)) init.map_without_baseline = false;
}

bool initialise_step(MapCore& s, InitialiserState& init, const CurrentFrame& f, MotionModel& motion,
                     BrightnessTrack& brightness, TrackingReference& ref) {
  Keyframe& host = init_host(s);
  Se3 M = motion_step(motion, f.t_s) * (motion.T_cw * host.T_cw.inverse());  // constant-velocity guess
  // Where the frame has the host's level it has the host's brightness.
  const bool level_unknown = brightness_free(s, f);
  Brightness br = level_unknown ? Brightness{brightness.a, brightness.b, true} : Brightness{host.a, host.b, false};
  Solved solved = refine(s, f, M, br);
  const bool basins_differ = init.frames > 0 && solve_afresh_if_better(s, f, M, br, solved);
  const std::uint32_t finest_inliers = solved.inliers;
  // Keep the mean inverse depth at 1: the scale of monocular odometry is free.
  const double mean = mean_idepth(host);
  if (mean > 1e-6) {
    for (std::uint32_t i = 0; i < host.count; ++i) host.points[i].idepth = static_cast<float>(host.points[i].idepth / mean);
    M.t *= mean;
  }
  // Diverged, or the first keyframe no longer matches anything, or it has too few points to be
  // tracked from (a view of a blank wall): restart from the next frame.
  if (!M.t.allFinite() || !M.R.allFinite() || M.t.norm() > 10.0 || finest_inliers * 5 < host.count ||
      host.count < kMinInitPoints) {
    init.frames = kGiveUp;
    return false;
  }
  ++init.frames;
  if (init.frames <= kMaxInitFrames) init.solved[init.frames - 1] = {f.t_s, M};  // relative, until it completes
  if (basins_differ) init.agreed_since = init.frames;
  const double baseline_flow = s.cfg.camera.fx * M.t.norm();
  // The first keyframe's patterns must still match at the end: a slow camera (9 Hz) moves as far
  // in 10 frames as a 60 Hz one in 67, so it may stop at the time 10 frames take at 30 Hz.
  const bool long_enough = init.frames >= kMinInitFrames ||
                           (init.frames >= 2 && f.t_s - host.t_s >= kMinInitSeconds - 1e-6);
  const bool ready = long_enough && baseline_flow >= baseline_flow_needed(s.cfg);
  const bool rotation = ready && explained_by_rotation(s, f, M, br);
  const Se3 previous = motion.T_cw;
  motion.T_cw = (M * host.T_cw).orthonormalised();
  brightness.a = br.a, brightness.b = br.b;
  brightness.level_unknown = level_unknown;
  record_motion(motion, previous, f.t_s);
  if (!ready) return false;
  if (rotation) {
    // The camera has turned about its centre since the host: the map starts flat, the motion
    // model turns at the average rate, and there is no basin to wait for.
    for (std::uint32_t i = 0; i < host.count; ++i) host.points[i].idepth = 1.0f;
    const double frames = static_cast<double>(init.frames);
    motion.step = Se3::exp(M.log() / frames).orthonormalised();
    motion.step_dt_s = (f.t_s - host.t_s) / frames;
    init.map_without_baseline = true;
    init.map_origin = host.T_cw;
  } else if (keep_waiting_for_the_basin(init, basins_differ)) {
    return false;
  }
  // Done: the points that fit become the map.
  const float hub = huber_threshold(s);
  for (std::uint32_t i = 0; i < host.count; ++i) {
    Point& p = host.points[i];
    if (p.status != PointStatus::immature) continue;
    if (p.energy > kPattern * hub * hub * 6.0f) {
      p.status = PointStatus::empty;
      continue;
    }
    p.status = PointStatus::active;
    p.idepth_min = p.idepth * 0.5f, p.idepth_max = p.idepth * 2.0f;
  }
  publish_initialisation_poses(init, host, init.frames - 1);
  init.initialised = true;
  ref.dirty = true;
  return true;
}

}  // namespace bolo::vo

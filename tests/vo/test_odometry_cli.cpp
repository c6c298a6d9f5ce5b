// bolo odometry and bolo evaluate end to end, in-process: a short simulated street/drive
// sequence (160x120, 60 Hz, tau 12 ms, noise 3) through every photometric mode, the outputs'
// formats, an ATE bound for the no-carry-over case, and the refusals of docs/errors.md section 12.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <sstream>

#include <unistd.h>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "../cli/cli_test_support.hpp"
#include "../hal/flirone_frames.hpp"
#include "bolo/odometry/run_odometry.hpp"
#include "bolo/odometry/stats_csv.hpp"
#include "bolo/odometry/tum.hpp"
#include "bolo/recording/recording.hpp"
#include "bolo/vo/config.hpp"

using namespace bolo;
using namespace bolo::test;

namespace {

// One simulated sequence per tau and length (~1 s to render, ~5 s under ASan), rendered once per
// build of this binary and shared by its test processes through BOLO_TEST_CACHE: the folder's name
// carries the binary's size and time, so a rebuilt renderer renders anew. A process renders into a
// folder of its own and renames it into place; when another was first, its copy is used.
const fs::path& sequence(const char* name, const char* tau, const char* frames = "36") {
  static std::map<std::string, fs::path> made;
  const std::string key = std::string(name) + tau + "-" + frames;
  if (!made.count(key)) {
    const fs::path exe = fs::read_symlink("/proc/self/exe");
    const fs::path dir = fs::path(BOLO_TEST_CACHE) /
                         (key + "-" + std::to_string(fs::file_size(exe)) + "-" +
                          std::to_string(static_cast<std::uint64_t>(fs::last_write_time(exe).time_since_epoch().count())));
    if (!fs::is_directory(dir)) {
      const fs::path mine = dir.string() + ".part-" + std::to_string(::getpid());
      const CliResult r = run_bolo({"simulate", mine.string(), "--scene", "street", "--trajectory", "drive", "--fps",
                                    "60", "--frames", frames, "--size", "160x120", "--tau", tau, "--noise", "3",
                                    "--seed", "1"});
      INFO(r.err);
      REQUIRE(r.code == 0);
      std::error_code ec;
      fs::rename(mine, dir, ec);
      if (ec) fs::remove_all(mine);
      REQUIRE(fs::is_directory(dir));
    }
    made[key] = dir;
  }
  return made[key];
}

// A street sequence at `fps` (default 60 Hz), 160x120, noise 3, rendered over each pixel's area (3 x 3 rays),
// with one effect of the simulator's catalogue when `effect` is given.
fs::path street_ss3(const fs::path& seq, const char* trajectory, const char* frames, const char* tau,
                    const char* seed, const char* effect = nullptr, const char* fps = "60") {
  std::vector<std::string> args = {"simulate", seq.string(), "--scene", "street", "--trajectory", trajectory,
                                   "--fps", fps, "--frames", frames, "--size", "160x120", "--tau", tau,
                                   "--noise", "3", "--seed", seed, "--supersample", "3"};
  if (effect) args.insert(args.end(), {"--effect", effect});
  const CliResult r = run_bolo(args);
  INFO(r.err);
  REQUIRE(r.code == 0);
  return seq;
}

// A new recording folder `out` with some of `seq`'s files (the rest left out or written by the
// caller).
fs::path copy_files(const fs::path& seq, const fs::path& out, std::initializer_list<const char*> files) {
  fs::create_directories(out);
  for (const char* f : files) fs::copy_file(seq / f, out / f);
  return out;
}

nlohmann::json evaluate(const fs::path& run) {
  const CliResult r = run_bolo({"evaluate", run.string(), "--json", (run / "eval.json").string()});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(r.out.find("ATE rmse") != std::string::npos);
  std::ifstream in(run / "eval.json");
  return nlohmann::json::parse(in);
}

// bolo odometry over `seq` into `run` with `options`; the test stops unless it succeeds.
void odometry(const fs::path& seq, const fs::path& run, const std::vector<std::string>& options) {
  std::vector<std::string> args = {"odometry", seq.string(), "--out", run.string()};
  args.insert(args.end(), options.begin(), options.end());
  const CliResult r = run_bolo(args);
  INFO(args.back() << ": " << r.err);
  REQUIRE(r.code == 0);
}

nlohmann::json summary_of(const fs::path& run) {
  std::ifstream in(run / "summary.json");
  return nlohmann::json::parse(in);
}

// bolo odometry over `seq` in `mode` into `run`, then bolo evaluate: the evaluation.
nlohmann::json odometry_evaluated(const fs::path& seq, const fs::path& run, const char* mode) {
  odometry(seq, run, {"--photometric", mode});
  return evaluate(run);
}

// Every photometric mode over `seq` into `out`/MODE, each evaluation handed to `check`.
template <typename Check>
void each_mode_evaluated(const fs::path& seq, const fs::path& out, Check check) {
  for (const char* mode : {"none", "affine", "ir", "ir-loop"}) {
    const nlohmann::json e = odometry_evaluated(seq, out / mode, mode);
    INFO(mode << ": " << e.dump(2));
    check(std::string(mode), e);
  }
}

}  // namespace

TEST_CASE("odometry tracks a short drive and writes every output", "[vo][cli]") {
  const fs::path& seq = sequence("drive", "0.0002");
  TempDir out;
  const fs::path run = out / "vo";
  odometry(seq, run, {"--photometric", "none"});
  for (const char* file : {"trajectory.tum", "stats.csv", "points.ply", "trajectory.svg", "summary.json"})
    CHECK(fs::exists(run / file));
  const auto poses = odo::read_tum(run / "trajectory.tum");
  CHECK(poses.size() >= 20);  // initialisation takes ~12 frames of 36
  const nlohmann::json e = evaluate(run);
  INFO(e.dump(2));
  // 36 frames, ~6 m of path: the aligned trajectory stays within 10 % of the path length.
  CHECK(e["ate_relative"].get<double>() < 0.10);
  CHECK(e["keyframes"].get<int>() >= 2);
  CHECK(e["tracked_points_total"].get<int>() > 1000);
}

TEST_CASE("odometry writes the trajectory refined on the keyframes' last poses", "[vo][cli]") {
  // trajectory-refined.tum: every pose of trajectory.tum carried on its keyframe's pose as the
  // window BA last left it (keyframes.tum), as DSO's and ORB-SLAM's end-of-run trajectories are.
  const fs::path& seq = sequence("drive", "0.0002");
  TempDir out;
  const fs::path run = out / "vo";
  odometry(seq, run, {"--photometric", "none"});
  const auto online = odo::read_tum(run / "trajectory.tum");
  const auto refined = odo::read_tum(run / "trajectory-refined.tum");
  const auto keyframes = odo::read_tum(run / "keyframes.tum");
  const nlohmann::json summary = summary_of(run);
  INFO(summary.dump(2));
  REQUIRE(refined.size() == online.size());
  CHECK(summary["refined_poses"].get<std::size_t>() == online.size());
  CHECK(keyframes.size() == summary["keyframes"].get<std::size_t>() + 1);  // the map's first as well
  // A keyframe's own frame lies on its last pose; the bundle adjustments after a frame was tracked
  // moved its keyframe, so some refined pose differs from the tracked one.
  std::size_t on_keyframe = 0;
  double largest_move = 0;
  for (std::size_t k = 0; k < online.size(); ++k) {
    CHECK(refined[k].t == online[k].t);
    largest_move = std::max(largest_move, (refined[k].T_wc.t - online[k].T_wc.t).norm());
    for (const auto& kf : keyframes)
      if (kf.t == refined[k].t) {
        ++on_keyframe;
        CHECK((kf.T_wc.t - refined[k].T_wc.t).norm() < 1e-6);
      }
  }
  CHECK(on_keyframe == keyframes.size());
  CHECK(largest_move > 1e-4);
  // bolo evaluate --refined scores it.
  const CliResult r = run_bolo({"evaluate", run.string(), "--refined", "--json", (run / "refined.json").string()});
  INFO(r.err);
  REQUIRE(r.code == 0);
  std::ifstream in(run / "refined.json");
  CHECK(nlohmann::json::parse(in)["ate_relative"].get<double>() < 0.10);
  // Without the file, --refined is refused by its name.
  fs::remove(run / "trajectory-refined.tum");
  const CliResult missing = run_bolo({"evaluate", run.string(), "--refined"});
  CHECK(missing.code != 0);
  CHECK(missing.err.find("trajectory-refined.tum") != std::string::npos);
}

namespace {

// The median number of frames between consecutive keyframes of a run (stats.csv's keyframe column).
int median_keyframe_spacing(const fs::path& run) {
  std::vector<int> keyframe_frames;
  for (const odo::StatsRow& row : odo::read_stats_csv(run / "stats.csv"))
    if (row.keyframe) keyframe_frames.push_back(static_cast<int>(row.index));
  REQUIRE(keyframe_frames.size() >= 10);
  std::vector<int> spacing;
  for (std::size_t k = 1; k < keyframe_frames.size(); ++k) spacing.push_back(keyframe_frames[k] - keyframe_frames[k - 1]);
  std::nth_element(spacing.begin(), spacing.begin() + spacing.size() / 2, spacing.end());
  return spacing[spacing.size() / 2];
}

}  // namespace

TEST_CASE("odometry: --keyframe-parallax quantile spaces keyframes by the parallax most points see", "[vo][cli]") {
  // Ahead of a car at 60 Hz the road below the bumper sweeps tens of pixels in a few frames: the
  // translation flow's rms makes a keyframe every ~6 frames on this 4-s drive, three quarters of
  // the points' flow every ~10 (docs/odometry-study.md, "Where the accuracy goes").
  const fs::path& seq = sequence("drive", "0.012", "240");
  TempDir out;
  odometry(seq, out / "rms", {"--photometric", "none"});
  odometry(seq, out / "quantile", {"--photometric", "none", "--keyframe-parallax", "quantile"});
  CHECK(summary_of(out / "rms")["keyframe_parallax"] == "rms");
  CHECK(summary_of(out / "quantile")["keyframe_parallax"] == "quantile");
  const int rms = median_keyframe_spacing(out / "rms"), quantile = median_keyframe_spacing(out / "quantile");
  INFO("median keyframe spacing: rms " << rms << ", quantile " << quantile);
  CHECK(quantile >= 8);
  CHECK(quantile >= rms + 2);
  const nlohmann::json e = evaluate(out / "quantile");
  INFO(e.dump(2));
  CHECK(e["ate_relative"].get<double>() < 0.005);
  CHECK(e["coverage"].get<double>() > 0.9);
  const CliResult bad = run_bolo({"odometry", seq.string(), "--out", (out / "bad").string(), "--keyframe-parallax", "p90"});
  CHECK(bad.code == 2);
  CHECK(bad.err.find("--keyframe-parallax") != std::string::npos);
  CHECK(!fs::exists(out / "bad"));
}

TEST_CASE("odometry poses the frames its initialisation took once it completes", "[vo][cli]") {
  // The initialisation takes ~12 frames before it has the baseline; once it completes they are
  // posed (their rotations, the camera centre on the way to the completing frame's), unless only
  // the poses given as each frame came are asked for.
  const fs::path& seq = sequence("drive", "0.012");
  TempDir out;
  odometry(seq, out / "all", {"--photometric", "ir"});
  odometry(seq, out / "online", {"--photometric", "ir", "--online-poses-only"});
  const nlohmann::json all = evaluate(out / "all"), online = evaluate(out / "online");
  INFO("all: " << all.dump(2) << "\nonline: " << online.dump(2));
  CHECK(summary_of(out / "all")["posed_at_initialisation"].get<int>() >= 8);
  CHECK(summary_of(out / "online")["posed_at_initialisation"] == 0);
  // Every frame but the first, whose carry-over is unknown in the ir modes.
  CHECK(all["posed"].get<int>() >= all["frames"].get<int>() - 1);
  CHECK(all["posed"].get<int>() - online["posed"].get<int>() == summary_of(out / "all")["posed_at_initialisation"].get<int>());
  CHECK(odo::read_tum(out / "all" / "trajectory.tum").front().t < 1.5 / 60);
  // The added poses hold the trajectory's accuracy.
  CHECK(all["ate_relative"].get<double>() < 0.01);
  CHECK(all["ate_relative"].get<double>() < 1.5 * online["ate_relative"].get<double>());
}

TEST_CASE("odometry --poses-at-read carries each ir pose forward over its corrected image's delay", "[vo][cli]") {
  // The heating weights' centroid: half a short exposure, 6.1 ms before the read of a whole 60 Hz
  // period at tau 10 ms (docs/odometry-study.md, "A continuous lag").
  CHECK(odo::corrected_image_delay_s(1e-6, 0.010) == Approx(0.5e-6).epsilon(1e-3));
  CHECK(odo::corrected_image_delay_s(1.0 / 60, 0.010) == Approx(0.0061191).epsilon(1e-4));
  const fs::path& seq = sequence("drive", "0.010");
  TempDir out;
  odometry(seq, out / "plain", {"--photometric", "ir"});
  odometry(seq, out / "read", {"--photometric", "ir", "--poses-at-read"});
  const auto plain = odo::read_tum(out / "plain" / "trajectory.tum");
  const auto read = odo::read_tum(out / "read" / "trajectory.tum");
  REQUIRE(plain.size() == read.size());
  REQUIRE(plain.size() >= 20);
  // Each pose but the map's first moves along the camera's last step by delay / period of it
  // (exposure half the period, tau near 10 ms: about 3.6 / 16.7 = 0.2).
  CHECK((read[0].T_wc.t - plain[0].T_wc.t).norm() == 0.0);
  std::vector<double> shares;
  for (std::size_t k = 1; k < plain.size(); ++k) {
    const vo::Vec3 step = plain[k].T_wc.t - plain[k - 1].T_wc.t, moved = read[k].T_wc.t - plain[k].T_wc.t;
    if (plain[k].t - plain[k - 1].t > 0.02 || step.norm() == 0) continue;
    CHECK(moved.dot(step) > 0.98 * moved.norm() * step.norm());
    shares.push_back(moved.norm() / step.norm());
  }
  REQUIRE(shares.size() >= 15);
  std::sort(shares.begin(), shares.end());
  CHECK(shares[shares.size() / 2] > 0.15);
  CHECK(shares[shares.size() / 2] < 0.30);
  const CliResult r = run_bolo({"odometry", seq.string(), "--out", (out / "bad").string(), "--photometric", "none",
                                "--poses-at-read"});
  CHECK(r.code == 2);
  CHECK(contains(r.err, "--poses-at-read: the ir modes only"));
}

TEST_CASE("odometry takes the recording as file:REC; a spec no backend knows is refused by name", "[vo][cli]") {
  const fs::path& seq = sequence("drive", "0.0002");
  TempDir out;
  odometry(fs::path("file:" + seq.string()), out / "vo", {"--photometric", "none"});
  CHECK(fs::exists(out / "vo" / "trajectory.tum"));
  CliResult r = run_bolo({"odometry", "nosuch:thing", "--out", (out / "bad").string()});
  CHECK(r.code == 2);
  CHECK(contains(r.err, "nosuch:thing: unknown device (expected "));
  r = run_bolo({"odometry", "v4l2:/dev/video0", "--out", (out / "bad").string()});
  CHECK(r.code == 2);
  CHECK(contains(r.err, "--frames: required for a live camera (v4l2:/dev/video0)"));
  CHECK_FALSE(fs::exists(out / "bad"));
}

TEST_CASE("odometry runs over a live source (a FLIR ONE transfer log) and writes its trajectory", "[vo][cli]") {
  TempDir out;
  write_flirone_log(out / "log", 12, {6});
  const std::string spec = "flirone-log:" + (out / "log").string();
  const CliResult r = run_bolo({"odometry", spec, "--out", (out / "vo").string(), "--hfov", "50", "--no-progress"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(contains(r.out, "odometry: wrote " + (out / "vo").string() + ": 11 frames"));
  CHECK(contains(r.out, "odometry: live source " + spec));
  CHECK(fs::exists(out / "vo" / "trajectory.tum"));
  CHECK(read_text(out / "vo" / "trajectory.tum").rfind("# bolo odometry: none", 0) == 0);
  const nlohmann::json s = summary_of(out / "vo");
  CHECK(s["frames"] == 11);
  CHECK(s["source"]["spec"] == spec);
  CHECK(s["source"]["skipped"] == 1);
  CHECK(contains(s["source"]["faults"].get<std::string>(), "corrupt 1"));
  // --frames bounds what is read; without --hfov there are no intrinsics.
  odometry(fs::path(spec), out / "five", {"--hfov", "50", "--frames", "5"});
  CHECK(summary_of(out / "five")["frames"] == 5);
  const CliResult no_hfov = run_bolo({"odometry", spec, "--out", (out / "no-hfov").string()});
  CHECK(no_hfov.code == 2);
  CHECK(contains(no_hfov.err, spec + ": a live source has no camera.json (give --hfov DEG)"));
  CHECK_FALSE(fs::exists(out / "no-hfov"));
}

TEST_CASE("odometry runs over the real FLIR ONE transfer log as a live source", "[vo][cli][real]") {
  const fs::path log = shared_folder("usb/flirone-pro", "1.txt");
  if (log.empty()) return;
  TempDir out;
  odometry(fs::path("flirone-log:" + log.string()), out / "vo", {"--hfov", "50", "--photometric", "ir"});
  CHECK(fs::exists(out / "vo" / "trajectory.tum"));
  CHECK(summary_of(out / "vo")["frames"] == 20);
}

TEST_CASE("odometry: --max-keyframes sets the sliding window", "[vo][cli][long]") {
  const fs::path& seq = sequence("drive", "0.0002");
  TempDir out;
  const fs::path run = out / "vo", full = out / "vo8";
  odometry(seq, run, {"--max-keyframes", "4"});
  odometry(seq, full, {});
  const nlohmann::json four = summary_of(run), eight = summary_of(full);
  CHECK(four["max_keyframes"].get<int>() == 4);
  CHECK(eight["max_keyframes"].get<int>() == 8);
  CHECK(eight["retirement"].get<std::string>() == "spread");  // the default (keyframe_retirement.cpp)
  // The VO is configured with it: half the keyframes' pyramids and points, a smaller arena.
  CHECK(four["arena_bytes"].get<double>() < 0.75 * eight["arena_bytes"].get<double>());
  const nlohmann::json e = evaluate(run);
  CHECK(e["ate_relative"].get<double>() < 0.10);
}

TEST_CASE("odometry: --points-per-keyframe sets the keyframes' point count", "[vo][cli][long]") {
  const fs::path& seq = sequence("drive", "0.0002");
  TempDir out;
  odometry(seq, out / "few", {"--points-per-keyframe", "150"});
  odometry(seq, out / "default", {});
  const nlohmann::json few = summary_of(out / "few"), standard = summary_of(out / "default");
  CHECK(few["points_per_keyframe"].get<int>() == 150);
  CHECK(standard["points_per_keyframe"].get<int>() == 480);  // one per 40 pixels of 160x120
  // The VO is configured with it: fewer points in the arena and in the map.
  CHECK(few["arena_bytes"].get<double>() < 0.8 * standard["arena_bytes"].get<double>());
  CHECK(few["points"].get<double>() < 0.6 * standard["points"].get<double>());
}

TEST_CASE("odometry: --marginalisation-prior keeps what retired keyframes knew", "[vo][cli][long]") {
  // 60 frames and a window of 3 keyframes, so that keyframes retire (the 36-frame sequence of the
  // other tests makes 3 to 5 keyframes, which leaves the prior untested on some builds).
  const fs::path& seq = sequence("drive", "0.0002", "60");
  TempDir out;
  const fs::path with = out / "prior", without = out / "plain";
  odometry(seq, with, {"--max-keyframes", "3", "--marginalisation-prior"});
  odometry(seq, without, {"--max-keyframes", "3"});
  CHECK(summary_of(with)["marginalisation_prior"].get<bool>());
  CHECK_FALSE(summary_of(without)["marginalisation_prior"].get<bool>());
  const nlohmann::json e = evaluate(with);
  INFO(e.dump(2));
  REQUIRE(e["keyframes"].get<int>() > 3);  // at least one retired
  CHECK(e["ate_relative"].get<double>() < 0.10);
  // The prior took part: the trajectories differ.
  const auto read = [](const fs::path& file) {
    std::ifstream in(file);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  CHECK(read(with / "trajectory.tum") != read(without / "trajectory.tum"));
}

TEST_CASE("every photometric mode runs on a ghosting sequence", "[vo][cli]") {
  const fs::path& seq = sequence("drive", "0.012");
  TempDir out;
  each_mode_evaluated(seq, out.path(), [](const std::string& mode, const nlohmann::json& e) {
    CHECK(e["posed"].get<int>() >= 10);
    if (mode.rfind("ir", 0) == 0) {
      CHECK(e["tau_true_c_s"].get<double>() == Approx(0.012));
      CHECK(e["tau_c_s"].get<double>() > 0.001);  // estimated, within the physical bounds
      CHECK(e["tau_c_s"].get<double>() < 0.1);
    }
  });
}

TEST_CASE("odometry says where its tau comes from", "[vo][cli][tau]") {
  // tau from motion alone depends on the frames' smoothness (docs/odometry-study.md, "τ"), so the run says when that is all it had; shutter events and exposure changes
  // are the long tests' (below).
  const fs::path& seq = sequence("drive", "0.012");
  TempDir out;
  const auto run = [&](const char* name, std::vector<std::string> options) {
    std::vector<std::string> args = {"odometry", seq.string(), "--out", (out / name).string()};
    args.insert(args.end(), options.begin(), options.end());
    const CliResult r = run_bolo(args);
    INFO(r.err);
    REQUIRE(r.code == 0);
    return std::make_pair(summary_of(out / name)["tau_source"].get<std::string>(), r.out);
  };
  // tau's standard error: the carry-over fits' frame-to-frame scatter where tau is estimated,
  // null where it is not.
  const auto standard_error = [&](const char* name) { return summary_of(out / name)["tau_c_standard_error_s"]; };
  const auto [motion, motion_out] = run("ir", {"--photometric", "ir"});
  CHECK(motion == "motion");
  CHECK(motion_out.find("tau from camera motion alone") != std::string::npos);
  REQUIRE(standard_error("ir").is_number());
  CHECK(standard_error("ir").get<double>() > 0);
  CHECK(standard_error("ir").get<double>() < 0.1 * summary_of(out / "ir")["tau_c_s"].get<double>());
  const auto [fixed, fixed_out] = run("fixed", {"--photometric", "ir-loop", "--fixed-tau", "--tau-init", "0.012"});
  CHECK(fixed == "fixed");
  CHECK(fixed_out.find("tau from camera motion alone") == std::string::npos);
  CHECK(standard_error("fixed").is_null());
  CHECK(run("affine", {"--photometric", "affine"}).first == "none");
  CHECK(standard_error("affine").is_null());
}

TEST_CASE("the ir modes track a ghosting drive and estimate tau", "[vo][cli][tau][long]") {
  // 2.5 s of street/drive at 60 Hz with tau 12 ms, rendered over each pixel's area (3 x 3 rays).
  // Started at 10 ms, a tau that never moved is 16.7 % off and fails the 10 % bound.
  TempDir tmp;
  const fs::path seq = street_ss3(tmp / "drive-ss3", "drive", "150", "0.012", "1");
  for (const char* mode : {"ir", "ir-loop"}) {
    const nlohmann::json e = odometry_evaluated(seq, tmp / mode, mode);
    INFO(e.dump(2));
    CHECK(e["posed"].get<int>() >= 135);  // of 150; initialisation takes ~12
    CHECK(e["reinitialisations"].get<int>() == 0);
    CHECK(e["ate_relative"].get<double>() < 0.01);
    REQUIRE(e["tau_c_error_2s"].is_number());
    CHECK(e["tau_c_error_2s"].get<double>() < 0.10);
  }
}

TEST_CASE("the ir modes read tau 15 ms within 10 % on a handheld walk", "[vo][cli][tau][long]") {
  // Handheld, tau 15 ms, 3 x 3 rays: the fit's Jacobians must be the raw frames' (the low-passed
  // tracking images' gradients bias it low; tau_estimator.cpp). Started at 10 ms, 33 % off.
  TempDir tmp;
  const fs::path seq = street_ss3(tmp / "handheld-15ms", "handheld", "150", "0.015", "2");
  for (const char* mode : {"ir", "ir-loop"}) {
    const nlohmann::json e = odometry_evaluated(seq, tmp / mode, mode);
    INFO(mode << ": " << e.dump(2));
    REQUIRE(e["tau_c_error_2s"].is_number());
    CHECK(e["tau_c_error_2s"].get<double>() < 0.10);
    CHECK(e["ate_relative"].get<double>() < 0.01);
  }
}

TEST_CASE("the tau estimate does not depend on its start (handheld, tau 8 ms)", "[vo][cli][tau][long]") {
  // 2.5 s of street/handheld at 60 Hz with tau 8 ms (3 x 3 rays), `ir` started from 10 and from
  // 15 ms. Each frame's pose is tracked on the image made with the current tau, so pairs sampled
  // at that pose lean towards it unless the poses and depths are eliminated from the fit
  // (tau_estimator.cpp): both starts must end within 10 % and within 0.5 ms of each other.
  TempDir tmp;
  const fs::path seq = street_ss3(tmp / "handheld-ss3", "handheld", "150", "0.008", "5");
  double tau_2s[2] = {0, 0};
  int i = 0;
  for (const char* start : {"0.010", "0.015"}) {
    const fs::path run = tmp / (std::string("ir-") + start);
    odometry(seq, run, {"--photometric", "ir", "--tau-init", start});
    const nlohmann::json e = evaluate(run);
    INFO(start << "\n" << e.dump(2));
    REQUIRE(e["tau_c_at_2s_s"].is_number());
    tau_2s[i++] = e["tau_c_at_2s_s"].get<double>();
    CHECK(e["tau_c_error_2s"].get<double>() < 0.10);
  }
  CHECK(std::abs(tau_2s[0] - tau_2s[1]) < 0.0005);
}

TEST_CASE("repeated frames are skipped and break the carry-over chain", "[vo][cli][tau][long]") {
  // The simulator's frame_duplication effect: every 10th frame repeats the one before bit for
  // bit, and the sensor frame it stands for never arrives (2.5 s of street/drive, 60 Hz, tau
  // 12 ms, 3 x 3 rays). Taken as frames, the repeats would pair identical frames as carry-over
  // and the frame after them with the wrong predecessor, which reads tau far too low.
  TempDir tmp;
  const fs::path seq = street_ss3(tmp / "drive-repeats", "drive", "150", "0.012", "1", "frame_duplication:every=10");
  for (const char* mode : {"ir", "ir-loop"}) {
    const fs::path run = tmp / mode;
    const nlohmann::json e = odometry_evaluated(seq, run, mode);
    INFO(mode << ": " << e.dump(2));
    CHECK(summary_of(run)["duplicates"].get<int>() == 15);  // frames 9, 19, ..., 149
    CHECK(e["duplicates"].get<int>() == 15);
    // stats.csv marks exactly those frames, and none of them has a pose.
    int marked = 0;
    for (const odo::StatsRow& row : odo::read_stats_csv(run / "stats.csv")) {
      const bool duplicate = row.state == "duplicate";
      CHECK(duplicate == (row.index % 10 == 9));
      marked += duplicate;
    }
    CHECK(marked == 15);
    CHECK(e["posed"].get<int>() >= 115);  // of 135 new frames; initialisation takes ~12
    CHECK(e["lost"].get<int>() == 0);
    CHECK(e["reinitialisations"].get<int>() == 0);
    CHECK(e["ate_relative"].get<double>() < 0.01);
    REQUIRE(e["tau_c_error_2s"].is_number());
    CHECK(e["tau_c_error_2s"].get<double>() < 0.10);
  }
}

TEST_CASE("dead pixels do not pull the tau estimate", "[vo][cli][tau][long]") {
  // Ten pixels stuck at 0 or full scale (the simulator's dead_pixels; no bad-pixel replacement
  // in front of the VO), 2.5 s of street/drive, 60 Hz, tau 12 ms, 3 x 3 rays. A dead pixel in a
  // carry-over sample's interpolation footprint puts a step of thousands of counts into A and B
  // alike, which reads as alpha = 1; samples near stuck pixels are left out.
  TempDir tmp;
  const fs::path seq = street_ss3(tmp / "drive-dead", "drive", "150", "0.012", "1", "dead_pixels");
  for (const char* mode : {"ir", "ir-loop"}) {
    const nlohmann::json e = odometry_evaluated(seq, tmp / mode, mode);
    INFO(mode << ": " << e.dump(2));
    CHECK(e["ate_relative"].get<double>() < 0.01);
    REQUIRE(e["tau_c_error_2s"].is_number());
    CHECK(e["tau_c_error_2s"].get<double>() < 0.10);
  }
}

TEST_CASE("shutter events give tau from their step response and reset the offset", "[vo][cli][tau][long]") {
  // 2.5 s of street/drive, 60 Hz, tau 10 ms, rendered with 6 x 6 rays (smooth images, where the
  // carry-over pairs read tau high: docs/odometry-study.md, "τ"), with a flagged
  // shutter event every 50 frames: the pixels settle on the shutter and the camera's offset jumps
  // by 10-20 counts. The frame after an event is the scene's step response; its contrast against
  // the keyframes gives tau at first order, so the bound is 2 %.
  TempDir tmp;
  const fs::path seq = tmp / "drive-ss6-ffc";
  const CliResult made = run_bolo({"simulate", seq.string(), "--scene", "street", "--trajectory", "drive", "--fps", "60",
                                   "--frames", "150", "--size", "160x120", "--tau", "0.010", "--noise", "3", "--seed",
                                   "1", "--supersample", "6", "--effect", "ffc_step:every=50"});
  INFO(made.err);
  REQUIRE(made.code == 0);
  for (const char* mode : {"ir", "ir-loop"}) {
    const fs::path run = tmp / mode;
    const nlohmann::json e = odometry_evaluated(seq, run, mode);
    const nlohmann::json summary = summary_of(run);
    INFO(mode << ": " << e.dump(2) << summary.dump(2));
    CHECK(summary["shutter_events"] == 2);
    CHECK(summary["tau_source"] == "shutter_events");
    REQUIRE(summary["tau_from_shutter_events"].size() == 2);
    for (const auto& event : summary["tau_from_shutter_events"]) CHECK(event["tau_s"].get<double>() == Approx(0.010).epsilon(0.02));
    // Two events: the standard error from their spread (a third of its square under the mean's
    // weights), within the 2 % they agree to.
    REQUIRE(summary["tau_c_standard_error_s"].is_number());
    CHECK(summary["tau_c_standard_error_s"].get<double>() > 0);
    CHECK(summary["tau_c_standard_error_s"].get<double>() < 0.0002);
    CHECK(e["ate_relative"].get<double>() < 0.003);
    CHECK(e["lost"].get<int>() == 0);
    REQUIRE(e["tau_c_error_2s"].is_number());
    CHECK(e["tau_c_error_2s"].get<double>() < 0.02);
  }
}

TEST_CASE("the ir modes hold when exposure and readout split the frame unevenly", "[vo][cli][tau][long]") {
  // 2.5 s of street/drive, 60 Hz, tau 10 ms, 3 x 3 rays, with t_e 12.5 / t_r 4.1 ms and the other
  // way round. The scene estimate's static level is (1 - alpha) / beta times the raw one, which
  // moves with tau unless t_e = t_r, so the tracking images are scaled back to the raw level.
  // ir-loop with the short readout misses issue 41's 10 % (docs/odometry-study.md, "τ"): the
  // bound here is 20 %, against a start 50 % off.
  TempDir tmp;
  for (const auto& [exposure, readout] : {std::pair{"0.0125", "0.0041"}, std::pair{"0.0041", "0.0125"}}) {
    const fs::path seq = tmp / (std::string("drive-") + exposure);
    const CliResult made = run_bolo({"simulate", seq.string(), "--scene", "street", "--trajectory", "drive", "--fps",
                                     "60", "--frames", "150", "--size", "160x120", "--tau", "0.010", "--noise", "3",
                                     "--seed", "1", "--supersample", "3", "--exposure", exposure, "--readout", readout});
    INFO(made.err);
    REQUIRE(made.code == 0);
    for (const char* mode : {"ir", "ir-loop"}) {
      // Started at 15 ms, away from the truth: a tau that never moved would fail the bound below.
      const fs::path run = tmp / (std::string(mode) + exposure);
      odometry(seq, run, {"--photometric", mode, "--tau-init", "0.015"});
      const nlohmann::json e = evaluate(run);
      INFO(exposure << " / " << readout << " " << mode << ": " << e.dump(2));
      CHECK(e["ate_relative"].get<double>() < 0.006);
      CHECK(e["coverage"].get<double>() > 0.9);
      REQUIRE(e["tau_c_error_2s"].is_number());
      CHECK(e["tau_c_error_2s"].get<double>() < 0.2);
    }
  }
}

TEST_CASE("affine and the ir modes hold a drive whose exposure switches", "[vo][cli][tau][long]") {
  // 2.5 s of street/drive, 60 Hz, tau 12 ms (the VO starts at 10), 3 x 3 rays, the exposure
  // switching between 50 and 35 % of the period every 30 frames (bolo simulate
  // --alternate-exposure): the raw static level changes by a factor of the true tau at each
  // switch, which gives tau at first order (tau_source exposure_changes) and which the brightness
  // must follow across each change of timing.
  TempDir tmp;
  const fs::path seq = tmp / "drive-switching";
  const CliResult made = run_bolo({"simulate", seq.string(), "--scene", "street", "--trajectory", "drive", "--fps", "60",
                                   "--frames", "150", "--size", "160x120", "--tau", "0.012", "--noise", "3", "--seed",
                                   "1", "--supersample", "3", "--exposure", "0.008333", "--alternate-exposure",
                                   "0.005833", "--alternate-every", "30"});
  INFO(made.err);
  REQUIRE(made.code == 0);
  // Brightness constancy on raw counts cannot follow the level steps: the sequence does test them.
  CHECK(odometry_evaluated(seq, tmp / "none", "none")["coverage"].get<double>() < 0.9);
  for (const char* mode : {"affine", "ir", "ir-loop"}) {
    const nlohmann::json e = odometry_evaluated(seq, tmp / mode, mode);
    INFO(mode << ": " << e.dump(2));
    CHECK(e["ate_relative"].get<double>() < 0.004);
    CHECK(e["coverage"].get<double>() > 0.9);
    CHECK(e["reinitialisations"].get<int>() == 0);
    if (std::string(mode) != "affine") {
      REQUIRE(e["tau_c_error_2s"].is_number());
      CHECK(std::fabs(e["tau_c_error_2s"].get<double>()) < 0.05);
      CHECK(summary_of(tmp / mode)["tau_source"] == "exposure_changes");
    }
  }
}

TEST_CASE("the ir modes initialise on a handheld walk within 16 frames", "[vo][cli][init][long]") {
  // 1 s of street/handheld (walking forward along the optical axis with hand shake) at 60 Hz,
  // tau 15 ms. Forward motion is the hard case of monocular initialisation: the warm-started
  // solve can keep a lateral translation that a wrong rotation cancels, and a radial flow comes
  // only after ~1.3 m, so the initialiser also solves fresh (initializer.cpp).
  TempDir tmp;
  const fs::path seq = street_ss3(tmp / "handheld-ss3", "handheld", "60", "0.015", "1");
  for (const char* mode : {"ir", "ir-loop"}) {
    const nlohmann::json e = odometry_evaluated(seq, tmp / mode, mode);
    INFO(mode << ": " << e.dump(2));
    CHECK(e["posed"].get<int>() >= 44);  // of 60: initialised within 16 frames
    CHECK(e["reinitialisations"].get<int>() == 0);
    CHECK(e["ate_relative"].get<double>() < 0.03);
  }
}

TEST_CASE("every photometric mode holds on a drone's view of the road", "[vo][cli][long]") {
  // The flyover: image motion across a near-planar ground seen 40-50 degrees down, which the VO
  // was not developed on (the study's "A trajectory the VO was not developed on"; over 4 s the IR
  // modes still lose the scale on seed 3).
  TempDir tmp;
  const fs::path seq = street_ss3(tmp / "fly", "flyover", "120", "0.010", "1");
  each_mode_evaluated(seq, tmp.path(), [](const std::string&, const nlohmann::json& e) {
    CHECK(e["ate_relative"].get<double>() < 0.03);
    CHECK(e["posed"].get<int>() >= 100);
    CHECK(e["lost"].get<int>() == 0);
  });
}

TEST_CASE("every photometric mode tracks a pan about the camera's centre", "[vo][cli][long]") {
  // A pure rotation (30 deg/s) gives no baseline: no new point matures, and the initial map
  // leaves the view after ~1.5 s. The points no baseline could place are activated when the
  // tracked points run short (activate_mature_points), so no mode loses a frame or restarts.
  TempDir tmp;
  const fs::path seq = street_ss3(tmp / "pan", "pan", "150", "0.010", "1");
  each_mode_evaluated(seq, tmp.path(), [](const std::string&, const nlohmann::json& e) {
    CHECK(e["lost"].get<int>() == 0);
    CHECK(e["reinitialisations"].get<int>() == 0);
    CHECK(e["posed"].get<int>() >= 95);
    CHECK(e["rpe_rot_rmse_deg"].get<double>() < 2.0);
  });
}

TEST_CASE("every photometric mode tracks a drive filmed at 9 Hz", "[vo][cli][long]") {
  // A 9 Hz camera (the export-free rate of small thermal cores): a car at ~10 m/s moves 1.1 m a
  // frame. The initialisation's and the keyframes' spacing are bounded in time as well as in
  // frames (10 frames, 3 frames, or what they take at 30 Hz); spaced in frames alone they span
  // metres, and the modes lose frames and accuracy.
  TempDir tmp;
  const fs::path seq = street_ss3(tmp / "drive9", "drive", "72", "0.012", "2", nullptr, "9");
  each_mode_evaluated(seq, tmp.path(), [](const std::string&, const nlohmann::json& e) {
    CHECK(e["ate_relative"].get<double>() < 0.01);
    CHECK(e["posed"].get<int>() >= 64);
    CHECK(e["reinitialisations"].get<int>() == 0);
  });
}

// The distance the camera centre moved between the poses nearest t0 and t1 (s).
double moved(const std::vector<odo::StampedPose>& poses, double t0, double t1) {
  const auto near = [&](double t) {
    const odo::StampedPose* best = &poses.front();
    for (const odo::StampedPose& p : poses)
      if (std::fabs(p.t - t) < std::fabs(best->t - t)) best = &p;
    return best->T_wc.t;
  };
  return (near(t1) - near(t0)).norm();
}

TEST_CASE("the map's scale survives a walker's look-arounds", "[vo][cli][long]") {
  // Handheld seed 5 turns the camera at 4.0-4.2 s and 5.75-5.9 s (180-200 deg/s) while walking
  // on; the map's points leave the view and the new view's are placed at the typical depth. The
  // scale bridge holds the camera centre on the velocity before each turn until the new view's
  // points have depths (scale_bridge.cpp); without it the distance per true metre after the
  // turns collapses.
  TempDir tmp;
  const fs::path seq = tmp / "walk";
  const CliResult r = run_bolo({"simulate", seq.string(), "--scene", "street", "--trajectory", "handheld", "--fps",
                                "60", "--frames", "420", "--size", "160x120", "--tau", "0.010", "--noise", "3",
                                "--seed", "5"});
  REQUIRE(r.code == 0);
  odometry(seq, tmp / "bridged", {"--photometric", "none"});
  odometry(seq, tmp / "free", {"--photometric", "none", "--no-scale-bridge"});
  const auto truth = odo::read_tum(seq / "poses.tum");
  const auto scale_kept = [&](const fs::path& run) {
    const auto est = odo::read_tum(run / "trajectory.tum");
    const double before = moved(est, 1.0, 2.0) / moved(truth, 1.0, 2.0);
    const double after = moved(est, 6.2, 7.0) / moved(truth, 6.2, 7.0);
    return after / before;
  };
  const double bridged = scale_kept(tmp / "bridged"), free = scale_kept(tmp / "free");
  const nlohmann::json with = evaluate(tmp / "bridged"), without = evaluate(tmp / "free");
  INFO("bridged: scale kept " << bridged << ", " << with.dump(2) << "\nfree: scale kept " << free << ", " << without.dump(2));
  CHECK(bridged > 0.6);
  CHECK(bridged < 1.6);
  CHECK(free < 0.3);
  CHECK(with["reinitialisations"].get<int>() == 0);
  CHECK(with["ate_relative"].get<double>() < 0.5 * without["ate_relative"].get<double>());
  const nlohmann::json bridges = summary_of(tmp / "bridged")["scale_bridges"];
  CHECK(bridges.size() == 2);
  CHECK(summary_of(tmp / "free")["scale_bridges"].empty());
  CHECK(summary_of(tmp / "free")["scale_bridge"] == false);
}

TEST_CASE("the ir modes hold tau where noise dominates the carry-over pairs (a render from elsewhere)", "[vo][cli][tau][long]") {
  // scripts/study/plane-render/plane_render.cpp: a real FLIR T1030 frame on a ground plane, its
  // own renderer and the paper's discrete ghost, tau 15 ms, noise 3 counts. Its fine texture moves
  // under the VO's flat-block noise measurement, which reads ~3.5 counts; the noise takes three
  // quarters of B^2, and an over-corrected fit would run tau to the 100-ms bound. The signal-share
  // bound keeps it: tau must not run away, and ir must track nearly as well as none. tau within 10 % here
  // is issue 41's open ask (docs/odometry-study.md, "Frames from elsewhere").
  const fs::path shared = shared_recording("flir-t1030-hand");
  if (shared.empty()) return;
  TempDir tmp;
  const fs::path seq = tmp / "plane";
  const std::string cmd = std::string(BOLO_PLANE_RENDER) + " " + (shared / "frames.npy").string() + " " + seq.string() +
                          " 320 256 300 60 0.015 3";
  REQUIRE(std::system(cmd.c_str()) == 0);
  const nlohmann::json ir = odometry_evaluated(seq, tmp / "ir", "ir");
  const nlohmann::json none = odometry_evaluated(seq, tmp / "none", "none");
  INFO("ir: " << ir.dump(2) << "\nnone: " << none.dump(2));
  CHECK(ir["tau_c_s"].get<double>() < 0.02);
  CHECK(ir["ate_relative"].get<double>() < 1.5 * none["ate_relative"].get<double>());
  CHECK(ir["ate_relative"].get<double>() < 0.01);
}

TEST_CASE("real motion: the Optris clip through its rational lens, forward against reversed", "[vo][cli][long]") {
  // ../shared/data/real/optris-pi450-handheld: 100 frames, 382x288, ~28 Hz, handheld over a desk,
  // a strong fixed pattern, camera.json with OpenCV's rational model; no ground truth. The fixed
  // pattern is taken out first (median_nuc.py through bolo correct --nuc, the two-frame correction
  // off), then the check: the frames run backwards must give the same motion, so the forward run is
  // evaluated against the reversed one; with the distortion switched off the two disagree by
  // several degrees (figures: docs/odometry-study.md, "Real motion").
  const fs::path rec = shared_recording("optris-pi450-handheld");
  if (rec.empty()) return;
  TempDir tmp;
  const std::string nuc_cmd = std::string("python3 ") + BOLO_MEDIAN_NUC + " " + rec.string() + " " +
                              (tmp / "nuc.npy").string() + " > /dev/null";
  REQUIRE(std::system(nuc_cmd.c_str()) == 0);
  const fs::path flat = tmp / "flat";
  const CliResult corrected = run_bolo({"correct", rec.string(), flat.string(), "--nuc", (tmp / "nuc.npy").string(),
                                        "--tau-h", "0.0001", "--tau-c", "0.0001", "--exposure", "0.0178",
                                        "--readout", "0.0178"});
  INFO(corrected.err);
  REQUIRE(corrected.code == 0);
  // The same frames behind a lens without distortion (k1..k6, p1, p2 = 0; the same intrinsics).
  const fs::path no_lens = copy_files(flat, tmp / "no-lens", {"recording.json", "frames.csv", "frames.npy"});
  {
    std::ifstream in(flat / "camera.json");
    nlohmann::json cam = nlohmann::json::parse(in);
    for (const char* k : {"k1", "k2", "k3", "k4", "k5", "k6", "p1", "p2"}) cam[k] = 0.0;
    std::ofstream(no_lens / "camera.json") << cam.dump();
  }
  const auto forward_against_reversed = [&](const fs::path& seq, const std::string& name) {
    odometry(seq, tmp / name, {"--photometric", "none"});
    odometry(seq, tmp / (name + "-reversed"), {"--photometric", "none", "--reverse"});
    const fs::path json = tmp / name / "reversed.json";
    const CliResult r = run_bolo({"evaluate", (tmp / name).string(), "--truth",
                                  (tmp / (name + "-reversed") / "trajectory.tum").string(), "--rpe-delta", "0.25",
                                  "--json", json.string()});
    INFO(r.err);
    REQUIRE(r.code == 0);
    std::ifstream in(json);
    return nlohmann::json::parse(in);
  };
  const nlohmann::json lens = forward_against_reversed(flat, "lens");
  const nlohmann::json off = forward_against_reversed(no_lens, "off");
  INFO("camera.json: " << lens.dump(2) << "\nwithout distortion: " << off.dump(2));
  CHECK(summary_of(tmp / "lens")["undistorted"] == true);
  CHECK(summary_of(tmp / "lens-reversed")["reverse"] == true);
  CHECK(lens["frames"] == 100);
  CHECK(lens["posed"].get<int>() >= 70);
  CHECK(summary_of(tmp / "lens-reversed")["posed"].get<int>() >= 70);
  CHECK(lens["rpe_rot_rmse_deg"].get<double>() > 0);  // the runs share posed frames
  CHECK(lens["rpe_rot_rmse_deg"].get<double>() < 2.0);
  CHECK(off["rpe_rot_rmse_deg"].get<double>() > 2.0);
}

TEST_CASE("the ir modes hold the scale on a handheld sequence once the carry-over correction is cored", "[vo][cli][long]") {
  // The full correction (the paper's, --carry-coring 0) is an inverse filter: at tau 12 ms and
  // 60 Hz it leaves 2.2 times the pixel noise in still image regions, and on this handheld
  // sequence the map's scale drifts. Run without the tracking image's low-pass (--smoothing 0),
  // which damps that noise too and would hide the difference.
  TempDir tmp;
  const fs::path seq = street_ss3(tmp / "handheld", "handheld", "180", "0.012", "2");
  odometry(seq, tmp / "ir", {"--photometric", "ir", "--smoothing", "0"});
  odometry(seq, tmp / "ir-loop", {"--photometric", "ir-loop", "--smoothing", "0"});
  odometry(seq, tmp / "full", {"--photometric", "ir", "--carry-coring", "0", "--smoothing", "0"});
  const nlohmann::json ir = evaluate(tmp / "ir"), loop = evaluate(tmp / "ir-loop"), full = evaluate(tmp / "full");
  INFO("ir: " << ir.dump(2) << "\nir-loop: " << loop.dump(2) << "\nfull correction: " << full.dump(2));
  CHECK(ir["ate_relative"].get<double>() < 0.006);
  CHECK(loop["ate_relative"].get<double>() < 0.006);
  CHECK(ir["ate_relative"].get<double>() < 0.5 * full["ate_relative"].get<double>());
  CHECK(summary_of(tmp / "ir")["carry_coring"] == 1.0);
  CHECK(summary_of(tmp / "full")["carry_coring"] == 0.0);
}

TEST_CASE("odometry: --hfov stands in for a missing camera.json", "[vo][cli][long]") {
  const fs::path& seq = sequence("drive", "0.0002");
  TempDir tmp;
  const fs::path nocam = tmp / "nocam";
  copy_files(seq, nocam, {"recording.json", "frames.npy", "frames.csv"});
  // The simulator's 160x120 camera: a centred pinhole of 50 degrees (fx = 80 / tan 25 deg).
  const CliResult with_json = run_bolo({"odometry", seq.string(), "--out", (tmp / "json").string()});
  const CliResult with_fov = run_bolo({"odometry", nocam.string(), "--out", (tmp / "fov").string(), "--hfov", "50"});
  INFO(with_json.err << with_fov.err);
  REQUIRE(with_json.code == 0);
  REQUIRE(with_fov.code == 0);
  const auto a = odo::read_tum(tmp / "json" / "trajectory.tum");
  const auto b = odo::read_tum(tmp / "fov" / "trajectory.tum");
  REQUIRE(a.size() == b.size());
  REQUIRE(a.size() >= 20);
  for (std::size_t i = 0; i < a.size(); ++i) {
    CHECK(a[i].t == b[i].t);
    CHECK((a[i].T_wc.t - b[i].T_wc.t).norm() < 1e-3);
  }
  // A different field of view is a different camera: the scale-free path still comes out, but
  // not the same one.
  const CliResult wide = run_bolo({"odometry", nocam.string(), "--out", (tmp / "wide").string(), "--hfov", "70"});
  REQUIRE(wide.code == 0);
  const auto c = odo::read_tum(tmp / "wide" / "trajectory.tum");
  double differs = 0;
  for (std::size_t i = 0; i < std::min(a.size(), c.size()); ++i)
    differs = std::max(differs, (a[i].T_wc.t - c[i].T_wc.t).norm());
  CHECK(differs > 1e-3);
  CHECK(refused({"odometry", nocam.string(), "--out", (tmp / "x").string(), "--hfov", "180"})
            .find("--hfov: must be within 1..179 degrees") != std::string::npos);
  CHECK(refused({"odometry", nocam.string(), "--out", (tmp / "y").string()}).find("or give --hfov DEG") !=
        std::string::npos);
}

TEST_CASE("odometry: a lens with distortion is resampled onto a pinhole", "[vo][cli][remap][long]") {
  TempDir tmp;
  const fs::path seq = tmp / "barrel";
  REQUIRE(run_bolo({"simulate", seq.string(), "--scene", "street", "--trajectory", "drive", "--fps", "60", "--frames",
                    "90", "--size", "160x120", "--tau", "0.010", "--noise", "3", "--seed", "1", "--supersample", "3",
                    "--distortion", "-0.25,0.05"})
              .code == 0);
  {
    std::ifstream in(seq / "camera.json");
    const nlohmann::json cam = nlohmann::json::parse(in);
    CHECK(cam["k1"] == -0.25);
    CHECK(cam["k2"] == 0.05);
  }
  // The same frames with the distortion left out of camera.json: what the VO saw before.
  const fs::path naive = tmp / "naive";
  copy_files(seq, naive, {"recording.json", "frames.npy", "frames.csv", "poses.tum"});
  {
    std::ifstream in(seq / "camera.json");
    nlohmann::json cam = nlohmann::json::parse(in);
    cam["k1"] = 0, cam["k2"] = 0;
    std::ofstream(naive / "camera.json") << cam.dump();
  }
  fs::create_directories(tmp / "run");
  fs::create_directories(tmp / "naive-run");
  // Compared on the frames tracked as they came: the initialisation's, posed at its end in the
  // map's first scale, would blur the lens model's effect.
  for (const char* mode : {"none", "ir"}) {
    INFO(mode);
    const CliResult r = run_bolo({"odometry", seq.string(), "--out", (tmp / "run" / mode).string(), "--photometric", mode,
                                  "--online-poses-only"});
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(r.out.find("camera.json has lens distortion: frames resampled onto a pinhole (focal lengths x1)") !=
          std::string::npos);
    CHECK(summary_of(tmp / "run" / mode)["undistorted"] == true);
    const nlohmann::json resampled = evaluate(tmp / "run" / mode);
    odometry(naive, tmp / "naive-run" / mode, {"--photometric", mode, "--online-poses-only"});
    const nlohmann::json ignored = evaluate(tmp / "naive-run" / mode);
    CHECK(summary_of(tmp / "naive-run" / mode)["undistorted"] == false);
    CHECK(resampled["coverage"].get<double>() > 0.8);  // the first ~10 frames initialise
    CHECK(resampled["ate_relative"].get<double>() < 0.004);
    CHECK(resampled["ate_relative"].get<double>() < ignored["ate_relative"].get<double>());
  }
}

// `seq` with every frame's counts multiplied by `gain` (a camera or renderer with another scale).
fs::path with_gain(const fs::path& seq, const fs::path& out, double gain) {
  rec::Recording in(seq);
  rec::RecordingWriter writer(out, in.info());
  if (in.camera()) writer.set_camera(*in.camera());
  std::vector<std::uint16_t> frame(std::size_t{in.width()} * in.height());
  for (std::uint64_t i = 0; i < in.rows().size(); ++i) {
    in.read_frame(i, frame);
    for (std::uint16_t& v : frame) v = static_cast<std::uint16_t>(std::min(65535.0, std::round(v * gain)));
    writer.append(frame, in.rows()[i]);
  }
  for (const char* file : {"poses.tum", "truth/effects.json"}) {  // the ground truth, tau's included
    std::ifstream from(seq / file);
    std::stringstream text;
    text << from.rdbuf();
    writer.add_file(file, text.str());
  }
  writer.commit();
  return out;
}

TEST_CASE("odometry: frames with five times the counts track as the originals", "[vo][cli][tau][long]") {
  // The VO's thresholds in counts (Huber, gradient weight, point selection, tau prior) were tuned
  // on the simulator's scale; they follow the measured pixel noise above 4 counts, so frames with
  // five times the counts track as the originals.
  TempDir tmp;
  const fs::path seq = street_ss3(tmp / "drive", "drive", "150", "0.010", "1");
  const fs::path bright = with_gain(seq, tmp / "drive-x5", 5.0);
  for (const char* mode : {"none", "ir", "ir-loop"}) {
    const nlohmann::json original = odometry_evaluated(seq, tmp / (std::string("original-") + mode), mode);
    const nlohmann::json scaled = odometry_evaluated(bright, tmp / (std::string("x5-") + mode), mode);
    const nlohmann::json summary = summary_of(tmp / (std::string("x5-") + mode));
    INFO(mode << ": " << original.dump(2) << scaled.dump(2));
    CHECK(summary_of(tmp / (std::string("original-") + mode))["intensity_scale"] == 1.0);
    CHECK(summary["intensity_scale"].get<double>() > 3.4);
    CHECK(summary["intensity_scale"].get<double>() < 4.4);
    CHECK(scaled["coverage"].get<double>() > 0.9);
    CHECK(scaled["ate_relative"].get<double>() < 0.005);
    if (std::string(mode) != "none") {
      REQUIRE(scaled["tau_c_error_2s"].is_number());
      CHECK(scaled["tau_c_error_2s"].get<double>() < 0.10);
    }
  }
  // The thresholds as configured (--intensity-scale 1) do not hold there: the tau fit stays at
  // its start or the path is lost.
  odometry(bright, tmp / "x5-unscaled", {"--photometric", "ir-loop", "--intensity-scale", "1", "--tau-init", "0.015"});
  const nlohmann::json unscaled = evaluate(tmp / "x5-unscaled");
  INFO("unscaled: " << unscaled.dump(2));
  CHECK(summary_of(tmp / "x5-unscaled")["intensity_scale"] == 1.0);
  CHECK((!unscaled["tau_c_error_2s"].is_number() || unscaled["tau_c_error_2s"].get<double>() > 0.3 ||
         unscaled["ate_relative"].get<double>() > 0.01));
}

TEST_CASE("odometry: the ir modes warn on tone-mapped frames", "[vo][cli]") {
  const fs::path& seq = sequence("drive", "0.012");
  TempDir tmp;
  const fs::path toned = tmp / "toned";
  copy_files(seq, toned, {"frames.npy", "frames.csv", "camera.json"});
  {
    std::ifstream in(seq / "recording.json");
    nlohmann::json info = nlohmann::json::parse(in);
    info["units"] = "counts8";
    std::ofstream(toned / "recording.json") << info.dump();
  }
  const CliResult ir = run_bolo({"odometry", toned.string(), "--out", (tmp / "ir").string(), "--photometric", "ir", "--frames", "5"});
  REQUIRE(ir.code == 0);
  CHECK(ir.out.find("warning: the recording's units are counts8 (tone-mapped)") != std::string::npos);
  const CliResult plain = run_bolo({"odometry", toned.string(), "--out", (tmp / "affine").string(), "--photometric", "affine", "--frames", "5"});
  REQUIRE(plain.code == 0);
  CHECK(plain.out.find("warning") == std::string::npos);
}

// The recording with every exposure_s and readout_s cell of frames.csv emptied (unknown).
// A new recording folder `out` with `seq`'s frames and each frames.csv row (after the header)
// rewritten by `edit(index, row)`.
fs::path with_frames_csv(const fs::path& seq, const fs::path& out,
                         const std::function<std::string(std::size_t, const std::string&)>& edit) {
  copy_files(seq, out, {"recording.json", "frames.npy", "camera.json"});
  std::ifstream in(seq / "frames.csv");
  std::ofstream csv(out / "frames.csv");
  std::string line;
  std::getline(in, line);
  csv << line << "\n";
  for (std::size_t i = 0; std::getline(in, line); ++i) csv << edit(i, line) << "\n";
  return out;
}

fs::path without_frame_timing(const fs::path& seq, const fs::path& out) {
  return with_frames_csv(seq, out, [](std::size_t, const std::string& line) {
    const auto c1 = line.find(','), c2 = line.find(',', c1 + 1), c3 = line.find(',', c2 + 1),
               c4 = line.find(',', c3 + 1);
    return line.substr(0, c2 + 1) + "," + line.substr(c4);  // index,t_s,,,ffc,...
  });
}

TEST_CASE("odometry: empty exposure_s/readout_s cells are filled", "[vo][cli][long]") {
  // The sequence's timing is the simulator's default split, half the frame period each.
  const fs::path& seq = sequence("drive", "0.012");
  TempDir tmp;
  const fs::path bare = without_frame_timing(seq, tmp / "bare");
  {
    std::ifstream in(bare / "frames.csv");
    std::string header, row;
    std::getline(in, header), std::getline(in, row);
    REQUIRE(row.find("0,0,,,") == 0);
  }
  odometry(seq, tmp / "timed", {"--photometric", "ir"});
  const CliResult assumed = run_bolo({"odometry", bare.string(), "--out", (tmp / "assumed").string(), "--photometric", "ir"});
  INFO(assumed.err);
  REQUIRE(assumed.code == 0);
  CHECK(assumed.out.find("no exposure_s/readout_s for 36 frames: assumed half the frame interval each (8.333 ms)") !=
        std::string::npos);
  const auto timed = odo::read_tum(tmp / "timed" / "trajectory.tum");
  const auto filled = odo::read_tum(tmp / "assumed" / "trajectory.tum");
  REQUIRE(timed.size() >= 20);
  REQUIRE(timed.size() == filled.size());
  for (std::size_t i = 0; i < timed.size(); ++i) CHECK((timed[i].T_wc.t - filled[i].T_wc.t).norm() < 1e-6);
  const nlohmann::json a = summary_of(tmp / "assumed");
  CHECK(a["timing_assumed"] == 36);
  CHECK(a["timing_from_options"] == 0);
  CHECK(std::fabs(a["timing_assumed_s"].get<double>() - 1.0 / 120) < 1e-9);
  CHECK(std::fabs(a["tau_c_s"].get<double>() - summary_of(tmp / "timed")["tau_c_s"].get<double>()) < 1e-6);
  CHECK(summary_of(tmp / "timed")["timing_assumed"] == 0);
  // A different split is a different model: the same frames give another tau (alpha = exp(-t_r /
  // tau) is what they fix), and the options count where they were used.
  odometry(bare, tmp / "given", {"--photometric", "ir", "--exposure", "0.0125", "--readout", "0.0041667"});
  const nlohmann::json g = summary_of(tmp / "given");
  CHECK(g["timing_from_options"] == 36);
  CHECK(g["timing_assumed"] == 0);
  CHECK(g["timing_assumed_s"].is_null());
  CHECK(g["tau_c_s"].get<double>() < 0.8 * a["tau_c_s"].get<double>());
  // none and affine do not use the timing.
  const CliResult plain = run_bolo({"odometry", bare.string(), "--out", (tmp / "plain").string()});
  REQUIRE(plain.code == 0);
  CHECK(plain.out.find("assumed") == std::string::npos);
}

// A copy of `seq` whose frames from `from` on come `gap_s` later (frames.csv t_s only).
fs::path with_time_gap(const fs::path& seq, const fs::path& out, std::size_t from, double gap_s) {
  return with_frames_csv(seq, out, [&](std::size_t i, const std::string& line) {
    const auto c1 = line.find(','), c2 = line.find(',', c1 + 1);
    std::ostringstream t;
    t.precision(17);
    t << std::stod(line.substr(c1 + 1, c2 - c1 - 1)) + (i >= from ? gap_s : 0.0);
    return line.substr(0, c1 + 1) + t.str() + line.substr(c2);
  });
}

TEST_CASE("odometry: a gap in time breaks the carry-over chain where the corrector's rule does", "[vo][cli]") {
  const fs::path& seq = sequence("drive", "0.012");
  TempDir tmp;
  odometry(seq, tmp / "whole", {});
  CHECK(summary_of(tmp / "whole")["carry_over_breaks"] == 0);
  // Four frame periods missing before frame 18 (a link that dropped frames it did not count).
  odometry(with_time_gap(seq, tmp / "gap", 18, 4.0 / 60), tmp / "gapped", {});
  CHECK(summary_of(tmp / "gapped")["carry_over_breaks"] == 1);
  // Within 1.5 periods the chain holds.
  odometry(with_time_gap(seq, tmp / "late", 18, 0.4 / 60), tmp / "late-out", {});
  CHECK(summary_of(tmp / "late-out")["carry_over_breaks"] == 0);
}

TEST_CASE("odometry and evaluate refuse bad input with one line and leave nothing behind", "[vo][cli][refusal]") {
  const fs::path& seq = sequence("drive", "0.0002");
  TempDir tmp;
  // 10.1 unknown model
  CHECK(refused({"odometry", seq.string(), "--out", (tmp / "a").string(), "--photometric", "dso"})
            .find("--photometric: unknown model 'dso'") != std::string::npos);
  // 10.2 no camera.json
  const fs::path nocam = tmp / "nocam";
  copy_files(seq, nocam, {"recording.json", "frames.npy", "frames.csv"});
  CHECK(refused({"odometry", nocam.string(), "--out", (tmp / "b").string()}).find("camera.json: missing") !=
        std::string::npos);
  // 10.3 a camera model other than the format's pinhole, a distortion that folds
  fs::copy_file(seq / "camera.json", nocam / "camera.json");
  const auto edit_camera = [&](const char* key, const nlohmann::json& value) {
    std::ifstream in(seq / "camera.json");
    nlohmann::json cam = nlohmann::json::parse(in);
    cam[key] = value;
    std::ofstream(nocam / "camera.json") << cam.dump();
  };
  edit_camera("model", "fisheye");
  CHECK(refused({"odometry", nocam.string(), "--out", (tmp / "c").string()}).find("field model is not \"pinhole\"") !=
        std::string::npos);
  edit_camera("k1", -1.5);
  CHECK(refused({"odometry", nocam.string(), "--out", (tmp / "c").string()})
            .find("camera.json: distortion coefficients: the radial distortion (k1..k6) folds back inside the image") !=
        std::string::npos);
  // 10.4 ir without timing
  {
    std::ifstream in(seq / "frames.csv");
    std::stringstream text;
    text << in.rdbuf();
    std::string csv = text.str();
    const auto line2 = csv.find('\n', csv.find('\n') + 1);  // end of frame 0's row
    std::string row0 = csv.substr(csv.find('\n') + 1, line2 - csv.find('\n') - 1);
    const auto c1 = row0.find(','), c2 = row0.find(',', c1 + 1), c3 = row0.find(',', c2 + 1);
    row0 = row0.substr(0, c2 + 1) + "0" + row0.substr(c3);  // exposure_s of frame 0 zero
    csv.replace(csv.find('\n') + 1, line2 - csv.find('\n') - 1, row0);
    fs::copy_file(seq / "camera.json", tmp / "cam.json");
    std::ofstream(nocam / "frames.csv") << csv;
    std::ifstream cin(tmp / "cam.json");
    std::ofstream(nocam / "camera.json") << cin.rdbuf();
  }
  CHECK(refused({"odometry", nocam.string(), "--out", (tmp / "d").string(), "--photometric", "ir"})
            .find("frames.csv: frame 0: exposure_s must be positive") != std::string::npos);
  CHECK(refused({"odometry", seq.string(), "--out", (tmp / "d").string(), "--photometric", "ir", "--exposure", "0"})
            .find("--exposure: must be within 0..1 s (exclusive), got 0") != std::string::npos);
  CHECK(refused({"odometry", seq.string(), "--out", (tmp / "d").string(), "--photometric", "ir", "--readout", "-1"})
            .find("--readout: must be within 0..1 s, got -1") != std::string::npos);
  // 10.5 existing output
  fs::create_directories(tmp / "exists");
  CHECK(refused({"odometry", seq.string(), "--out", (tmp / "exists").string()}).find("already exists") !=
        std::string::npos);
  // 10.6 --tau-init out of range
  CHECK(refused({"odometry", seq.string(), "--out", (tmp / "e").string(), "--tau-init", "0.5"})
            .find("--tau-init: must be within") != std::string::npos);
  CHECK(refused({"odometry", seq.string(), "--out", (tmp / "e").string(), "--intensity-scale", "-1"})
            .find("--intensity-scale: must be within 0..10000 (0: measured), got -1") != std::string::npos);
  CHECK(refused({"odometry", seq.string(), "--out", (tmp / "e").string(), "--max-keyframes", "9"})
            .find("--max-keyframes: must be within 2..8, got 9") != std::string::npos);
  CHECK(refused({"odometry", seq.string(), "--out", (tmp / "e").string(), "--points-per-keyframe", "20"})
            .find("--points-per-keyframe: must be 0 (one per 40 pixels, at most 500) or within 50..8000, got 20") !=
        std::string::npos);
  CHECK(refused({"odometry", seq.string(), "--out", (tmp / "e").string(), "--retirement", "newest"})
            .find("--retirement: must be oldest or spread, got newest") != std::string::npos);
  CHECK(refused({"odometry", seq.string(), "--out", (tmp / "e").string(), "--carry-coring", "-0.5"})
            .find("--carry-coring: must be within 0..100 (0: the full correction), got -0.5") != std::string::npos);
  CHECK(refused({"odometry", seq.string(), "--out", (tmp / "e").string(), "--smoothing", "4"})
            .find("--smoothing: must be within 0..3 passes, got 4") != std::string::npos);
  CHECK(refused({"odometry", seq.string(), "--out", (tmp / "e").string(), "--photometric", "ir", "--reverse"})
            .find("--reverse: the ir modes' carry-over runs forward in time (use none or affine)") != std::string::npos);
  CHECK_FALSE(fs::exists(tmp / "e"));
  // 10.7 evaluate: not an odometry output
  CHECK(refused({"evaluate", seq.string()}).find("summary.json: cannot open") != std::string::npos);
  // 10.8 evaluate: a bad ground-truth file
  {
    const fs::path run = tmp / "run";
    REQUIRE(run_bolo({"odometry", seq.string(), "--out", run.string()}).code == 0);
    // The command line's defaults are written out in apps/bolo/commands.hpp: they must stay the VO's.
    const nlohmann::json summary = summary_of(run);
    CHECK(summary["smoothing"] == vo::VoConfig{}.smoothing);
    CHECK(summary["carry_coring"] == static_cast<double>(vo::VoConfig{}.carry_coring));
    CHECK(summary["max_keyframes"] == vo::VoConfig{}.max_keyframes);
    std::ofstream(tmp / "bad.tum") << "0.0 1 2 3\n";
    CHECK(refused({"evaluate", run.string(), "--truth", (tmp / "bad.tum").string()})
              .find("bad.tum: line 1: expected 8 numbers") != std::string::npos);
  }
  // Nothing half-written: no output folders and no temporary leftovers besides what we made.
  for (const char* name : {"a", "b", "c", "d", "e"}) CHECK_FALSE(fs::exists(tmp / name));
  for (const auto& entry : fs::directory_iterator(tmp.path()))
    CHECK(entry.path().filename().string().find(".partial") == std::string::npos);
}

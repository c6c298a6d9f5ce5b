// bolo simulate: a recording with known ghosting that `bolo correct` with the same time
// constants restores to its scene.npy.

#include <catch2/catch.hpp>

#include <cmath>

#include "bolo/sim/scene/trajectory.hpp"
#include "cli_test_support.hpp"

using namespace bolo;
using namespace bolo::test;

TEST_CASE("simulate writes a ghosted recording that correct restores", "[cli][simulate]") {
  TempDir tmp;
  const auto sim_dir = tmp / "sim";
  const auto fixed_dir = tmp / "fixed";
  // One sub-step: the input is constant within each frame, the case the two-frame model (and so
  // the corrector) describes exactly.
  auto r = run_bolo({"simulate", sim_dir.string(), "--frames", "20", "--size", "40x30", "--fps",
                     "60", "--noise", "0", "--bits", "16", "--substeps", "1", "--effect",
                     "ffc_step:every=8,step=0"});
  REQUIRE(r.code == 0);
  rec::Recording sim(sim_dir);
  REQUIRE(sim.has_scene());
  CHECK(sim.frame_count() == 20);
  CHECK(sim.rows()[8].ffc == std::optional<bool>(true));
  CHECK(fs::exists(sim_dir / "truth" / "effects.json"));

  r = run_bolo({"correct", sim_dir.string(), fixed_dir.string(), "--tau-h", "0.012", "--tau-c",
                "0.012"});
  REQUIRE(r.code == 0);
  rec::Recording fixed(fixed_dir);
  std::vector<float> scene(40 * 30);
  double worst_raw = 0, worst_fixed = 0;
  const double heat = 1 - std::exp(-(0.5 / 60) / 0.012);
  for (std::uint64_t i = 0; i < 20; ++i) {
    // The first frame and the first after a shutter event hold the image of what the pixels saw
    // before (the scene before recording started, the shutter), which the corrector, knowing no
    // predecessor, cannot remove: only frames with a predecessor are compared.
    if (i == 0 || sim.rows()[i].ffc == std::optional<bool>(true)) continue;
    sim.read_scene(i, scene);
    const auto raw = read_u16_frame(sim, i);
    const auto out = read_u16_frame(fixed, i);
    for (std::size_t p = 0; p < scene.size(); ++p) {
      worst_raw = std::max(worst_raw, std::abs(raw[p] / heat - scene[p]));
      worst_fixed = std::max(worst_fixed, std::abs(out[p] - double{scene[p]}));
    }
  }
  INFO("worst |raw/heat - scene| " << worst_raw << ", worst |corrected - scene| " << worst_fixed);
  CHECK(worst_raw > 1000);   // the model did ghost the moving disc
  CHECK(worst_fixed <= 3.0);  // quantisation of raw counts, amplified by g and a*g
}

TEST_CASE("simulate --lag continuous: frames.csv says exposure = readout = the period, correct restores it, poses at t_s",
          "[cli][simulate]") {
  TempDir tmp;
  const auto sim_dir = tmp / "lag", fixed_dir = tmp / "lag-fixed";
  // One sub-step: the input is constant within each period, so the lag is the two-frame model
  // with t_e = t_r = the period, and the corrector given frames.csv's timing undoes it.
  auto r = run_bolo({"simulate", sim_dir.string(), "--frames", "12", "--size", "40x30", "--fps", "60", "--noise", "0",
                     "--bits", "16", "--substeps", "1", "--tau", "0.010", "--lag", "continuous"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  rec::Recording sim(sim_dir);
  for (std::uint64_t i = 0; i < 12; ++i) {
    CHECK(*sim.rows()[i].exposure_s == Approx(1.0 / 60).epsilon(1e-12));
    CHECK(*sim.rows()[i].readout_s == Approx(1.0 / 60).epsilon(1e-12));
    CHECK(*sim.rows()[i].t_s == Approx((i + 1) / 60.0).epsilon(1e-12));  // read at the period's end
  }
  r = run_bolo({"correct", sim_dir.string(), fixed_dir.string(), "--tau-h", "0.010", "--tau-c", "0.010"});
  REQUIRE(r.code == 0);
  rec::Recording fixed(fixed_dir);
  std::vector<float> scene(40 * 30);
  double worst_raw = 0, worst_fixed = 0;
  for (std::uint64_t i = 1; i < 12; ++i) {
    sim.read_scene(i, scene);
    const auto raw = read_u16_frame(sim, i);
    const auto out = read_u16_frame(fixed, i);
    for (std::size_t p = 0; p < scene.size(); ++p) {
      worst_raw = std::max(worst_raw, std::abs(raw[p] - double{scene[p]}));
      worst_fixed = std::max(worst_fixed, std::abs(out[p] - double{scene[p]}));
    }
  }
  INFO("worst |raw - scene| " << worst_raw << ", worst |corrected - scene| " << worst_fixed);
  CHECK(worst_raw > 500);     // the lag did ghost the moving disc
  CHECK(worst_fixed <= 2.0);  // quantisation of raw counts, amplified by the correction
  // A 3D scene's truth pose is at the frame's t_s, the instant it is read.
  const auto street = tmp / "street";
  REQUIRE(run_bolo({"simulate", street.string(), "--scene", "street", "--size", "32x24", "--frames", "3", "--fps", "60",
                    "--tau", "0.010", "--lag", "continuous"}).code == 0);
  rec::Recording street_rec(street);
  std::istringstream poses(read_text(street / "poses.tum"));
  double t = 0;
  for (std::uint64_t i = 0; i < 3; ++i) {
    REQUIRE(poses >> t);
    CHECK(t == Approx(*street_rec.rows()[i].t_s).margin(1e-8));
    poses.ignore(1000, '\n');
  }
}

TEST_CASE("simulate with an alternating exposure: frames.csv follows it and correct restores the scene", "[cli][simulate]") {
  TempDir tmp;
  const auto sim_dir = tmp / "sim";
  const auto fixed_dir = tmp / "fixed";
  const double period = 1 / 60.0, exposure = 0.5 * period, alternate = 0.3 * period;
  auto r = run_bolo({"simulate", sim_dir.string(), "--frames", "20", "--size", "40x30", "--fps", "60", "--noise", "0",
                     "--bits", "16", "--substeps", "1", "--tau", "0.012", "--alternate-exposure",
                     std::to_string(alternate), "--alternate-every", "4"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(r.out.find("every other 4 frames") != std::string::npos);
  rec::Recording sim(sim_dir);
  CHECK(sim.info().source.find("exposure alternating") != std::string::npos);
  for (std::uint64_t i = 0; i < 20; ++i) {
    const double expected = (i / 4) % 2 == 0 ? exposure : alternate;
    INFO("frame " << i);
    CHECK(*sim.rows()[i].exposure_s == Approx(expected).epsilon(1e-6));
    CHECK(*sim.rows()[i].exposure_s + *sim.rows()[i].readout_s == Approx(period).epsilon(1e-6));
  }
  CHECK(read_text(sim_dir / "truth" / "effects.json").find("every_frames") != std::string::npos);
  // The corrector takes each frame's exposure and its predecessor's readout from frames.csv.
  r = run_bolo({"correct", sim_dir.string(), fixed_dir.string(), "--tau-h", "0.012", "--tau-c", "0.012"});
  REQUIRE(r.code == 0);
  rec::Recording fixed(fixed_dir);
  std::vector<float> scene(40 * 30);
  double worst = 0;
  for (std::uint64_t i = 1; i < 20; ++i) {
    sim.read_scene(i, scene);
    const auto out = read_u16_frame(fixed, i);
    for (std::size_t p = 0; p < scene.size(); ++p) worst = std::max(worst, std::abs(out[p] - double{scene[p]}));
  }
  INFO("worst |corrected - scene| " << worst);
  CHECK(worst <= 4.0);  // quantisation of raw counts, amplified by 1/beta of the shorter exposure
}

TEST_CASE("simulate refuses bad options", "[cli][simulate][refusal]") {
  TempDir tmp;
  for (const auto& [args, needle] : std::vector<std::pair<std::vector<std::string>, std::string>>{
           {{"--size", "40by30"}, "--size"},
           {{"--fps", "0"}, "--fps"},
           {{"--tau-h", "-1"}, "--tau-h"},
           {{"--bits", "20"}, "--bits"},
           {{"--fps", "30", "--exposure", "0.05"}, "--readout"},
           {{"--effect", "warp_drive"}, "unknown effect"},
           {{"--alternate-every", "4"}, "--alternate-exposure and --alternate-every: give both or neither"},
           {{"--alternate-exposure", "0.005"}, "--alternate-exposure and --alternate-every: give both or neither"},
           {{"--fps", "60", "--alternate-exposure", "0.02", "--alternate-every", "4"}, "--alternate-exposure: 0.02 s does not fit"},
           {{"--alternate-exposure", "0", "--alternate-every", "4"}, "--alternate-exposure: must be a positive number"},
           {{"--frames", "-3"}, "--frames: must not be negative"},
           {{"--frames", "0"}, "--frames"},
           {{"--substeps", "0"}, "--substeps"},
           {{"--supersample", "0"}, "--supersample"},
           {{"--supersample", "9"}, "--supersample"},
           {{"--bits", "-16"}, "--bits: must not be negative"},
           {{"--effect", "offset_fpn:sigma=-2"}, "offset_fpn: sigma"},
           {{"--preset", "nosuch"}, "--preset nosuch"},
           {{"--scene", "nosuch"}, "--scene nosuch"},
           {{"--distortion", "-0.2"}, "--distortion: the demo scene is a flat pattern without a lens"},
           {{"--scene", "street", "--distortion", "-1.5"}, "--distortion: the radial distortion (k1..k6) folds back"},
           {{"--scene", "street", "--distortion", "0.1,0,0,0,0.1,0,0,0,0.1"}, "--distortion: at most 8 values"},
       }) {
    std::vector<std::string> argv = {"simulate", (tmp / "x").string()};
    argv.insert(argv.end(), args.begin(), args.end());
    const auto r = run_bolo(argv);
    INFO(r.err);
    CHECK(r.code == 2);
    CHECK(r.err.find(needle) != std::string::npos);
    CHECK(!fs::exists(tmp / "x"));
  }
}

TEST_CASE("simulate a 3D scene: camera.json, one pose per frame, counts from kelvin", "[cli][simulate]") {
  TempDir tmp;
  const auto dir = tmp / "street";
  const auto r = run_bolo({"simulate", "--out", dir.string(), "--scene", "street", "--trajectory", "drive",
                           "--size", "64x48", "--frames", "5", "--fps", "60", "--tau", "0.010", "--noise", "3",
                           "--seed", "1", "--effect", "fpa_drift:rate=0.5"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  rec::Recording rec(dir);
  REQUIRE(rec.camera().has_value());
  CHECK((*rec.camera())["model"] == "pinhole");
  CHECK((*rec.camera())["cx"] == 31.5);
  std::istringstream poses(read_text(dir / "poses.tum"));
  std::string line;
  int lines = 0;
  double t = 0, x = 0, previous_x = -1e9;
  while (std::getline(poses, line)) {
    std::istringstream fields(line);
    fields >> t >> x;
    CHECK(x > previous_x);  // driving forward along +x
    previous_x = x;
    ++lines;
  }
  CHECK(lines == 5);
  CHECK(rec.rows()[4].fpa_temp_c.has_value());
  // A night street: the cold sky (230-260 K) reads far below the 300 K level of the preset.
  std::vector<float> scene(64 * 48);
  rec.read_scene(0, scene);
  CHECK(*std::min_element(scene.begin(), scene.end()) < 8000 - 40 * 35);
  // --supersample: the pixel's area instead of its centre. The first frame is the steady state of
  // its input, so scene.npy's level (a mean of the same rays and more) stays close, edges differ.
  const auto ss = tmp / "street-ss";
  REQUIRE(run_bolo({"simulate", "--out", ss.string(), "--scene", "street", "--trajectory", "drive", "--size", "64x48",
                    "--frames", "1", "--fps", "60", "--tau", "0.010", "--noise", "0", "--seed", "1", "--supersample", "3"})
              .code == 0);
  rec::Recording ss_rec(ss);
  std::vector<float> one_ray(64 * 48), area(64 * 48);
  rec.read_scene(0, one_ray);
  ss_rec.read_scene(0, area);
  double mean_one = 0, mean_area = 0, differ = 0;
  for (std::size_t k = 0; k < area.size(); ++k)
    mean_one += one_ray[k], mean_area += area[k], differ += std::fabs(area[k] - one_ray[k]) > 1.0f;
  CHECK(std::fabs(mean_one - mean_area) / static_cast<double>(area.size()) < 40.0);  // within a kelvin on average
  CHECK(differ > 0.05 * static_cast<double>(area.size()));
  CHECK(ss_rec.info().source.find("3x3 rays per pixel") != std::string::npos);
  CHECK(run_bolo({"simulate", (tmp / "x").string(), "--scene", "street", "--trajectory", "warp"}).code == 2);
  CHECK(run_bolo({"simulate", (tmp / "y").string(), "--scene", "street", "--trajectory", "blackbody"}).err.find("laid out for the lab scene") != std::string::npos);
}

TEST_CASE("simulate's help and its unknown-trajectory error list every trajectory the scene library has", "[cli][simulate]") {
  const CliResult help = run_bolo({"simulate", "--help"});
  REQUIRE(help.code == 0);
  const auto tmp = std::filesystem::temp_directory_path() / "bolo_cli_trajectory_names";
  std::filesystem::remove_all(tmp);
  const CliResult refused = run_bolo({"simulate", (tmp / "x").string(), "--scene", "street", "--trajectory", "warp"});
  CHECK(refused.code == 2);
  CHECK_FALSE(std::filesystem::exists(tmp / "x"));
  for (const auto& name : sim::scene::trajectory_names()) {
    INFO(name);
    CHECK(help.out.find(name) != std::string::npos);
    CHECK(refused.err.find(name) != std::string::npos);
  }
}

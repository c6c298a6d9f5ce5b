// bolo simulate OUT: a recording with known physics: a scene seen through the continuous-time
// bolometer model, any catalogue effects, noise and quantisation (sim/simulator), written in the
// shared format with scene.npy (the steady-state input) and truth/ (parameters and maps).

#include <cmath>
#include <memory>
#include <sstream>
#include <vector>

#include <fstream>

#include <nlohmann/json.hpp>

#include "bolo/commands.hpp"
#include "bolo/diagnose/simulator_config.hpp"
#include "bolo/errors.hpp"
#include "bolo/progress.hpp"
#include "bolo/recording/recording.hpp"
#include "bolo/registry.hpp"
#include "bolo/sim/demo_scene.hpp"
#include "bolo/sim/sensor_preset.hpp"
#include "bolo/sim/simulator.hpp"
#include "bolo/simulate_scene.hpp"

namespace bolo::cli {
namespace {

void parse_size(const std::string& text, std::uint32_t& width, std::uint32_t& height) {
  unsigned w = 0, h = 0;
  char x = 0, extra = 0;
  std::istringstream in(text);
  if (!(in >> w >> x >> h) || (x != 'x' && x != 'X') || (in >> extra))
    fail("--size: expected WIDTHxHEIGHT such as 160x120, got '", text, "'");
  if (w < 8 || h < 8 || w > 4096 || h > 4096)
    fail("--size: ", w, "x", h, " is outside 8x8 .. 4096x4096");
  width = w;
  height = h;
}

void require_positive(const char* flag, double value) {
  if (!std::isfinite(value) || value <= 0) fail(flag, ": must be a positive number, got ", value);
}

// The frame's timing: --lag, then exposure, readout, their schedule and jitter.
void resolve_timing(const SimulateOptions& o, sim::SimulatorConfig& c) {
  sim::SimulationInfo& i = c.info;
  const double period = 1.0 / i.fps;
  if (o.lag == "continuous") {
    // The pixel relaxes through the whole period: the two-frame model's t_e = t_r = the period.
    if (o.exposure_s || o.readout_s) fail("--exposure, --readout: not with --lag continuous (both are the frame period)");
    if (o.alternate_every > 0 || o.alternate_exposure_s || o.timing_jitter != 0)
      fail("--alternate-exposure, --alternate-every, --timing-jitter: not with --lag continuous");
    if (i.tau_h_s != i.tau_c_s)
      fail("--tau-h ", i.tau_h_s, " s and --tau-c ", i.tau_c_s, " s: --lag continuous has one time constant (--tau)");
    c.lag = sim::PixelLag::continuous;
    i.exposure_s = i.readout_s = period;
    return;
  }
  if (o.lag != "exposure-readout") fail("--lag: expected exposure-readout or continuous, got '", o.lag, "'");
  i.exposure_s = o.exposure_s.value_or(0.5 * period);
  require_positive("--exposure", i.exposure_s);
  i.readout_s = o.readout_s.value_or(period - i.exposure_s);
  if (!std::isfinite(i.readout_s) || i.readout_s < 0)
    fail("--readout: must be >= 0, got ", i.readout_s, " (exposure ", i.exposure_s, " s at ", i.fps, " fps)");
  if (i.exposure_s + i.readout_s > period * (1 + 1e-9))
    fail("--exposure + --readout: ", i.exposure_s + i.readout_s, " s do not fit one frame period (",
         period, " s at ", i.fps, " fps)");
  if (o.alternate_exposure_s.has_value() != (o.alternate_every > 0))
    fail("--alternate-exposure and --alternate-every: give both or neither");
  if (o.alternate_every > 0) {
    const double alternate = *o.alternate_exposure_s;
    require_positive("--alternate-exposure", alternate);
    if (alternate > i.exposure_s + i.readout_s * (1 + 1e-9))
      fail("--alternate-exposure: ", alternate, " s does not fit exposure + readout (", i.exposure_s + i.readout_s, " s)");
    c.exposure_schedule = {alternate, o.alternate_every};
  }
  if (!std::isfinite(o.timing_jitter) || o.timing_jitter < 0 || o.timing_jitter > 0.1)
    fail("--timing-jitter: must be 0..0.1 (a relative spread), got ", o.timing_jitter);
  c.timing_jitter = o.timing_jitter;
}

// Everything the simulator needs, resolved from the preset and the flags.
sim::SimulatorConfig resolve(const SimulateOptions& o, const sim::SensorPreset& preset) {
  sim::SimulatorConfig c;
  sim::SimulationInfo& i = c.info;
  i.width = preset.width;
  i.height = preset.height;
  if (o.size) parse_size(*o.size, i.width, i.height);
  i.fps = o.fps.value_or(preset.fps);
  require_positive("--fps", i.fps);
  i.tau_h_s = o.tau_h_s.value_or(o.tau_s.value_or(preset.tau_s));
  i.tau_c_s = o.tau_c_s.value_or(o.tau_s.value_or(preset.tau_s));
  require_positive(o.tau_h_s ? "--tau-h" : "--tau", i.tau_h_s);
  require_positive(o.tau_c_s ? "--tau-c" : "--tau", i.tau_c_s);
  resolve_timing(o, c);
  i.bits = o.bits.value_or(preset.bits);
  if (i.bits < 8 || i.bits > 16) fail("--bits: must be 8..16, got ", i.bits);
  i.reference_level = preset.level_300k * std::ldexp(1.0, static_cast<int>(i.bits) - 14);
  i.seed = o.seed;
  c.noise_counts = o.noise.value_or(preset.noise_counts);
  if (!std::isfinite(c.noise_counts) || c.noise_counts < 0) fail("--noise: must be >= 0, got ", c.noise_counts);
  c.noise_1f_counts = o.noise_1f;
  if (!std::isfinite(c.noise_1f_counts) || c.noise_1f_counts < 0) fail("--noise-1f: must be >= 0, got ", c.noise_1f_counts);
  if (o.substeps < 1 || o.substeps > 64) fail("--substeps: must be 1..64, got ", o.substeps);
  c.substeps = o.substeps;
  for (const std::string& e : o.effects) c.effects.push_back(sim::parse_effect(e));
  return c;
}

// --config FILE: every option the file sets and the command line does not.
void apply_simulate_config(const std::string& file, const CLI::App& app, SimulateOptions& o) {
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, ": cannot read the --config file");
  std::ostringstream text;
  text << in.rdbuf();
  std::vector<diag::ConfigEntry> entries;
  try {
    entries = diag::parse_simulator_config(text.str(), file);
  } catch (const std::runtime_error& e) {
    fail(e.what());
  }
  for (const diag::ConfigEntry& e : entries) {
    const std::string where = file + ": line " + std::to_string(e.line) + ": " + e.option;
    const CLI::Option* given = app.get_option_no_throw("--" + e.option);
    if (given && given->count() > 0) continue;  // the command line wins
    auto one = [&]() -> const std::string& {
      if (e.values.size() != 1) fail(where, ": expected one value, got ", e.values.size());
      return e.values[0];
    };
    auto number = [&]() {
      const std::string& v = one();
      std::size_t used = 0;
      double x = 0;
      try { x = std::stod(v, &used); } catch (const std::exception&) { used = 0; }
      if (used != v.size() || !std::isfinite(x)) fail(where, ": not a number: '", v, "'");
      return x;
    };
    auto count = [&]() {
      const double x = number();
      if (x < 0 || x != std::floor(x) || x > 1e12) fail(where, ": not a whole non-negative number");
      return x;
    };
    if (e.option == "size") o.size = one();
    else if (e.option == "fps") o.fps = number();
    else if (e.option == "frames") o.frames = static_cast<std::uint64_t>(count());
    else if (e.option == "tau") o.tau_s = number();
    else if (e.option == "tau-h") o.tau_h_s = number();
    else if (e.option == "tau-c") o.tau_c_s = number();
    else if (e.option == "exposure") o.exposure_s = number();
    else if (e.option == "readout") o.readout_s = number();
    else if (e.option == "alternate-exposure") o.alternate_exposure_s = number();
    else if (e.option == "alternate-every") o.alternate_every = static_cast<std::uint32_t>(std::min(count(), 1e6));
    else if (e.option == "timing-jitter") o.timing_jitter = number();
    else if (e.option == "noise") o.noise = number();
    else if (e.option == "noise-1f") o.noise_1f = number();
    else if (e.option == "bits") o.bits = static_cast<std::uint32_t>(count());
    else if (e.option == "lag") o.lag = one();
    else if (e.option == "substeps") o.substeps = static_cast<std::uint32_t>(std::min(count(), 1e6));
    else if (e.option == "seed") o.seed = static_cast<std::uint64_t>(count());
    else if (e.option == "preset") o.preset = one();
    else if (e.option == "scene") o.scene = one();
    else if (e.option == "trajectory") o.trajectory = one();
    else if (e.option == "effect") o.effects.insert(o.effects.end(), e.values.begin(), e.values.end());
    else fail(where, ": not an option of bolo simulate");
  }
}

}  // namespace

int run_simulate(const SimulateOptions& o, std::ostream& out) {
  if (o.output.empty()) fail("no output folder: give OUT or --out");
  if (o.frames == 0) fail("--frames: must be at least 1");
  const sim::SensorPreset& preset = sim::sensor_preset(o.preset);
  const sim::SimulatorConfig config = resolve(o, preset);
  const sim::SimulationInfo& i = config.info;
  if (o.supersample < 1 || o.supersample > 8) fail("--supersample: must be 1..8, got ", o.supersample);
  SimulatedScene scene = make_simulated_scene(o.scene, o.trajectory, preset, i, o.supersample, o.distortion);
  sim::Simulator simulator(config, scene.input);  // checks the effects before anything is written

  rec::RecordingInfo info;
  info.sensor = preset.sensor;
  info.width = i.width;
  info.height = i.height;
  info.bits = i.bits;
  info.fps = i.fps;
  info.units = rec::Units::counts;
  std::ostringstream source;
  source << "bolo simulate: scene " << o.scene << (scene.trajectory.empty() ? "" : ", trajectory " + scene.trajectory)
         << ", preset " << preset.name << ", tau_h " << i.tau_h_s << " s, tau_c " << i.tau_c_s
         << " s, noise " << config.noise_counts << " counts, seed " << o.seed;
  if (o.supersample > 1) source << ", " << o.supersample << "x" << o.supersample << " rays per pixel";
  if (config.exposure_schedule.every_frames > 0)
    source << ", exposure alternating with " << config.exposure_schedule.alternate_exposure_s << " s every "
           << config.exposure_schedule.every_frames << " frames";
  if (config.lag == sim::PixelLag::continuous) source << ", continuous lag through the frame period";
  if (config.timing_jitter > 0) source << ", exposure and readout jittered by " << config.timing_jitter << " (relative)";
  if (!o.distortion.empty()) {
    source << ", lens distortion";
    for (std::size_t k = 0; k < o.distortion.size(); ++k) source << (k ? "," : " ") << o.distortion[k];
  }
  for (const auto& e : o.effects) source << ", effect " << e;
  info.source = source.str();
  info.notes = "scene.npy holds the steady-state input; truth/ the model, its parameters and maps";

  rec::RecordingWriter writer(o.output, info, {.overwrite = o.overwrite});
  if (scene.camera) writer.set_camera(*scene.camera);
  std::string poses;
  sim::SimulatedFrame frame;
  Progress progress("simulate", o.frames, o.progress);
  for (std::uint64_t n = 0; n < o.frames; ++n) {
    simulator.next(frame);
    writer.append(frame.counts, frame.row);
    writer.append_scene(frame.scene);
    if (scene.pose_line) poses += scene.pose_line(frame.pose_t_s);
    progress.update(n + 1);
  }
  progress.finish();
  if (!poses.empty()) writer.add_file("poses.tum", poses);
  nlohmann::json truth = simulator.truth();
  truth["scene"] = {{"name", o.scene}, {"trajectory", scene.trajectory}, {"preset", preset.name},
                    {"counts_per_kelvin", preset.counts_per_kelvin}};
  writer.add_file("truth/effects.json", truth.dump(2) + "\n");
  for (const auto& [name, values] : simulator.truth_maps()) {
    std::vector<std::uint64_t> shape;
    if (values.size() == std::size_t{i.width} * i.height) shape = {i.height, i.width};
    else shape = {values.size()};
    writer.add_file("truth/" + name + ".npy", rec::encode_npy_f4(shape, values));
  }
  writer.commit();
  out << "simulate: wrote " << o.output.string() << ": " << o.frames << " frames of " << i.width << "x"
      << i.height << " at " << i.fps << " fps (" << preset.name << ", scene " << o.scene
      << (scene.trajectory.empty() ? "" : ", " + scene.trajectory) << "), tau_h " << i.tau_h_s
      << " s, tau_c " << i.tau_c_s << " s, exposure " << i.exposure_s << " s, readout " << i.readout_s << " s";
  if (config.exposure_schedule.every_frames > 0)
    out << " (exposure " << config.exposure_schedule.alternate_exposure_s << " s every other "
        << config.exposure_schedule.every_frames << " frames)";
  out << ", " << o.effects.size() << " effect(s)\n";
  return kExitOk;
}

Command add_simulate_command(CLI::App& parent) {
  auto o = std::make_shared<SimulateOptions>();
  auto out_flag = std::make_shared<std::string>();
  CLI::App* app = add_command(
      parent, "simulate", "Simulate a microbolometer recording with known physics (scene, tau, effects, noise)",
      "Renders a scene, runs it through the continuous-time bolometer model (the paper's two-frame\n"
      "model for an input constant within a frame; motion within the exposure sampled at --substeps;\n"
      "--lag continuous: a first-order lag through the whole frame period),\n"
      "adds the chosen effects of the catalogue (--effect ID:KEY=VALUE,..., repeatable; ids:\n"
      "rolling_readout tau_spread tau_temperature thermal_memory crosstalk nonlinearity gain_fpn\n"
      "offset_fpn column_fpn row_fpn shading ffc_step fpa_drift temporal_filter agc dead_pixels\n"
      "frame_duplication), white and 1/f noise and quantisation. Writes frames.npy, frames.csv\n"
      "(exposure, readout, shutter flags, FPA temperature), scene.npy, camera.json and poses.tum for\n"
      "3D scenes, and truth/ (effects.json, per-pixel maps as .npy).\n"
      "Example: bolo simulate out/sim --effect thermal_memory:tau2_s=0.2,weight=0.03 --effect ffc_step:every=100");
  app->add_option("OUT", o->output, "Recording folder to write");
  app->add_option("--out", *out_flag, "Recording folder to write (same as OUT)");
  app->add_option("--preset", o->preset, "Sensor preset: generic, lepton3, boson320, boson640, tau2")->capture_default_str();
  app->add_option("--scene", o->scene, "Scene: " + simulated_scene_names())->capture_default_str();
  app->add_option("--trajectory", o->trajectory, "Camera trajectory for 3D scenes: " + simulated_trajectory_names());
  // Unsigned options take "-3" as a huge number unless the text is checked first.
  app->add_option("--frames", o->frames, "Number of frames")
      ->check(not_negative())->capture_default_str();
  app->add_option("--size", o->size, "Frame size WIDTHxHEIGHT (default: the preset's)");
  app->add_option("--fps", o->fps, "Frame rate (default: the preset's)");
  app->add_option("--tau", o->tau_s, "Thermal time constant for heating and cooling, seconds (default: the preset's)");
  app->add_option("--tau-h", o->tau_h_s, "Heating time constant, seconds (overrides --tau)");
  app->add_option("--tau-c", o->tau_c_s, "Cooling time constant, seconds (overrides --tau)");
  app->add_option("--exposure", o->exposure_s, "Exposure time t_e, seconds (default: half the frame period)");
  app->add_option("--readout", o->readout_s, "Readout time t_r, seconds (default: frame period - exposure)");
  app->add_option("--alternate-exposure", o->alternate_exposure_s,
                  "With --alternate-every: the exposure switches between --exposure and this, seconds; the readout "
                  "takes up the difference (a camera changing its integration time at a fixed frame rate)");
  app->add_option("--alternate-every", o->alternate_every, "Frames between exposure switches (with --alternate-exposure)")
      ->check(not_negative());
  app->add_option("--timing-jitter", o->timing_jitter,
                  "Each frame's exposure and readout scaled by 1 + J z, z ~ N(0,1) cut at +-3, as frames.csv records "
                  "them; the frame interval follows (0..0.1)")
      ->capture_default_str();
  app->add_option("--noise", o->noise, "White temporal noise, standard deviation in counts (default: the preset's)");
  app->add_option("--noise-1f", o->noise_1f, "1/f temporal noise, standard deviation in counts")->capture_default_str();
  app->add_option("--bits", o->bits, "Sensor bit depth 8..16 (default: the preset's)")->check(not_negative());
  app->add_option("--lag", o->lag,
                  "How a pixel forms its reading: exposure-readout (heats during --exposure, then only cools over "
                  "--readout; t_s is the exposure's start, the pose its middle) or continuous (a first-order lag "
                  "with --tau through the whole frame period while the scene moves, read at its end, which is t_s "
                  "and the pose's time; frames.csv records exposure = readout = the period, the two-frame model's "
                  "exact coefficients for it)")
      ->capture_default_str();
  app->add_option("--substeps", o->substeps, "Scene samples per exposure, or per period with --lag continuous (motion within a frame), 1 to 64")
      ->check(not_negative())->capture_default_str();
  app->add_option("--supersample", o->supersample,
                  "3D scenes: N x N rays per pixel, averaged (the pixel's area; 1 = one ray through its centre, aliased), 1 to 8")
      ->check(not_negative())->capture_default_str();
  app->add_option("--distortion", o->distortion,
                  "3D scenes: lens distortion K1[,K2[,P1[,P2[,K3[,K4,K5,K6]]]]] (OpenCV's order and rational model, as camera.json records it; "
                  "e.g. -0.2,0.04 for a barrel lens)")
      ->delimiter(',');
  app->add_option("--effect", o->effects, "Catalogue effect ID[:KEY=VALUE,...]; repeatable");
  app->add_option("--seed", o->seed, "Seed of noise, maps and scene")->check(not_negative())->capture_default_str();
  app->add_flag("--overwrite", o->overwrite, "Replace OUT if it is a recording");
  auto config = std::make_shared<std::string>();
  app->add_option("--config", *config,
                  "Options from FILE, `option = value` per line (the simulate.cfg of `bolo diagnose`); flags given win");
  return {app, [o, out_flag, config, app](std::ostream& out) {
            if (!config->empty()) apply_simulate_config(*config, *app, *o);
            if (!out_flag->empty()) {
              if (!o->output.empty() && o->output != *out_flag)
                fail("OUT ", o->output.string(), " and --out ", *out_flag, ": give one");
              o->output = *out_flag;
            }
            return run_simulate(*o, out);
          }};
}

}  // namespace bolo::cli

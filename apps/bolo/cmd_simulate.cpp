// bolo simulate OUT: a recording with known ghosting, made by the paper's discrete sensor model
// run forward over a moving demo scene. The small stand-in for the full simulator, and what the
// set-up command corrects where ../shared/data is absent.

#include <cmath>
#include <memory>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "bolo/commands.hpp"
#include "bolo/errors.hpp"
#include "bolo/progress.hpp"
#include "bolo/recording/recording.hpp"
#include "bolo/registry.hpp"
#include "bolo/sim/demo_scene.hpp"
#include "bolo/sim/two_frame_sensor.hpp"

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

}  // namespace

int run_simulate(const SimulateOptions& o, std::ostream& out) {
  std::uint32_t width = 0, height = 0;
  parse_size(o.size, width, height);
  require_positive("--fps", o.fps);
  require_positive("--tau-h", o.tau_h_s);
  require_positive("--tau-c", o.tau_c_s);
  if (o.frames == 0) fail("--frames: must be at least 1");
  if (o.bits < 8 || o.bits > 16) fail("--bits: must be 8..16, got ", o.bits);
  if (!std::isfinite(o.noise) || o.noise < 0) fail("--noise: must be >= 0, got ", o.noise);
  const double period = 1.0 / o.fps;
  const double exposure = o.exposure_s.value_or(0.5 * period);
  const double readout = o.readout_s.value_or(period - exposure);
  require_positive("--exposure", exposure);
  if (!std::isfinite(readout) || readout < 0)
    fail("--readout: must be >= 0, got ", readout, " (exposure ", exposure, " s at ", o.fps, " fps)");

  rec::RecordingInfo info;
  info.sensor = "bolo simulate: two-frame microbolometer model";
  info.width = width;
  info.height = height;
  info.bits = o.bits;
  info.fps = o.fps;
  info.units = rec::Units::counts;
  std::ostringstream source;
  source << "bolo simulate, demo scene, tau_h " << o.tau_h_s << " s, tau_c " << o.tau_c_s
         << " s, exposure " << exposure << " s, readout " << readout << " s, noise " << o.noise
         << " counts, seed " << o.seed;
  info.source = source.str();
  info.notes = "scene.npy holds the steady-state input; truth/parameters.json the model parameters";

  rec::RecordingWriter writer(o.output, info, {.overwrite = o.overwrite});
  sim::TwoFrameSensor::Options sensor_options;
  sensor_options.tau_h_s = o.tau_h_s;
  sensor_options.tau_c_s = o.tau_c_s;
  sensor_options.noise_counts = o.noise;
  sensor_options.bits = o.bits;
  sensor_options.seed = o.seed;
  sim::TwoFrameSensor sensor(width, height, sensor_options);

  // Scene levels scaled to the sensor's range, so 8- to 16-bit sensors all see a usable scene.
  const double full = std::ldexp(1.0, static_cast<int>(o.bits)) - 1.0;
  sim::DemoSceneOptions scene_options;
  scene_options.background = 0.37 * full;
  scene_options.gradient = 0.05 * full;
  scene_options.bar_contrast = -0.04 * full;
  scene_options.hot_contrast = 0.25 * full;
  scene_options.speed_px_per_s = 2.0 * width;  // two widths a second: strong ghosting

  std::vector<float> scene(std::size_t{width} * height);
  std::vector<std::uint16_t> frame(scene.size());
  Progress progress("simulate", o.frames, o.progress);
  for (std::uint64_t i = 0; i < o.frames; ++i) {
    const double t = static_cast<double>(i) * period;
    sim::render_demo_scene(width, height, t, scene_options, scene);
    const bool ffc = o.ffc_every > 0 && i > 0 && i % o.ffc_every == 0;
    sensor.expose(scene, {exposure, readout}, i == 0 || ffc, frame);
    rec::FrameRow row;
    row.index = i;
    row.t_s = t;
    row.exposure_s = exposure;
    row.readout_s = readout;
    row.ffc = ffc;
    writer.append(frame, row);
    writer.append_scene(scene);
    progress.update(i + 1);
  }
  progress.finish();
  const nlohmann::json truth = {{"model", "two_frame"},         {"tau_h_s", o.tau_h_s},
                                {"tau_c_s", o.tau_c_s},         {"exposure_s", exposure},
                                {"readout_s", readout},         {"noise_counts", o.noise},
                                {"seed", o.seed},               {"ffc_every", o.ffc_every}};
  writer.add_file("truth/parameters.json", truth.dump(2) + "\n");
  writer.commit();
  out << "simulate: wrote " << o.output.string() << ": " << o.frames << " frames of " << width
      << "x" << height << " at " << o.fps << " fps, tau_h " << o.tau_h_s << " s, tau_c "
      << o.tau_c_s << " s, exposure " << exposure << " s, readout " << readout << " s\n";
  return kExitOk;
}

Command add_simulate_command(CLI::App& parent) {
  auto o = std::make_shared<SimulateOptions>();
  CLI::App* app = add_command(
      parent, "simulate", "Make a recording with known ghosting (two-frame sensor model, demo scene)",
      "Runs the paper's discrete microbolometer model forward,\n"
      "  I_i = I_ss,i (1 - exp(-t_e/tau_h)) + I_{i-1} exp(-t_r/tau_c),\n"
      "over a moving demo scene (warm gradient, cool bars, a hot disc crossing the view), with white\n"
      "noise and quantisation. Writes frames.npy, frames.csv (with exposure/readout), scene.npy\n"
      "(the steady-state input) and truth/parameters.json. `bolo correct` with the same tau\n"
      "restores scene.npy.");
  app->add_option("OUT", o->output, "Recording folder to write")->required();
  app->add_option("--frames", o->frames, "Number of frames")->capture_default_str();
  app->add_option("--size", o->size, "Frame size WIDTHxHEIGHT")->capture_default_str();
  app->add_option("--fps", o->fps, "Frame rate")->capture_default_str();
  app->add_option("--tau-h", o->tau_h_s, "Heating time constant, seconds")->capture_default_str();
  app->add_option("--tau-c", o->tau_c_s, "Cooling time constant, seconds")->capture_default_str();
  app->add_option("--exposure", o->exposure_s, "Exposure time t_e, seconds (default: half the frame period)");
  app->add_option("--readout", o->readout_s, "Readout time t_r, seconds (default: frame period - exposure)");
  app->add_option("--noise", o->noise, "White temporal noise, standard deviation in counts")->capture_default_str();
  app->add_option("--bits", o->bits, "Sensor bit depth (8..16)")->capture_default_str();
  app->add_option("--ffc-every", o->ffc_every, "A shutter event every N frames (0: none)")->capture_default_str();
  app->add_option("--seed", o->seed, "Noise seed")->capture_default_str();
  app->add_flag("--overwrite", o->overwrite, "Replace OUT if it is a recording");
  return {app, [o](std::ostream& out) { return run_simulate(*o, out); }};
}

}  // namespace bolo::cli

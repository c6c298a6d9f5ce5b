// The frame loop of `bolo correct`: the recording player -> CorrectionChain (Pipeline ([bad
// pixels] -> two-frame corrector), with --float the reference beside it) -> RecordingWriter.

#include "bolo/correct/correct_recording.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "bolo/hal/recording_player.hpp"
#include "bolo/hal/source_registry.hpp"
#include "corrected_output.hpp"
#include "correction_chain.hpp"
#include "fail.hpp"
#include "frame_timing.hpp"

namespace bolo::correct {
namespace {

namespace fs = std::filesystem;

// The recording folder the input names; the output copies the recording's rows, camera, poses
// and scene, so other sources are refused.
fs::path recording_folder(const CorrectRequest& o) {
  try {
    return hal::recording_folder_of(o.input.string(), "correct");
  } catch (const hal::SourceError& e) {
    fail(e.what());
  }
}

}  // namespace

std::string seconds_text(double seconds) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.9g", seconds);
  return buffer;
}

CorrectResult correct_recording(const CorrectRequest& request, std::span<FrameObserver* const> observers) {
  CorrectRequest o = request;
  if (!o.output.empty() && !o.output.has_filename()) o.output = o.output.parent_path();  // "out/"
  // 1. Flags.
  const fw::TimeConstants tau{flag_ns("--tau-h", o.tau_h_s), flag_ns("--tau-c", o.tau_c_s)};
  Defaults exposure, readout;
  if (o.exposure_s) exposure = {o.exposure_s, flag_ns("--exposure", *o.exposure_s)};
  if (o.readout_s) readout = {o.readout_s, flag_ns("--readout", *o.readout_s)};
  std::uint32_t nominal_period_ns = 0;
  if (o.nominal_fps) {
    if (!std::isfinite(*o.nominal_fps) || !(*o.nominal_fps > 0.25) || *o.nominal_fps > 1e6)
      fail("--nominal-fps ", seconds_text(*o.nominal_fps), ": must be a frame rate between 0.25 and 1e6");
    nominal_period_ns = static_cast<std::uint32_t>(std::lround(1e9 / *o.nominal_fps));
  }
  // 2. Files: the source is opened once; the player validates the whole recording.
  const fs::path dir = recording_folder(o);
  check_output(o, dir);
  const std::unique_ptr<hal::OpenedSource> source = hal::open_source("file:" + dir.string());
  auto& player = dynamic_cast<hal::RecordingPlayer&>(source->backend());
  const rec::Recording& recording = player.recording();
  const fs::path csv = dir / "frames.csv";
  const hal::SourceFormat format = player.format();
  const std::uint32_t width = format.width, height = format.height;
  if (recording.frame_count() == 0) fail(csv.string(), ": no frames");
  // 3. Timing and coefficients of every frame.
  const std::vector<FrameTiming> timing = resolve_timing(recording, player.headers(), csv, exposure, readout);
  check_coefficients(timing, tau, o, csv);

  // 4. The pipeline.
  fw::PipelineConfig config;
  config.corrector.width = width;
  config.corrector.height = height;
  config.corrector.tau = tau;
  config.corrector.default_exposure_ns = exposure.ns;
  config.corrector.default_readout_ns = readout.ns;
  config.corrector.nominal_frame_period_ns = nominal_period_ns;
  config.use_bad_pixels = o.bad_pixels;
  const std::uint32_t bits = format.bits;
  config.bad_pixels.stuck_high =
      static_cast<fw::Pixel>(bits >= 16 || bits == 0 ? 0xFFFFu : (1u << bits) - 1u);
  config.bad_pixels.width = width;
  config.bad_pixels.height = height;
  CorrectionChain chain(config, o, o.input.string());

  // 5. Run, frame by frame, into the atomic writer; scene.npy (a simulation's steady-state input)
  // still describes the same frames and goes along.
  rec::RecordingWriter writer(o.output, corrected_info(recording.info(), o),
                              {o.overwrite, o.float_output ? rec::DType::f4 : rec::DType::u2});
  std::vector<float> scene(recording.has_scene() ? std::size_t{width} * height : 0);
  std::vector<FrameStats> stats;
  stats.reserve(timing.size());
  for (FrameObserver* observer : observers) observer->on_begin(timing.size());
  const auto start = std::chrono::steady_clock::now();
  for (std::uint64_t i = 0; i < timing.size(); ++i) {
    if (source->stream_frame(chain.input()) != hal::StreamStatus::frame)
      fail(o.input.string(), ": frame ", i, ": the player delivered no frame");
    const FrameStats s = chain.finish_frame(i, recording.rows()[i], timing, writer);
    if (!scene.empty()) {
      player.read_scene(i, scene);
      writer.append_scene(scene);
    }
    stats.push_back(s);
    for (FrameObserver* observer : observers) observer->on_frame(s);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  if (recording.camera()) writer.set_camera(*recording.camera());
  if (fs::exists(dir / "poses.tum")) writer.add_file("poses.tum", read_whole_file(dir / "poses.tum"));

  // 6. Stats first (atomic), then the recording; if the commit fails, the stats go too.
  if (o.stats) rec::write_file_atomically(*o.stats, stats_csv(stats));
  try {
    writer.commit();
  } catch (...) {
    if (o.stats) {
      std::error_code ec;
      fs::remove(*o.stats, ec);
    }
    throw;
  }
  return {timing.size(), seconds};
}

}  // namespace bolo::correct

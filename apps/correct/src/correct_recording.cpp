// The frame loop of `bolo correct`: the recording player -> [Tee ->] Pipeline ([bad pixels] ->
// two-frame corrector) -> FrameCollector -> RecordingWriter; with --float the double-precision
// reference gets the raw frames (after bad-pixel replacement when asked) and writes the pixels,
// the pipeline still making the per-frame decisions.

#include "bolo/correct/correct_recording.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "bolo/core/frame_collector.hpp"
#include "bolo/firmware/pipeline.hpp"
#include "bolo/hal/recording_player.hpp"
#include "bolo/hal/source_registry.hpp"
#include "bolo/sim/corrector_reference.hpp"
#include "corrected_output.hpp"
#include "fail.hpp"
#include "frame_timing.hpp"

namespace bolo::correct {
namespace {

namespace fs = std::filesystem;

// Forwards every event to two sinks.
class Tee final : public fw::LineSink {
 public:
  Tee(fw::LineSink& a, fw::LineSink& b) : a_(a), b_(b) {}
  void begin_frame(const fw::FrameHeader& h) override {
    a_.begin_frame(h);
    b_.begin_frame(h);
  }
  void push_line(std::uint32_t row, fw::LineView line) override {
    a_.push_line(row, line);
    b_.push_line(row, line);
  }
  void end_frame() override {
    a_.end_frame();
    b_.end_frame();
  }

 private:
  fw::LineSink& a_;
  fw::LineSink& b_;
};

// The recording folder the input names: a bare folder or file:REC. Other sources are refused, as
// the output copies the recording's rows, camera, poses and scene.
fs::path recording_folder(const CorrectRequest& o) {
  hal::SourceSpec spec;
  try {
    spec = hal::parse_source_spec(o.input.string());
  } catch (const hal::SourceError& e) {
    fail(e.what());
  }
  if (spec.backend.scheme != "file")
    fail(o.input.string(), ": bolo correct takes a recording (a folder or file:REC); record ",
         spec.backend.scheme, " with `bolo capture` first");
  const fs::path dir = spec.argument;
  std::error_code ec;
  if (!fs::exists(dir, ec)) fail(dir.string(), ": no such recording folder");
  if (!fs::is_directory(dir, ec))
    fail(dir.string(), ": not a folder (a recording is a folder with recording.json, frames.npy, frames.csv)");
  return dir;
}

double q24(std::uint32_t value) { return std::ldexp(static_cast<double>(value), -int{fw::kCoefficientFractionBits}); }

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
  std::vector<fw::Pixel> arena(fw::Pipeline::arena_pixels(config));
  std::vector<fw::Pixel> corrected_storage(fw::FrameCollector::storage_pixels(width, height));
  fw::FrameCollector corrected(width, height, corrected_storage);
  fw::Pipeline pipeline(config, arena, corrected);

  std::vector<fw::Pixel> raw_storage(fw::FrameCollector::storage_pixels(width, height));
  fw::FrameCollector raw(width, height, raw_storage);
  std::vector<fw::Pixel> float_bad_storage;
  std::optional<fw::BadPixelStage> float_bad_pixels;
  std::optional<sim::ReferenceCorrector> reference;
  std::optional<Tee> tee;
  std::vector<double> reference_out;
  std::vector<float> float_frame;
  if (o.float_output) {
    fw::LineSink* reference_input = &raw;
    if (o.bad_pixels) {
      float_bad_storage.resize(fw::BadPixelStage::storage_pixels(width, height));
      float_bad_pixels.emplace(config.bad_pixels, float_bad_storage, raw);
      reference_input = &*float_bad_pixels;
    }
    tee.emplace(pipeline.input(), *reference_input);
    std::optional<double> nominal_period_s;
    if (o.nominal_fps) nominal_period_s = 1.0 / *o.nominal_fps;
    reference.emplace(width, height, o.tau_h_s, o.tau_c_s, o.exposure_s, o.readout_s, nominal_period_s);
    reference_out.resize(std::size_t{width} * height);
    float_frame.resize(reference_out.size());
  }
  fw::LineSink& input = tee ? static_cast<fw::LineSink&>(*tee) : pipeline.input();

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
    if (source->stream_frame(input) != hal::StreamStatus::frame)
      fail(o.input.string(), ": frame ", i, ": the player delivered no frame");
    if (!corrected.complete()) fail(o.input.string(), ": frame ", i, ": the pipeline delivered an incomplete frame");
    const rec::FrameRow& row = recording.rows()[i];
    const fw::CorrectorFrameStats& cs = pipeline.corrector().last_frame();
    FrameStats s;
    s.frame = i;
    s.carry_over = cs.carry_over;
    s.coefficient_status = cs.coefficient_status;
    s.gain = q24(cs.coefficients.gain_q24);
    s.carry = q24(cs.coefficients.carry_q24);
    s.saturated_low = cs.saturated_low;
    s.saturated_high = cs.saturated_high;
    s.exposure_from_flag = timing[i].exposure_from_flag;
    s.readout_from_flag = timing[i].readout_from_flag;
    if (const fw::BadPixelStage* bad = pipeline.bad_pixels()) {
      s.bad_pixels_replaced = bad->last_frame().replaced;
      s.bad_pixels_unrepairable = bad->last_frame().unrepairable;
    }
    if (reference) {
      if (!raw.complete()) fail(o.input.string(), ": frame ", i, ": incomplete frame for the reference");
      const sim::ReferenceFrameInfo info{row.index, row.t_s, timing[i].exposure_s,
                                         timing[i].readout_s, row.ffc.value_or(false)};
      const bool applied = reference->process(info, raw.pixels(), reference_out);
      s.reference_disagrees = applied != (s.carry_over == fw::CarryOver::applied);
      const double g = 1.0 / (1.0 - std::exp(-timing[i].exposure_s / o.tau_h_s));
      s.gain = g;
      s.carry = applied ? g * std::exp(-timing[i - 1].readout_s / o.tau_c_s) : 0.0;
      s.saturated_low = s.saturated_high = 0;
      for (std::size_t p = 0; p < reference_out.size(); ++p) {
        float_frame[p] = static_cast<float>(reference_out[p]);
        s.saturated_low += reference_out[p] <= 0.0;
        s.saturated_high += reference_out[p] >= 65535.0;
      }
      writer.append(std::span<const float>(float_frame), row);
    } else {
      writer.append(corrected.pixels(), row);
    }
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

// The frame loop of `bolo correct`: a source -> CorrectionChain (Pipeline ([bad pixels] ->
// two-frame corrector), with --float the reference beside it) -> RecordingWriter. A recording
// (a folder, file:REC) is checked whole before anything runs and its rows, camera, poses and
// scene go along; a live source (a camera, a transfer log) is corrected frame by frame as it
// delivers, its faulted frames skipped and counted.

#include "bolo/correct/correct_recording.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "bolo/correct/source_correction.hpp"
#include "bolo/hal/recording_player.hpp"
#include "bolo/hal/source_registry.hpp"
#include "corrected_output.hpp"
#include "correction_chain.hpp"
#include "bolo/correct/fail.hpp"
#include "frame_timing.hpp"

namespace bolo::correct {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// Stats first (atomic), then the recording; if the commit fails, the stats go too.
void commit(const CorrectRequest& o, const std::vector<FrameStats>& stats, rec::RecordingWriter& writer) {
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
}

void deliver(std::span<FrameObserver* const> observers, const FrameStats& s, std::vector<FrameStats>& stats) {
  stats.push_back(s);
  for (FrameObserver* observer : observers) observer->on_frame(s);
}

CorrectResult correct_recording_folder(const CorrectRequest& o, const Setup& setup,
                                       std::span<FrameObserver* const> observers) {
  // The source is opened once; the player validates the whole recording.
  fs::path dir;
  try {
    dir = hal::recording_folder_of(o.input.string(), "correct");
  } catch (const hal::SourceError& e) {
    fail(e.what());
  }
  check_output(o, dir);
  const std::unique_ptr<hal::OpenedSource> source = hal::open_source("file:" + dir.string());
  auto& player = dynamic_cast<hal::RecordingPlayer&>(source->backend());
  const rec::Recording& recording = player.recording();
  const fs::path csv = dir / "frames.csv";
  const hal::SourceFormat format = player.format();
  if (recording.frame_count() == 0) fail(csv.string(), ": no frames");
  // Timing and coefficients of every frame to be corrected.
  std::span<const fw::FrameHeader> headers = player.headers();
  if (o.frames) headers = headers.first(std::min<std::size_t>(headers.size(), *o.frames));
  const std::vector<FrameTiming> timing = resolve_timing(recording, headers, csv, setup.exposure, setup.readout);
  check_coefficients(timing, setup.tau, o, csv);
  CorrectionChain chain(pipeline_config(setup, format, o.bad_pixels, o.input.string()), o, o.input.string());

  // Frame by frame into the atomic writer; scene.npy (a simulation's steady-state input) still
  // describes the same frames and goes along.
  rec::RecordingWriter writer(o.output, corrected_info(recording.info(), o, false),
                              {o.overwrite, o.float_output ? rec::DType::f4 : rec::DType::u2});
  std::vector<float> scene(recording.has_scene() ? std::size_t{format.width} * format.height : 0);
  std::vector<FrameStats> stats;
  stats.reserve(timing.size());
  for (FrameObserver* observer : observers) observer->on_begin(timing.size());
  const auto start = Clock::now();
  for (std::uint64_t i = 0; i < timing.size(); ++i) {
    if (source->stream_frame(chain.input()) != hal::StreamStatus::frame)
      fail(o.input.string(), ": frame ", i, ": the player delivered no frame");
    const FrameStats s = chain.finish_frame(i, recording.rows()[i], timing[i], i == 0 ? nullptr : &timing[i - 1]);
    chain.append(writer, recording.rows()[i]);
    if (!scene.empty()) {
      player.read_scene(i, scene);
      writer.append_scene(scene);
    }
    deliver(observers, s, stats);
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (recording.camera()) writer.set_camera(*recording.camera());
  if (fs::exists(dir / "poses.tum")) writer.add_file("poses.tum", read_whole_file(dir / "poses.tum"));
  commit(o, stats, writer);
  CorrectResult result;
  result.frames = timing.size();
  result.seconds = seconds;
  return result;
}

// A live source: what it knows of itself goes into recording.json, its fault counters into
// capture.json (as `bolo capture` writes them); frames.csv from each frame's header.
CorrectResult correct_live_source(const CorrectRequest& o, const hal::SourceSpec& spec,
                                  std::span<FrameObserver* const> observers) {
  const std::string name = o.input.string();
  if (!spec.backend.finite && !o.frames) fail("--frames: required for a live camera (", name, ")");
  check_output(o, {});
  std::unique_ptr<hal::OpenedSource> source;
  try {
    source = hal::open_source(name);
  } catch (const hal::SourceError& e) {
    fail(e.what());
  }
  SourceCorrection correction(o, *source);
  rec::RecordingWriter writer(o.output, correction.corrected_info(),
                              {o.overwrite, o.float_output ? rec::DType::f4 : rec::DType::u2});
  std::vector<FrameStats> stats;
  for (FrameObserver* observer : observers) observer->on_begin(o.frames.value_or(0));
  const auto start = Clock::now();
  while (!o.frames || correction.frames() < *o.frames) {
    const SourceCorrection::Next next = correction.next();
    if (next == SourceCorrection::Next::ended) break;
    if (next == SourceCorrection::Next::gave_up)
      fail(name, ": gave up after ", o.max_faults, " faults in a row, ", correction.frames(),
           " frames corrected, nothing written (", correction.faults(), ")");
    correction.append(writer);
    deliver(observers, correction.stats(), stats);
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (correction.frames() == 0) fail(name, ": delivered no frames, nothing written");
  writer.add_file("capture.json", correction.capture_json());
  commit(o, stats, writer);
  CorrectResult result;
  result.frames = correction.frames();
  result.seconds = seconds;
  result.live = true;
  result.faults = correction.faults();
  result.skipped = correction.skipped();
  return result;
}

}  // namespace

void check_flags(const CorrectRequest& request) { (void)checked_setup(request); }

std::string seconds_text(double seconds) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.9g", seconds);
  return buffer;
}

CorrectResult correct_recording(const CorrectRequest& request, std::span<FrameObserver* const> observers) {
  CorrectRequest o = request;
  if (!o.output.empty() && !o.output.has_filename()) o.output = o.output.parent_path();  // "out/"
  const Setup setup = checked_setup(o);
  hal::SourceSpec spec;
  try {
    spec = hal::parse_source_spec(o.input.string());
  } catch (const hal::SourceError& e) {
    fail(e.what());
  }
  if (spec.backend.scheme == "file") return correct_recording_folder(o, setup, observers);
  return correct_live_source(o, spec, observers);
}

}  // namespace bolo::correct

// The frame loop of `bolo run`: source -> SourceCorrection (FrameReader -> firmware pipeline) ->
// sink, the status once a second, a stop asked for between frames.

#include "bolo/run/run_pipeline.hpp"

#include <algorithm>
#include <filesystem>
#include <memory>
#include <optional>
#include <thread>

#include "bolo/correct/fail.hpp"
#include "bolo/correct/source_correction.hpp"
#include "bolo/hal/frame_sink.hpp"
#include "bolo/hal/source_registry.hpp"

namespace bolo::run {
namespace {

namespace fs = std::filesystem;

using correct::fail;

// --device takes a scheme always, as for `bolo capture`: a bare word is more likely a mistyped device.
constexpr hal::SourceOptions kDeviceOptions{.bare_path_is_recording = false};

// A recording sink must not replace the recording it reads.
void refuse_writing_over_the_input(const std::string& device, const hal::SinkSpec& sink) {
  if (sink.backend.scheme != "recording") return;
  const hal::SourceSpec source = hal::parse_source_spec(device, kDeviceOptions);
  std::error_code ec;
  if (source.backend.scheme == "file" && fs::equivalent(source.argument, sink.argument, ec))
    fail("--sink ", sink.backend.scheme, ":", sink.argument, ": is the input recording; write elsewhere");
}

// --real-time: frame i is released at the first frame's release + (t_s[i] - t_s[0]).
class RealTimePace {
 public:
  // Sleeps until the frame's time has come (a frame without t_s goes at once); returns the release.
  Clock::time_point hold(const rec::FrameRow& row) {
    if (!row.t_s) return Clock::now();
    if (!first_t_s_) {
      first_t_s_ = row.t_s;
      first_release_ = Clock::now();
      return first_release_;
    }
    const auto release =
        first_release_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(*row.t_s - *first_t_s_));
    std::this_thread::sleep_until(release);
    return release;
  }

 private:
  std::optional<double> first_t_s_;
  Clock::time_point first_release_;
};

}  // namespace

RunResult run_pipeline(const RunRequest& request, std::span<correct::FrameObserver* const> observers,
                       std::ostream& standard_output, std::ostream& status, const std::function<int()>& stop_requested) {
  correct::check_flags(request);
  const std::string device = request.input.string();
  hal::SinkSpec sink_spec;
  std::unique_ptr<hal::OpenedSource> source;
  try {
    sink_spec = hal::parse_sink_spec(request.sink);
    refuse_writing_over_the_input(device, sink_spec);
    source = hal::open_source(device, kDeviceOptions);
  } catch (const hal::SinkError& e) {
    fail("--sink ", e.what());
  } catch (const hal::SourceError& e) {
    fail("--device ", e.what());
  }
  correct::SourceCorrection correction(request, *source);
  std::unique_ptr<hal::FrameSink> sink;
  try {
    sink = hal::open_sink(request.sink, {correction.corrected_info(), request.overwrite, &standard_output});
  } catch (const hal::SinkError& e) {
    fail("--sink ", e.what());
  }
  const bool recording_sink = sink_spec.backend.scheme == "recording";

  RunResult result;
  for (correct::FrameObserver* observer : observers) observer->on_begin(request.frames.value_or(0));
  const Clock::time_point start = Clock::now();
  RunStatus run_status(status, start);
  RealTimePace pace;
  // A source that has gone silent still gets its status line, and a stop asked for meanwhile ends
  // the run.
  correction.set_stop([&] {
    run_status.on_fault(correction.skipped(), Clock::now());
    return stop_requested() != 0;
  });
  while (!request.frames || correction.frames() < *request.frames) {
    if ((result.stopped_by = stop_requested()) != 0) break;
    const correct::SourceCorrection::Next next = correction.next();
    if (next == correct::SourceCorrection::Next::stopped) break;
    if (next == correct::SourceCorrection::Next::ended) {
      result.source_ended = true;
      break;
    }
    if (next == correct::SourceCorrection::Next::gave_up)
      fail(device, ": gave up after ", request.max_faults, " faults in a row, ", correction.frames(), " frames corrected",
           recording_sink ? ", nothing written" : "", " (", correction.faults(), ")");
    Clock::time_point dequeued = correction.began();
    if (request.real_time) dequeued = std::max(dequeued, pace.hold(correction.row()));
    sink->write(correction.pixels(), correction.row());
    const Clock::time_point done = Clock::now();
    result.latency.add(done - dequeued);
    for (correct::FrameObserver* observer : observers) observer->on_frame(correction.stats());
    run_status.on_frame(correction.stats(), done - dequeued, correction.skipped(), done);
  }
  if (result.stopped_by == 0) result.stopped_by = stop_requested();  // a signal during the last frame
  result.correction.frames = correction.frames();
  result.correction.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  result.correction.live = !correction.from_recording();
  result.correction.faults = correction.faults();
  result.correction.skipped = correction.skipped();
  if (correction.frames() == 0) {
    if (result.stopped_by != 0) return result;  // stopped before the first frame: nothing to finish
    fail(device, ": delivered no frames, nothing written");
  }
  if (!correction.from_recording()) sink->add_file("capture.json", correction.capture_json());
  sink->finish();
  result.written = true;
  return result;
}

}  // namespace bolo::run

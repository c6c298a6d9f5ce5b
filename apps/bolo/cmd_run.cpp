// bolo run --device SPEC --sink SPEC --tau-h S --tau-c S ...: the firmware pipeline live, from any
// source into a sink (apps/run), until the source ends, --frames are done, or SIGINT/SIGTERM.
// Everything it says goes to stderr: stdout may be the frames (raw:-).

#include <iomanip>
#include <memory>
#include <sstream>

#include "bolo/correct/correction_summary.hpp"
#include "bolo/correction_options.hpp"
#include "bolo/errors.hpp"
#include "bolo/hal/frame_sink.hpp"
#include "bolo/hal/source_registry.hpp"
#include "bolo/registry.hpp"
#include "bolo/run/run_pipeline.hpp"
#include "bolo/run/stop_signals.hpp"

namespace bolo::cli {
namespace {

int run_run(const run::RunRequest& request, std::ostream& out, std::ostream& err) {
  correct::SummaryTally tally;
  correct::FrameObserver* const observers[] = {&tally};
  const run::StopSignals signals;
  const run::RunResult result = run::run_pipeline(request, observers, out, err, &run::StopSignals::received);
  correct::CorrectRequest shown = request;
  shown.output = request.sink;
  correct::print_summary(err, shown, tally, result.correction);
  const auto line = [&err](const char* key) -> std::ostream& { return err << "  " << std::left << std::setw(14) << key; };
  line("latency") << "median " << run::milliseconds_text(result.latency.median()) << ", max "
                  << run::milliseconds_text(result.latency.max()) << " (a frame's first line in to its sink write)\n";
  if (result.stopped_by != 0)
    line("stopped") << "by " << run::signal_name(result.stopped_by) << " after " << result.correction.frames
                    << " frames" << (result.written ? "" : "; nothing written") << '\n';
  else if (result.source_ended)
    line("ended") << "the source has no more frames\n";
  return kExitOk;
}

// The registered sources and sinks, one per line, for the help page.
std::string spec_lists() {
  std::ostringstream text;
  text << "Sources (--device):\n";
  for (const hal::SourceBackend& b : hal::source_schemes())
    text << "  " << std::left << std::setw(20) << b.example() << " " << b.summary << "\n";
  text << "Sinks (--sink):\n";
  for (const hal::SinkBackend& b : hal::sink_schemes())
    text << "  " << std::left << std::setw(20) << b.example() << " " << b.summary << "\n";
  return text.str();
}

}  // namespace

Command add_run_command(CLI::App& parent, std::ostream& err) {
  auto o = std::make_shared<run::RunRequest>();
  o->tool = "bolo run";
  auto frames = std::make_shared<std::uint64_t>(0);
  CLI::App* app = add_command(
      parent, "run", "Run the correction live from a camera (or any source) into a recording, stdout or a V4L2 output",
      "Runs the firmware pipeline (bad pixels, two-frame corrector; as `bolo correct`) on a source's\n"
      "frames as they come and hands each corrected frame to a sink, until the source ends, --frames\n"
      "are done, or SIGINT/SIGTERM: then the frame in hand is finished, a recording sink committed\n"
      "whole, the summary printed, exit 0 (a second signal stops it at once; a recording sink then\n"
      "leaves only its hidden temporary folder). Once a second a status line: frame rate,\n"
      "dequeue-to-sink latency (median, max), frames skipped for faults, frames corrected without\n"
      "their predecessor (carry-over breaks). Status and summary go to stderr.\n" +
          spec_lists() +
          "raw:- writes each frame as W x H little-endian uint16, row-major, no headers (W, H: the\n"
          "source's; the summary and recording.json name them).\n\n"
          "Examples:\n"
          "  bolo run --device v4l2:/dev/video0 --tau-h 0.012 --tau-c 0.012 --exposure 0.01 --readout 0.1 \\\n"
          "      --sink recording:out/run\n"
          "  bolo run --device flirone-log:../shared/data/usb/flirone-pro --tau-h 0.012 --tau-c 0.012 \\\n"
          "      --exposure 0.01 --readout 0.1 --sink raw:- | gst-launch-1.0 fdsrc ! \\\n"
          "      rawvideoparse format=gray16-le width=80 height=60 framerate=9/1 ! videoconvert ! autovideosink\n"
          "  bolo run --device v4l2:/dev/video0 --tau-h 0.012 --tau-c 0.012 --sink v4l2:/dev/video10");
  app->add_option("--device", o->input, "Where frames come from (see above; a recording is file:REC)")->required();
  app->add_option("--sink", o->sink, "Where corrected frames go (see above)")->required();
  const std::function<void()> take_correction_options = add_correction_options(*app, *o);
  app->add_option("--frames", *frames, "Stop after N frames (default: when the source ends, or at SIGINT)")
      ->check(CLI::PositiveNumber);
  app->add_flag("--overwrite", o->overwrite, "A recording sink may replace an existing recording");
  app->add_flag("--real-time", o->real_time,
                "Hold each frame until its t_s after the first frame's: a recording or transfer log replayed\n"
                "at the pace the camera delivered it (the hold is not counted as latency)");
  return {app, [=, &err](std::ostream& out) {
            take_correction_options();
            if (*frames != 0) o->frames = *frames;
            return run_run(*o, out, err);
          }};
}

}  // namespace bolo::cli

// bolo correct SOURCE OUT --tau-h S --tau-c S ...: the command line of the correction driver
// (apps/correct: correct_recording, any source hal::open_source opens), its progress bar and
// summary fed by frame observers.

#include <memory>

#include "bolo/commands.hpp"
#include "bolo/correct/correction_summary.hpp"
#include "bolo/correction_options.hpp"
#include "bolo/errors.hpp"
#include "bolo/progress.hpp"
#include "bolo/registry.hpp"

namespace bolo::cli {
namespace {

namespace fs = std::filesystem;

// The progress bar, advanced once per corrected frame.
class ProgressObserver final : public correct::FrameObserver {
 public:
  explicit ProgressObserver(bool enabled) : enabled_(enabled) {}
  // A live source's count is unknown (0) unless --frames: no bar then.
  void on_begin(std::uint64_t frames) override { bar_.emplace("correct", frames, enabled_ && frames != 0); }
  void on_frame(const correct::FrameStats& s) override { bar_->update(s.frame + 1); }
  void finish() {
    if (bar_) bar_->finish();
  }

 private:
  bool enabled_;
  std::optional<Progress> bar_;
};

}  // namespace

int run_correct(const CorrectOptions& options, std::ostream& out) {
  correct::SummaryTally tally;
  ProgressObserver progress(options.progress);
  correct::FrameObserver* const observers[] = {&tally, &progress};
  const correct::CorrectResult result = correct::correct_recording(options, observers);
  progress.finish();
  correct::print_summary(out, options, tally, result);
  return kExitOk;
}

Command add_correct_command(CLI::App& parent) {
  auto o = std::make_shared<CorrectOptions>();
  auto stats = std::make_shared<std::string>();
  auto frames = std::make_shared<std::uint64_t>(0);
  CLI::App* app = add_command(
      parent, "correct", "Correct the ghosting of a recording or a camera (two-frame corrector, firmware pipeline)",
      "Corrects the ghosting of a source's frames with the two-frame corrector (paper Eq. 6):\n"
      "  I'_i = (I_i - a * I_{i-1}) * g,  a = exp(-t_r,i-1 / tau_c),  g = 1 / (1 - exp(-t_e,i / tau_h))\n"
      "run through the fixed-point firmware pipeline, and write the corrected recording to OUT\n"
      "(uint16 frames.npy; recording.json notes the correction). SOURCE is any source spec of\n"
      "`bolo capture --help` or a recording folder. From a recording, frames.csv, camera.json,\n"
      "poses.tum and scene.npy are copied and every frame is checked before any is corrected; from\n"
      "a live source (a camera, a transfer log), frames.csv comes from each frame's header,\n"
      "recording.json says what the source knows (sensor, size, bit depth) and capture.json holds its\n"
      "fault counters; faulted frames are skipped and counted, more than --max-faults in a row give\n"
      "up, and a camera that streams on needs --frames. Each frame's exposure and readout (frames.csv\n"
      "or the frame header) win over --exposure/--readout; every frame needs both from one or the\n"
      "other. A frame is corrected against its predecessor unless it is the first, follows an FFC\n"
      "event, a frame drop or a time gap (> 1.5 frame periods); the summary counts the reasons.\n\n"
      "Examples (a real recording without timing columns; a FLIR ONE transfer log):\n"
      "  bolo correct ../shared/data/real/lepton3-possum out/corrected --tau-h 0.012 --tau-c 0.012 \\\n"
      "      --exposure 0.01 --readout 0.1 --stats out/stats.csv\n"
      "  bolo correct flirone-log:../shared/data/usb/flirone-pro out/f1 --tau-h 0.012 --tau-c 0.012 \\\n"
      "      --exposure 0.01 --readout 0.1");
  app->add_option("SOURCE", o->input, "A recording folder or a source spec (file:REC, v4l2:/dev/video0, ...)")
      ->required();
  app->add_option("OUT", o->output, "Output recording folder (must not exist unless --overwrite)")
      ->required();
  const std::function<void()> take_correction_options = add_correction_options(*app, *o);
  app->add_flag("--float", o->float_output,
                "Write float32 frames.npy computed by the double-precision reference instead");
  app->add_flag("--overwrite", o->overwrite, "Replace OUT (and the --stats file) if they exist");
  CLI::Option* stats_opt = app->add_option(
      "--stats", *stats,
      "Write per-frame statistics CSV: frame, carry_over reason, coefficient status, gain, carry\n"
      "coefficient (a*g), saturated low/high pixel counts, bad pixels replaced");
  app->add_option("--frames", *frames, "Correct at most N frames (required for a camera that streams on)")
      ->check(CLI::PositiveNumber);
  app->add_flag("--no-progress", [o](std::int64_t) { o->progress = false; },
                "Never draw the progress bar (it is drawn only when stderr is a terminal)");
  return {app, [=](std::ostream& out) {
            take_correction_options();
            if (stats_opt->count()) o->stats = fs::path(*stats);
            if (*frames != 0) o->frames = *frames;
            return run_correct(*o, out);
          }};
}

}  // namespace bolo::cli

#pragma once
// The sinks a recording's frames are pushed into: the firmware pipeline into a FrameCollector and,
// with --float, the double-precision reference beside it (behind its own bad-pixel stage when
// asked), which then writes the pixels while the pipeline still makes the per-frame decisions.

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "bolo/core/frame_collector.hpp"
#include "bolo/correct/frame_observer.hpp"
#include "bolo/core/frame_source.hpp"
#include "bolo/firmware/pipeline.hpp"
#include "bolo/recording/recording.hpp"
#include "bolo/sim/corrector_reference.hpp"
#include "frame_timing.hpp"
#include "nuc_file.hpp"

namespace bolo::correct {

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

// The firmware pipeline's configuration for frames of `format` with the request's flags.
// Refuses (Error naming `input`) frames in units counts8: tone-mapped, not linear counts.
fw::PipelineConfig pipeline_config(const Setup& setup, const hal::SourceFormat& format, bool bad_pixels,
                                   const std::string& input);

class CorrectionChain {
 public:
  // `input` names the recording in errors.
  CorrectionChain(const fw::PipelineConfig& config, const CorrectRequest& request, std::string input);
  CorrectionChain(const CorrectionChain&) = delete;
  CorrectionChain& operator=(const CorrectionChain&) = delete;

  // Where the source pushes each frame.
  fw::LineSink& input() { return tee_ ? static_cast<fw::LineSink&>(*tee_) : pipeline_.input(); }
  // After frame `i` was pushed (with its timing and its predecessor's, none for the first frame):
  // its stats; with --float the reference has corrected it too.
  FrameStats finish_frame(std::uint64_t i, const rec::FrameRow& row, const FrameTiming& timing,
                          const FrameTiming* previous);
  // The last finished frame as the pipeline corrected it.
  std::span<const fw::Pixel> pixels() const { return corrected_.pixels(); }
  // Appends the last finished frame to `writer` with `row`: the pipeline's pixels, or with --float
  // the reference's.
  void append(rec::RecordingWriter& writer, const rec::FrameRow& row) const;

 private:
  FrameStats pipeline_stats(std::uint64_t i, const FrameTiming& timing);
  // --float: the reference's pixels, gain, carry and saturation replace the pipeline's.
  void run_reference(const rec::FrameRow& row, const FrameTiming& timing, const FrameTiming* previous,
                     FrameStats& s);

  const CorrectRequest& request_;
  std::string input_name_;
  NucFile nuc_;                  // --nuc: the tables config_ points at
  fw::PipelineConfig config_;
  std::vector<fw::Pixel> arena_, corrected_storage_;
  fw::FrameCollector corrected_;
  fw::Pipeline pipeline_;
  std::vector<fw::Pixel> raw_storage_;
  fw::FrameCollector raw_;
  std::vector<fw::Pixel> float_bad_storage_;
  std::optional<fw::BadPixelStage> float_bad_pixels_;
  std::vector<fw::Pixel> float_nuc_storage_;
  std::optional<fw::NucStage> float_nuc_;
  std::optional<sim::ReferenceCorrector> reference_;
  std::optional<Tee> tee_;
  std::vector<double> reference_out_;
  std::vector<float> float_frame_;
};

}  // namespace bolo::correct

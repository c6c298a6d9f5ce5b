#pragma once
// The frames of an opened source (a camera, a transfer log, a recording) corrected one at a time
// through the firmware pipeline, as `bolo correct` does with a live source and `bolo run` with
// any: faulted frames skipped and counted (hal::FrameReader), each frame's exposure and readout
// from its header (the flags fill in) and its coefficients checked before it is corrected, its
// frames.csv row from the recording (a recording source) or from its header (rec::RowClock).
// Memory stays constant however long the source streams.

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>

#include "bolo/correct/correct_recording.hpp"
#include "bolo/hal/source_registry.hpp"
#include "bolo/recording/recording.hpp"

namespace bolo::correct {

class SourceCorrection {
 public:
  using Clock = std::chrono::steady_clock;

  // `request.input` names the source in errors; the flags are checked as correct_recording checks
  // them. `source` must outlive this.
  SourceCorrection(const CorrectRequest& request, hal::OpenedSource& source);
  ~SourceCorrection();
  SourceCorrection(const SourceCorrection&) = delete;
  SourceCorrection& operator=(const SourceCorrection&) = delete;

  enum class Next { frame, ended, gave_up, stopped };
  // Reads and corrects the next whole frame: `frame`; `ended` when the source has no more;
  // `gave_up` after more than request.max_faults faulted frames in a row; `stopped` when `stop`
  // (set_stop) said so after a faulted frame. Throws Error when a frame's timing cannot be corrected.
  Next next();
  void set_stop(std::function<bool()> stop);

  // The last corrected frame: the pipeline's pixels, its frames.csv row, its stats, and when its
  // first line arrived from the source (the frame's dequeue).
  std::span<const std::uint16_t> pixels() const;
  const rec::FrameRow& row() const;
  const FrameStats& stats() const;
  Clock::time_point began() const;
  // Appends the last corrected frame to `writer` (with request.float_output the reference's).
  void append(rec::RecordingWriter& writer) const;

  std::uint64_t frames() const;   // corrected so far
  std::uint64_t skipped() const;  // faulted or incomplete frames skipped
  bool from_recording() const;    // the source is a recording (file:REC): its rows are kept
  // recording.json of the corrected frames: the recording's own, or what a live source knows of
  // itself, with the correction noted.
  rec::RecordingInfo corrected_info() const;
  // capture.json of a live source: its fault counters, as `bolo capture` writes them.
  std::string capture_json() const;
  // The fault counters as the summaries print them (hal::fault_text).
  std::string faults() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace bolo::correct

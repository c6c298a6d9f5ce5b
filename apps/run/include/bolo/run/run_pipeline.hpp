#pragma once
// `bolo run`'s work: the frames of any source (hal::open_source) through the firmware pipeline
// (correct::SourceCorrection) into a sink (hal::open_sink), frame by frame as they come, until the
// source ends, request.frames are done, or the caller asks it to stop (between frames: the frame
// in hand is finished and a recording sink is committed whole).

#include <cstdint>
#include <functional>
#include <ostream>
#include <span>
#include <string>

#include "bolo/correct/correct_recording.hpp"
#include "bolo/correct/frame_observer.hpp"
#include "bolo/run/run_status.hpp"

namespace bolo::run {

struct RunRequest : correct::CorrectRequest {  // input: the source spec (--device); output unused
  std::string sink;                            // recording:DIR, raw:-, v4l2:/dev/videoN
  // Each frame held back until its t_s after the first frame's (a recording or transfer log
  // replayed as the camera delivered it); the hold does not count as latency.
  bool real_time = false;
};

struct RunResult {
  correct::CorrectResult correction;  // frames, wall time, a live source's faults and skipped frames
  int stopped_by = 0;                 // the signal that stopped the run; 0: it ended otherwise
  bool source_ended = false;          // the source had no more frames
  bool written = false;               // the sink took every frame and was finished
  LatencyTally latency;               // dequeue to sink, the whole run
};

// Runs the request. `standard_output` is where raw:- writes; `status` gets a line once a second
// (RunStatus); `stop_requested` is asked between frames and returns the signal that asks the run
// to stop (0: go on). Errors name the flag (--device, --sink), the source or the sink; a failed run
// leaves no recording behind.
RunResult run_pipeline(const RunRequest& request, std::span<correct::FrameObserver* const> observers,
                       std::ostream& standard_output, std::ostream& status, const std::function<int()>& stop_requested);

}  // namespace bolo::run

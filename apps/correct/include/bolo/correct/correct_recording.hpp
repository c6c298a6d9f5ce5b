#pragma once
// `bolo correct`'s work: the frames of any source (a recording, a camera, a transfer log) through
// the firmware pipeline (or, with float_output, the double-precision reference beside it) into a
// new recording, each frame's stats to observers. Everything that can be checked is checked
// before anything is written (a recording's every frame; a live source's frames as they come);
// the output is atomic, so a failure leaves no output (and no stats file) behind.

#include <filesystem>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>

#include "bolo/correct/frame_observer.hpp"

namespace bolo::correct {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct CorrectRequest {
  std::filesystem::path input;   // a source spec (hal::open_source): a recording folder, file:REC, v4l2:...
  std::filesystem::path output;
  double tau_h_s = 0.0;
  double tau_c_s = 0.0;
  std::optional<double> exposure_s;  // for frames without one (empty exposure_s cell, 0 in the header)
  std::optional<double> readout_s;   // for frames without one (empty readout_s cell, 0 in the header)
  bool float_output = false;         // float32 frames.npy from the double-precision reference
  bool overwrite = false;
  bool bad_pixels = false;
  std::optional<std::filesystem::path> nuc;    // per-pixel gain and offset applied first (nuc_file.hpp)
  std::optional<std::filesystem::path> stats;  // per-frame statistics CSV
  std::optional<double> nominal_fps;           // frame rate for gap detection; default: learned
  std::optional<std::uint64_t> frames;         // at most this many; required for a camera that streams on
  std::uint64_t max_faults = 50;               // a live source's faulted frames in a row before giving up
  std::string tool = "bolo correct";           // the command recording.json names (source, correction.tool)
};

struct CorrectResult {
  std::uint64_t frames = 0;
  double seconds = 0;  // the frame loop's wall time
  // A live source (not a recording): its fault counters (hal::fault_text) and the frames skipped.
  bool live = false;
  std::string faults;
  std::uint64_t skipped = 0;
};

// Runs the correction; the observers see every frame in order. Errors name the flag, file, frame
// or field (flags as the command line spells them).
CorrectResult correct_recording(const CorrectRequest& request, std::span<FrameObserver* const> observers);

// The request's flags alone (tau, exposure, readout, nominal fps, frames), as correct_recording
// checks them before anything is opened; throws Error naming the flag.
void check_flags(const CorrectRequest& request);

// The seconds as the messages print them (%.9g).
std::string seconds_text(double seconds);

}  // namespace bolo::correct

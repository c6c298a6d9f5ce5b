#pragma once
// `bolo correct`'s work: a recording through the firmware pipeline (or, with float_output, the
// double-precision reference beside it) into a new recording, each frame's stats to observers.
// Everything that can be checked is checked before anything is written; the output is atomic,
// so a failure leaves no output (and no stats file) behind.

#include <filesystem>
#include <optional>
#include <span>
#include <stdexcept>

#include "bolo/correct/frame_observer.hpp"

namespace bolo::correct {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct CorrectRequest {
  std::filesystem::path input;   // a recording folder, or a source spec naming one (file:REC)
  std::filesystem::path output;
  double tau_h_s = 0.0;
  double tau_c_s = 0.0;
  std::optional<double> exposure_s;  // used for frames whose exposure_s cell is empty
  std::optional<double> readout_s;   // used for frames whose readout_s cell is empty
  bool float_output = false;         // float32 frames.npy from the double-precision reference
  bool overwrite = false;
  bool bad_pixels = false;
  std::optional<std::filesystem::path> stats;  // per-frame statistics CSV
  std::optional<double> nominal_fps;           // frame rate for gap detection; default: learned
};

struct CorrectResult {
  std::uint64_t frames = 0;
  double seconds = 0;  // the frame loop's wall time
};

// Runs the correction; the observers see every frame in order. Errors name the flag, file, frame
// or field (flags as the command line spells them).
CorrectResult correct_recording(const CorrectRequest& request, std::span<FrameObserver* const> observers);

// The seconds as the messages print them (%.9g).
std::string seconds_text(double seconds);

}  // namespace bolo::correct

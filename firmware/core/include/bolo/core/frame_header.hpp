#pragma once
// The per-frame metadata that travels with the lines of a frame from a source (HAL) through the
// pipeline stages. Integer units only: the board has no business rounding seconds in float.

#include <cstdint>

namespace bolo::fw {

enum class FfcState : std::uint8_t {
  unknown,    // the source cannot tell
  none,       // known: no shutter / flat-field event before this frame
  completed,  // a shutter / FFC event completed between the previous frame and this one
  imminent,   // known: no event before this frame, but the camera announced one soon (a good frame)
  in_progress,  // the shutter is closed (FFC running) during this frame: it shows the shutter
};

// The one rule for what a frame's FFC state means downstream: after a completed event, or while
// one is in progress, the frame is not the scene its predecessor saw (no carry-over correction
// against it; frames.csv `ffc` = 1).
constexpr bool shutter_event(FfcState ffc) { return ffc == FfcState::completed || ffc == FfcState::in_progress; }

inline constexpr std::int32_t kUnknownTemperature = INT32_MIN;

struct FrameHeader {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  // Source frame counter; consecutive frames differ by exactly one. A larger step is a drop.
  std::uint64_t sequence = 0;
  bool sequence_valid = false;
  // Capture time, nanoseconds on a monotonic clock of any origin.
  std::int64_t timestamp_ns = 0;
  bool timestamp_valid = false;
  // Exposure (heating) time of this frame and readout (cooling) time that follows it; 0 = unknown.
  std::uint32_t exposure_ns = 0;
  std::uint32_t readout_ns = 0;
  FfcState ffc = FfcState::unknown;
  // Milli-degrees Celsius, kUnknownTemperature where the source has none.
  std::int32_t fpa_temp_mc = kUnknownTemperature;
  std::int32_t housing_temp_mc = kUnknownTemperature;
};

}  // namespace bolo::fw

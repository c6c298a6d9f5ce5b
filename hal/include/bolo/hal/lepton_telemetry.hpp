#pragma once
// Lepton telemetry row A (80 words) as the FLIR ONE Pro and PureThermal (Y16, 160x122 or 80x63) deliver
// it. Pure decoding: no I/O, no allocation, no exceptions (board-safe).
//
// Word map (usb-thermal-cores.md, "Telemetry row A"): 3-4 status, 20-21 frame counter, 23 FPA
// counts, 24 FPA temperature (K x 100), 29 FPA temperature at the last FFC, 30-31 time at the
// last FFC (ms). Two more fields were established on the real FLIR ONE Pro capture against the
// recording made from it: 1-2 uptime (ms) and 26 housing temperature (K x 100). 32-bit fields
// are low word first: on the capture the frame counter then steps by 3 per exported frame
// (27 Hz core, ~8.6 Hz export) and the status reads "FFC complete".

#include <cstdint>
#include <span>

#include "bolo/core/frame_header.hpp"

namespace bolo::hal {

enum class LeptonFfcState : std::uint8_t { never, imminent, in_progress, complete };

struct LeptonTelemetry {
  std::uint16_t revision = 0;
  std::uint32_t uptime_ms = 0;
  std::uint32_t status = 0;
  bool ffc_desired = false;
  LeptonFfcState ffc_state = LeptonFfcState::never;
  bool agc_on = false;
  bool shutter_lockout = false;
  std::uint32_t frame_counter = 0;
  std::uint16_t fpa_counts = 0;
  std::uint16_t fpa_temp_ck = 0;           // centikelvin
  std::uint16_t housing_temp_ck = 0;       // centikelvin
  std::uint16_t fpa_temp_last_ffc_ck = 0;  // centikelvin
  std::uint32_t time_at_last_ffc_ms = 0;
};

inline constexpr std::size_t kLeptonTelemetryWords = 80;

// Telemetry rows a PureThermal appends (footer) to a Y16 frame of this size, as offered: 160x122
// (Lepton 3.x: 120 image rows; rows A-C, 240 words, fill two rows of 160) and 80x63 (Lepton 2.x:
// 60 image rows, rows A, B, C); 0 for any other size. Row A opens the first telemetry row.
std::uint32_t lepton_telemetry_rows(std::uint32_t width, std::uint32_t height);

// Decodes row A; false (and `out` untouched) when `row_a` holds fewer than 80 words.
bool decode_lepton_telemetry(std::span<const std::uint16_t> row_a, LeptonTelemetry& out);

// Each frame's FrameHeader FFC state from its telemetry, the one rule of every Lepton source:
// status "FFC in progress" -> in_progress (the frame shows the shutter); the first frame after
// such frames, or one whose "time at last FFC" differs from the previous frame's -> completed;
// status "FFC imminent" -> imminent; else none. After a (re)start the first frame has no
// predecessor to differ from.
class LeptonFfcTracker {
 public:
  fw::FfcState next(const LeptonTelemetry& telemetry);
  void restart() { have_ = in_progress_ = false; }

 private:
  bool have_ = false;
  bool in_progress_ = false;  // the previous frame's
  std::uint32_t last_ffc_ms_ = 0;
};

// Centikelvin -> milli-degrees Celsius (the FrameHeader unit); 0 (no reading) -> unknown.
std::int32_t centikelvin_to_mc(std::uint16_t ck);

// The largest forward step (in frames) taken as frames lost; beyond it, or more than 63 frames
// behind the highest, a step is a jump (a restarted core, a row that is not telemetry), not that
// many losses. Frames up to 63 behind are told apart as late or repeated.
inline constexpr std::uint32_t kLeptonCounterWindow = 64;
// The largest step per exported frame believed: the core runs at ~27 Hz and exports ~9 Hz.
inline constexpr std::uint32_t kLeptonMaxStride = 8;

// Follows the telemetry frame counter of the frames a source delivers, in delivery order. The
// counter counts the core's frames; a camera exporting every third (the FLIR ONE Pro capture)
// steps by 3, so the step of one exported frame (the stride) is learned: the smallest forward
// step since the (re)start. A forward step of n strides skips n - 1 frames. A counter behind
// the highest is late (uvcvideo hands frames over out of order now and then) unless it was
// delivered before: then it is a repeat, as is the highest again (the camera sent a frame twice).
class LeptonFrameCounter {
 public:
  enum class Step : std::uint8_t { first, forward, repeat, late, jump };
  Step add(std::uint32_t counter);
  void restart();  // a reopened device: the next counter is a first one
  // Exported frames the last `forward` step advanced (1: none skipped).
  std::uint32_t advanced() const { return advanced_; }
  // Of the frames the last `forward` step went over, those that `accounted` (frames the source
  // knows were lost elsewhere since: on the wire, by the driver) does not explain: the camera
  // counted them but never sent them.
  std::uint32_t skipped_beyond(std::uint64_t accounted) const {
    const std::uint64_t missing = advanced_ > 0 ? advanced_ - 1u : 0u;
    return missing > accounted ? static_cast<std::uint32_t>(missing - accounted) : 0u;
  }
  std::uint32_t stride() const { return stride_; }  // 0 until a forward step was seen
  std::uint64_t repeats() const { return repeats_; }
  std::uint64_t late() const { return late_; }
  std::uint64_t jumps() const { return jumps_; }

 private:
  void start_at(std::uint32_t counter);
  Step forward_by(std::uint32_t step);
  Step behind_by(std::uint32_t step);

  bool have_ = false;
  std::uint32_t highest_ = 0;
  std::uint32_t stride_ = 0;
  std::uint64_t delivered_ = 0;  // bit k: the frame k strides behind the highest was delivered
  std::uint32_t advanced_ = 0;
  std::uint64_t repeats_ = 0, late_ = 0, jumps_ = 0;
};

}  // namespace bolo::hal

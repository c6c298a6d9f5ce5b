#pragma once
// Lepton telemetry row A (80 words) as the FLIR ONE Pro and PureThermal (Y16, 160x122) deliver
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

// Decodes row A; false (and `out` untouched) when `row_a` holds fewer than 80 words.
bool decode_lepton_telemetry(std::span<const std::uint16_t> row_a, LeptonTelemetry& out);

// Centikelvin -> milli-degrees Celsius (the FrameHeader unit); 0 (no reading) -> unknown.
std::int32_t centikelvin_to_mc(std::uint16_t ck);

}  // namespace bolo::hal

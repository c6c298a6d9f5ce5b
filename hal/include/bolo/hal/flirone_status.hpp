#pragma once
// The JSON status string at the end of every FLIR ONE Pro frame, e.g.
//   {"shutterState":"ON","shutterTemperature":320.29,"usbNotifiedTimestamp":1167615302.51911,
//    "usbEnqueuedTimestamp":1167615302.52728,"ffcState":"FFC_VALID_RAD"}
// A flat object of strings and numbers; only the fields below are read, by a scanner that
// allocates nothing and never reads outside the given bytes (board-safe).

#include <cstdint>
#include <span>

namespace bolo::hal {

struct FlirOneStatus {
  static constexpr std::size_t kTextCapacity = 24;
  char shutter_state[kTextCapacity] = {};  // "ON", "OFF", ... ("" when absent)
  char ffc_state[kTextCapacity] = {};      // "FFC_VALID_RAD", "FFC_PROGRESS", ...
  bool has_shutter_temp = false;
  std::int32_t shutter_temp_mk = 0;  // millikelvin
  bool has_usb_timestamp = false;
  std::int64_t usb_timestamp_ns = 0;  // usbNotifiedTimestamp (camera clock, seconds -> ns)
};

// Reads the fields present in `json` (may end in NUL bytes). False when the text is not an
// object or a present field is malformed (string not closed, too long, number unreadable).
bool parse_flirone_status(std::span<const std::uint8_t> json, FlirOneStatus& out);

// True when ffc_state names a shutter event in progress (FFC_PROGRESS / ..._IN_PROGRESS).
bool flirone_ffc_in_progress(const FlirOneStatus& status);

}  // namespace bolo::hal

#pragma once
// An emulator's send log ("frame INDEX FAULT HASH COUNTER SIZE IMAGE_HASH" per frame) turned into
// what the host must see: the frames it must deliver, in order, and the faults it must count.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "emulators/fault_plan.hpp"

namespace bolo::hil {

struct SentFrame {
  std::uint64_t index = 0;
  Fault fault = Fault::none;
  std::uint64_t hash = 0;
  std::uint32_t counter = 0;
  std::uint64_t image_hash = 0;  // the 80x60 pixels only
};

struct Expectation {
  std::vector<SentFrame> deliver;            // in order; a duplicate appears twice
  std::array<std::uint64_t, 8> injected{};   // per Fault value
  std::uint64_t frames_sent = 0;
  std::uint64_t lost_by_emulator = 0;        // the host vanished under a frame: must be 0
  // Control requests the emulator refused ("# refused-requests N"; -1 when not reported): a host
  // that starts the device as its drivers do has none.
  long refused_requests = -1;
};

// Throws naming the file and line of a malformed entry.
Expectation read_send_log(const std::string& path);

// A frame-counter step that is no device's normal cadence (backwards, or a jump of more than
// 64 frames): what a host reports as a frame-id surprise.
bool counter_surprise(std::uint32_t previous, std::uint32_t next);

}  // namespace bolo::hil

#pragma once
// Which frame gets which device fault: a seeded, reproducible schedule shared by every emulator,
// and the names used in the emulators' send logs.

#include <cstdint>
#include <string>
#include <vector>

namespace bolo::hil {

enum class Fault : std::uint8_t {
  none,
  short_transfer,  // the frame stops part-way; the next frame follows
  corrupt,         // a packet id inside the frame is wrong
  stall,           // the bulk endpoint halts mid-frame
  timeout,         // the device goes quiet mid-frame for longer than the host waits
  disconnect,      // unplugged mid-frame, plugged back in
  frame_id_jump,   // the frame counter jumps (kept from then on), the frame itself is good
  duplicate,       // the same frame is sent twice
};

const char* fault_name(Fault fault);
Fault parse_fault(const std::string& name);  // throws naming the bad name
// Faults that cost the frame they hit (the host must count them and deliver nothing for it).
bool fault_loses_frame(Fault fault);

class FaultPlan {
 public:
  FaultPlan() = default;
  // `rate`: fraction of frames with a fault; `kinds`: faults to draw from (all if empty).
  FaultPlan(double rate, std::uint64_t seed, std::vector<Fault> kinds);
  Fault at(std::uint64_t frame) const;

 private:
  std::uint64_t threshold_ = 0;  // out of 2^32
  std::uint64_t seed_ = 0;
  std::vector<Fault> kinds_;
};

// "short_transfer,stall" -> faults; "all" -> every fault.
std::vector<Fault> parse_fault_list(const std::string& list);

}  // namespace bolo::hil

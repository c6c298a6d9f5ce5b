#pragma once
// The FLIR ONE's USB face for its emulator, written from the protocol facts
// (usb-thermal-cores.md), not from the HAL: its descriptors (VID:PID 09cb:1996, configuration 3,
// interfaces 0 iAP, 1 file I/O, 2 frames, each with alternate settings 0 and 1 and a bulk IN and
// a bulk OUT endpoint) and the check of its start-up: SET_CONFIGURATION 3, then standard
// SET_INTERFACE requests in the public drivers' order (2 alt 0, 1 alt 0, 1 alt 1, 2 alt 1);
// stopping is 2 alt 0 then 1 alt 0. Anything else is refused (stalled) and counted.

#include <linux/usb/ch9.h>

#include <cstdint>
#include <string>
#include <vector>

namespace bolo::hil::flirone {

inline constexpr std::uint8_t kConfiguration = 3;
inline constexpr int kInterfaces = 3;  // 0 iAP, 1 file I/O, 2 frames

class StartupChecker {
 public:
  // A control request other than GET_DESCRIPTOR. True: the camera takes it (ack); false: it is
  // refused (stall), counted, and last_refusal() says why.
  bool take(const usb_ctrlrequest& r);
  bool configured() const { return configured_; }
  bool streaming() const { return step_ == kSteps; }  // interface 2 at alt 1, in the drivers' order
  std::uint64_t refused() const { return refused_; }
  const std::string& last_refusal() const { return last_refusal_; }
  void unplugged();  // off the bus: unconfigured, not streaming

 private:
  static constexpr std::size_t kSteps = 4;
  bool refuse(const usb_ctrlrequest& r, const std::string& why);
  bool configured_ = false;
  std::size_t step_ = 0;  // SET_INTERFACE steps of the start sequence done since SET_CONFIGURATION
  std::uint64_t refused_ = 0;
  std::string last_refusal_;
};

struct EndpointPair {
  std::uint8_t in = 0, out = 0;  // endpoint addresses (IN with bit 7 set)
};

// The descriptors the camera answers GET_DESCRIPTOR with; the endpoint addresses per interface
// are what the UDC offers (the real camera: 0x81/0x02, 0x83/0x04, 0x85/0x06).
struct Descriptors {
  std::vector<std::uint8_t> device;
  std::vector<std::uint8_t> configuration;  // with its interfaces and endpoints
  std::vector<std::vector<std::uint8_t>> strings;  // index 0: the language list
};
Descriptors make_descriptors(const EndpointPair (&endpoints)[kInterfaces]);
// The answer to GET_DESCRIPTOR `r` (cut to wLength); false when the camera has no such descriptor.
bool descriptor_for(const Descriptors& d, const usb_ctrlrequest& r, std::vector<std::uint8_t>& out);

}  // namespace bolo::hil::flirone

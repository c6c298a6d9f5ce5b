#pragma once
// The UVC gadget function's V4L2 output node as the emulator drives it: UVC events (connect,
// class requests on ep0 and their data, stream on/off), answers to requests
// (UVCIOC_SEND_RESPONSE), and mmap output buffers that the function sends to the host as bulk
// payloads. Throws std::runtime_error naming the node and the call that failed.

#include <linux/usb/ch9.h>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "uvc_control.hpp"

namespace bolo::hil::uvc {

enum class EventType : std::uint8_t { connect, disconnect, setup, data, streamon, streamoff };

struct Event {
  EventType type = EventType::connect;
  usb_ctrlrequest setup{};          // setup
  std::vector<std::uint8_t> data;   // data (the OUT data stage of the last SET request)
};

class UvcDevice {
 public:
  // Opens the node and subscribes to the UVC events; subscribing to SETUP lets the function
  // connect to the host (usb_f_uvc keeps it away until then).
  explicit UvcDevice(std::string node);
  ~UvcDevice();
  UvcDevice(const UvcDevice&) = delete;
  UvcDevice& operator=(const UvcDevice&) = delete;

  // Waits up to `timeout_ms` for an event, or (while streaming) a buffer the host has taken.
  // True when something is ready.
  bool wait(int timeout_ms);
  std::optional<Event> next_event();
  // The data stage of the current setup request: `bytes` for IN requests; for OUT requests the
  // length to receive (the data comes as a data event). Nothing: stall.
  void respond(const std::optional<std::vector<std::uint8_t>>& bytes);
  void accept_out(std::uint16_t length);

  // Output format + buffers for `size` (Y16), then stream on; off frees the buffers.
  void start(FrameSize size, std::uint32_t buffers);
  void stop();
  bool streaming() const { return streaming_; }
  std::uint32_t buffer_count() const { return static_cast<std::uint32_t>(buffers_.size()); }

  // A buffer the host has taken whole (index), if any.
  std::optional<std::uint32_t> take_done();
  // Queues buffer `index` with `bytes` (fewer than the frame size: a short frame).
  void queue(std::uint32_t index, std::span<const std::uint8_t> bytes);

 private:
  std::string node_;
  int fd_ = -1;
  struct Buffer {
    void* start = nullptr;
    std::size_t length = 0;
  };
  std::vector<Buffer> buffers_;
  bool streaming_ = false;
};

}  // namespace bolo::hil::uvc

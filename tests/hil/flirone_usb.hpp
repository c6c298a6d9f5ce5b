#pragma once
// The FLIR ONE as libusb sees it: open by VID:PID, find the frame interface's bulk IN endpoint
// from the descriptors, claim the interfaces, start streaming, read transfers. Kept to the
// USB mechanics; frame reassembly is FrameAssembler's job.

#include <libusb.h>

#include <chrono>
#include <cstdint>
#include <string>

namespace bolo::hil::flirone {

enum class ReadStatus : std::uint8_t { data, timeout, stall, gone };

class FlirOneUsb {
 public:
  FlirOneUsb();
  ~FlirOneUsb();
  FlirOneUsb(const FlirOneUsb&) = delete;
  FlirOneUsb& operator=(const FlirOneUsb&) = delete;

  // Waits up to `patience` for the device to appear, then opens and starts it. False on
  // timeout; `error` says what failed last.
  bool open(std::chrono::milliseconds patience, std::string& error);
  // For the refusal check: opens it (configuration 3, interfaces claimed) and sends only the
  // vendor request 0x41/0x0b (wValue 1, interface 2) that no driver sends; returns its libusb
  // result (a camera stalls it: LIBUSB_ERROR_PIPE), or 1 when the device never appeared.
  int open_with_vendor_start(std::chrono::milliseconds patience, std::string& error);
  void close();
  bool is_open() const { return handle_ != nullptr; }

  ReadStatus read(std::uint8_t* buffer, int size, int& transferred, unsigned timeout_ms);
  void clear_stall();
  std::uint8_t frame_endpoint() const { return endpoint_; }

 private:
  bool try_open(std::string& error, bool drivers_start);
  int vendor_start_result_ = 1;
  libusb_context* context_ = nullptr;
  libusb_device_handle* handle_ = nullptr;
  std::uint8_t endpoint_ = 0;
};

}  // namespace bolo::hil::flirone

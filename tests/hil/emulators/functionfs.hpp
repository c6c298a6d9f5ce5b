#pragma once
// A FunctionFS function: the userspace half of a USB device. Mounts the function's file system,
// writes its interface/endpoint descriptors and strings to ep0, then hands out the endpoint
// files and the ep0 event stream (bind, enable, setup requests, ...).

#include <linux/usb/ch9.h>

#include <cstdint>
#include <string>
#include <vector>

namespace bolo::hil {

struct EndpointSpec {
  bool in = true;
  std::uint8_t attributes = USB_ENDPOINT_XFER_BULK;
};

struct InterfaceSpec {
  std::uint8_t interface_class = 0xFF;
  std::uint8_t interface_subclass = 0;
  std::uint8_t interface_protocol = 0;
  std::string name;  // interface string
  std::vector<EndpointSpec> endpoints;
};

enum class FfsEventType : std::uint8_t { bind, unbind, enable, disable, setup, suspend, resume, other };

struct FfsEvent {
  FfsEventType type = FfsEventType::other;
  usb_ctrlrequest setup{};
};

class FunctionFs {
 public:
  // Mounts functionfs instance `instance` at `mount_dir` (created if missing).
  FunctionFs(std::string instance, std::string mount_dir);
  ~FunctionFs();
  FunctionFs(const FunctionFs&) = delete;
  FunctionFs& operator=(const FunctionFs&) = delete;

  // Writes descriptors (full and high speed) and strings. `all_control_requests`: also receive
  // vendor requests addressed to the device, not only to our interfaces. After this the
  // endpoint files ep1..epN exist, numbered in the order the endpoints were listed.
  void describe(const std::vector<InterfaceSpec>& interfaces, bool all_control_requests);

  // Opens every endpoint file; fds in listing order.
  const std::vector<int>& open_endpoints();

  // Blocks for the next ep0 event.
  FfsEvent next_event();
  // Completes the status stage of a setup request without data (host-to-device, wLength 0),
  // or reads its `length` data bytes.
  std::vector<std::uint8_t> accept_setup(std::size_t length);
  // Answers a device-to-host setup request with data.
  void reply_setup(const std::vector<std::uint8_t>& data);
  // Refuses the request (the host sees a stall).
  void stall_setup(const usb_ctrlrequest& request);

  // Halts endpoint file `fd` (IN endpoint): the host sees -EPIPE until it clears the halt.
  static void halt_in_endpoint(int fd);

 private:
  std::string instance_;
  std::string mount_dir_;
  int ep0_ = -1;
  std::vector<int> endpoints_;
  std::size_t endpoint_count_ = 0;
  bool mounted_ = false;
};

}  // namespace bolo::hil

#pragma once
// A USB device through the kernel's Raw Gadget (/dev/raw-gadget, raw_gadget.ko: built out of
// tree by toolchain/vm/raw-gadget.sh): every control request reaches this program, which answers
// GET_DESCRIPTOR itself and acks or stalls the rest; endpoints are enabled from descriptors the
// program writes. One object is one plug-in: closing it unplugs the device.

#include <linux/usb/ch9.h>
#include <linux/usb/raw_gadget.h>

#include <cstdint>
#include <string>
#include <vector>

namespace bolo::hil {

struct RawEndpoint {  // one UDC endpoint as USB_RAW_IOCTL_EPS_INFO reports it
  std::string name;
  std::uint8_t number = 0;  // USB_RAW_EP_ADDR_ANY: any number
  bool bulk = false, interrupt = false, in = false, out = false;
};

struct RawEvent {
  enum class Type : std::uint8_t { connect, control, interrupted, other } type = Type::other;
  usb_ctrlrequest setup{};
};

class RawGadget {
 public:
  // Opens /dev/raw-gadget and binds to UDC `device` of driver `driver` (BOLO_HIL_UDC or the first
  // in /sys/class/udc when empty) at high speed: the host sees the device plugged in. Throws naming
  // the step that failed.
  explicit RawGadget(std::string device = {});
  ~RawGadget();  // unplugs
  RawGadget(const RawGadget&) = delete;
  RawGadget& operator=(const RawGadget&) = delete;

  // Blocks for the next event; `interrupted` when a signal cut the wait (see unplug use).
  RawEvent next_event();
  std::vector<RawEndpoint> endpoints();  // after the connect event
  // Completes a request: OUT with its data stage read (`length` bytes), IN with `data`; or stalls it.
  bool ack_out(std::size_t length);
  bool reply_in(const std::vector<std::uint8_t>& data);
  void stall();
  // Enables an endpoint from its descriptor; returns the handle for write/halt. Throws on failure.
  int enable(const usb_endpoint_descriptor& descriptor);
  void configure();  // after SET_CONFIGURATION: the UDC may draw bus power, endpoints run
  // One bulk IN transfer on endpoint handle `ep` (blocks until the host took it); false on failure.
  bool write(int ep, const std::uint8_t* data, std::size_t size);
  void halt(int ep);

 private:
  int fd_ = -1;
};

}  // namespace bolo::hil

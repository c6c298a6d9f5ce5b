#pragma once
// The libusb-1.0 side of the USB sources (host/board code with the OS; built only where
// libusb-1.0 is found, BOLO_HAVE_LIBUSB). Opens the first device with a matching VID:PID, claims
// its interfaces, finds the bulk IN endpoint in the configuration descriptor (never a fixed
// address), keeps asynchronous transfers in flight, reports an unplug as `disconnected` and
// reopens the device on reconnect() (polled every 100 ms).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "bolo/hal/usb_transport.hpp"

namespace bolo::hal {

enum class EndpointChoice : std::uint8_t {
  first_bulk_in,  // the first bulk IN endpoint of the lowest interface that has one (Seek: 0x81)
  last_bulk_in,   // the bulk IN endpoint of the highest interface that has one (FLIR ONE: 0x85)
};

struct ControlStep {  // one control transfer without data (a stream start or stop)
  std::uint8_t request_type, request;
  std::uint16_t value, index;
  bool index_is_stream_interface = false;  // wIndex = the interface the bulk IN endpoint is on
};

struct LibusbConfig {
  std::uint16_t vendor_id = 0;
  std::vector<std::uint16_t> product_ids;
  EndpointChoice endpoint = EndpointChoice::first_bulk_in;
  bool claim_all_interfaces = false;  // else interface 0 only
  // Sent after claiming / before releasing, in order. A failed step is not fatal: devices that
  // stream on their own (or refuse the request) still work.
  std::vector<ControlStep> start;
  std::vector<ControlStep> stop;
  bool streaming = false;             // keep `in_flight` reads queued (else one read per next())
  std::size_t transfer_bytes = std::size_t{64} * 1024;
  int in_flight = 4;
};

// What the descriptors said, for `bolo devices` and the logs.
struct LibusbOpened {
  std::uint16_t vendor_id = 0, product_id = 0;
  std::uint8_t bus = 0, address = 0, endpoint = 0;
  int interface_number = -1;
};

class LibusbTransport final : public VendorUsbTransport {
 public:
  // Throws std::runtime_error naming the VID:PID when no device matches or it cannot be opened.
  explicit LibusbTransport(const LibusbConfig& config);
  ~LibusbTransport() override;
  LibusbTransport(const LibusbTransport&) = delete;
  LibusbTransport& operator=(const LibusbTransport&) = delete;

  Transfer next(std::span<std::uint8_t> buffer, std::uint32_t timeout_ms) override;
  bool reconnect(std::uint32_t timeout_ms) override;
  Transfer control_out(std::uint8_t code, std::span<const std::uint8_t> data) override;
  Transfer control_in(std::uint8_t code, std::span<std::uint8_t> data) override;

  const LibusbOpened& opened() const { return opened_; }

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
  LibusbOpened opened_;
};

struct UsbDeviceEntry {
  std::uint16_t vendor_id, product_id;
  std::uint8_t bus, address;
  std::string what;  // the backend that knows it, e.g. "usb:flirone (FLIR ONE Pro)"
};
// USB devices with a known VID:PID (FLIR ONE Pro, Seek Compact/Pro, PureThermal, Boson control).
std::vector<UsbDeviceEntry> list_known_usb_devices();

// The configurations of the known cores. FLIR ONE: streaming is switched on and off with request
// 0x0b (wValue 1 / 0) to the frame interface, as the project's FLIR ONE emulator
// (tests/hil/emulators) implements it; the protocol facts only say "vendor control transfers".
LibusbConfig flirone_libusb_config();
LibusbConfig seek_libusb_config();

}  // namespace bolo::hal

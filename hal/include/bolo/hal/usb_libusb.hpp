#pragma once
// The libusb-1.0 side of the USB sources (host/board code with the OS; built only where
// libusb-1.0 is found, BOLO_HAVE_LIBUSB). Opens the first device with a matching VID:PID, brings
// it up with the configuration's start steps (or claims interface 0), finds the bulk IN endpoint
// in the configuration descriptor (never a fixed address), keeps asynchronous transfers in
// flight, reports an unplug as `disconnected` and reopens the device on reconnect() (polled
// every 100 ms).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "bolo/hal/usb_setup.hpp"
#include "bolo/hal/usb_transport.hpp"

namespace bolo::hal {

enum class EndpointChoice : std::uint8_t {
  first_bulk_in,  // the first bulk IN endpoint of the lowest interface that has one (Seek: 0x81)
  last_bulk_in,   // the bulk IN endpoint of the highest interface that has one (FLIR ONE: 0x85)
};

struct LibusbConfig {
  std::uint16_t vendor_id = 0;
  std::vector<std::uint16_t> product_ids;
  EndpointChoice endpoint = EndpointChoice::first_bulk_in;
  // Run at each open, in order (usb_setup.hpp); a refused step fails the open, naming the step.
  // Empty: interface 0 is claimed and nothing is sent.
  std::vector<UsbSetupStep> start;
  // Run before the interfaces are released (not after an unplug); refusals are only counted.
  std::vector<UsbSetupStep> stop;
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

// The configurations of the known cores. FLIR ONE: the public drivers' start and stop sequence
// (flirone::kStartSteps / kStopSteps).
LibusbConfig flirone_libusb_config();
LibusbConfig seek_libusb_config();

}  // namespace bolo::hal

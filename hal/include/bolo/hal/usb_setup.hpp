#pragma once
// Standard requests that bring a USB device up or take it down (configuration, interface claims,
// alternate settings) as a list of steps run through a UsbDeviceSetup: libusb on a device, a
// scripted fake in tests, so the order a source sends is the order a test can check.
// Board-safe: no heap, no exceptions.

#include <cstddef>
#include <cstdint>
#include <span>

namespace bolo::hal {

enum class UsbSetupKind : std::uint8_t {
  set_configuration,  // SET_CONFIGURATION `number`
  claim_interface,    // claim interface `number` on the host side (no request on the wire)
  set_interface,      // standard SET_INTERFACE: bmRequestType 0x01, bRequest 0x0b,
                      // wValue `alternate`, wIndex `number`, no data
};

struct UsbSetupStep {
  UsbSetupKind kind;
  std::uint8_t number;
  std::uint8_t alternate = 0;
};

class UsbDeviceSetup {
 public:
  virtual ~UsbDeviceSetup() = default;
  // Each true when the device (or the host stack) accepted the step.
  virtual bool set_configuration(std::uint8_t configuration) = 0;
  virtual bool claim_interface(std::uint8_t interface) = 0;
  virtual bool set_interface(std::uint8_t interface, std::uint8_t alternate) = 0;
};

// Runs `steps` in order up to the first one refused; returns how many were accepted (all of them
// when it equals steps.size()).
std::size_t run_usb_setup(UsbDeviceSetup& device, std::span<const UsbSetupStep> steps);

// "SET_INTERFACE 1 alt 1" and the like, into `out` (NUL-terminated, cut to `size`).
void describe_usb_step(const UsbSetupStep& step, char* out, std::size_t size);

// FLIR ONE (Gen 3, Pro), as its public drivers bring it up (usb-thermal-cores.md): configuration
// 3, interfaces 0-2 claimed, frames stopped (interface 2 alt 0), file I/O stopped (1 alt 0),
// file I/O started (1 alt 1), frames started (2 alt 1). Stop: frames, then file I/O, to alt 0.
namespace flirone {
inline constexpr std::uint8_t kConfiguration = 3;
inline constexpr std::uint8_t kFileInterface = 1, kFrameInterface = 2;
inline constexpr UsbSetupStep kStartSteps[] = {
    {UsbSetupKind::set_configuration, kConfiguration},
    {UsbSetupKind::claim_interface, 0},
    {UsbSetupKind::claim_interface, kFileInterface},
    {UsbSetupKind::claim_interface, kFrameInterface},
    {UsbSetupKind::set_interface, kFrameInterface, 0},
    {UsbSetupKind::set_interface, kFileInterface, 0},
    {UsbSetupKind::set_interface, kFileInterface, 1},
    {UsbSetupKind::set_interface, kFrameInterface, 1},
};
inline constexpr UsbSetupStep kStopSteps[] = {
    {UsbSetupKind::set_interface, kFrameInterface, 0},
    {UsbSetupKind::set_interface, kFileInterface, 0},
};
}  // namespace flirone

}  // namespace bolo::hal

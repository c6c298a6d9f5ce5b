#include "bolo/hal/usb_setup.hpp"

#include <cstdio>

namespace bolo::hal {

std::size_t run_usb_setup(UsbDeviceSetup& device, std::span<const UsbSetupStep> steps) {
  std::size_t done = 0;
  for (const UsbSetupStep& s : steps) {
    bool ok = false;
    switch (s.kind) {
      case UsbSetupKind::set_configuration: ok = device.set_configuration(s.number); break;
      case UsbSetupKind::claim_interface: ok = device.claim_interface(s.number); break;
      case UsbSetupKind::set_interface: ok = device.set_interface(s.number, s.alternate); break;
    }
    if (!ok) break;
    ++done;
  }
  return done;
}

void describe_usb_step(const UsbSetupStep& step, char* out, std::size_t size) {
  switch (step.kind) {
    case UsbSetupKind::set_configuration: std::snprintf(out, size, "SET_CONFIGURATION %u", step.number); break;
    case UsbSetupKind::claim_interface: std::snprintf(out, size, "claim interface %u", step.number); break;
    case UsbSetupKind::set_interface:
      std::snprintf(out, size, "SET_INTERFACE %u alt %u", step.number, step.alternate);
      break;
  }
}

}  // namespace bolo::hal

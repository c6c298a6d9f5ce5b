#include "flirone_control.hpp"

#include <cstdio>

namespace bolo::hil::flirone {

namespace {

constexpr std::uint8_t kStandardOutInterface = USB_DIR_OUT | USB_TYPE_STANDARD | USB_RECIP_INTERFACE;
constexpr std::uint8_t kStandardOutDevice = USB_DIR_OUT | USB_TYPE_STANDARD | USB_RECIP_DEVICE;

struct Step {
  std::uint16_t interface, alternate;
};
// The public drivers' start sequence after SET_CONFIGURATION 3 (usb-thermal-cores.md).
constexpr Step kStart[] = {{2, 0}, {1, 0}, {1, 1}, {2, 1}};

std::string describe(const usb_ctrlrequest& r) {
  char text[96];
  std::snprintf(text, sizeof text, "bmRequestType 0x%02x bRequest 0x%02x wValue %u wIndex %u wLength %u",
                r.bRequestType, r.bRequest, r.wValue, r.wIndex, r.wLength);
  return text;
}

void put16(std::vector<std::uint8_t>& b, std::uint16_t v) {
  b.push_back(static_cast<std::uint8_t>(v & 0xFF));
  b.push_back(static_cast<std::uint8_t>(v >> 8));
}

std::vector<std::uint8_t> string_descriptor(const std::string& text) {
  std::vector<std::uint8_t> b{static_cast<std::uint8_t>(2 + 2 * text.size()), USB_DT_STRING};
  for (char c : text) put16(b, static_cast<std::uint8_t>(c));
  return b;
}

}  // namespace

bool StartupChecker::refuse(const usb_ctrlrequest& r, const std::string& why) {
  ++refused_;
  last_refusal_ = describe(r) + ": " + why;
  return false;
}

bool StartupChecker::take(const usb_ctrlrequest& r) {
  if (r.bRequestType == kStandardOutDevice && r.bRequest == USB_REQ_SET_CONFIGURATION) {
    if (r.wValue != kConfiguration && r.wValue != 0) return refuse(r, "the camera has configuration 3 only");
    if (r.wLength != 0) return refuse(r, "SET_CONFIGURATION carries no data");
    configured_ = r.wValue == kConfiguration;  // 0: back to the address state
    step_ = 0;
    return true;
  }
  if (r.bRequestType == kStandardOutInterface && r.bRequest == USB_REQ_SET_INTERFACE) {
    if (!configured_) return refuse(r, "SET_INTERFACE before SET_CONFIGURATION 3");
    // Stopping from streaming: frames (2 alt 0), then file I/O (1 alt 0), i.e. the start
    // sequence's first two steps again.
    const std::size_t expected = step_ == kSteps ? 0 : step_;
    const Step& s = kStart[expected];
    if (r.wIndex != s.interface || r.wValue != s.alternate)
      return refuse(r, "expected SET_INTERFACE " + std::to_string(s.interface) + " alt " +
                           std::to_string(s.alternate) + " (start step " + std::to_string(expected + 1) + " of 4)");
    // No data (the standard request); flirone-v4l2 sends two zero bytes with the last step.
    const bool last = expected == kSteps - 1;
    if (r.wLength != 0 && !(last && r.wLength == 2)) return refuse(r, "unexpected data stage");
    step_ = expected + 1;
    return true;
  }
  return refuse(r, "not a request of the drivers' start-up");
}

void StartupChecker::unplugged() {
  configured_ = false;
  step_ = 0;
}

Descriptors make_descriptors(const EndpointPair (&endpoints)[kInterfaces]) {
  Descriptors d;
  d.device = {USB_DT_DEVICE_SIZE, USB_DT_DEVICE};
  put16(d.device, 0x0200);                    // bcdUSB
  d.device.insert(d.device.end(), {0, 0, 0, 64});  // class per interface, ep0 64 bytes
  put16(d.device, 0x09cb);
  put16(d.device, 0x1996);
  put16(d.device, 0x0100);
  d.device.insert(d.device.end(), {1, 2, 3, 1});  // strings, one configuration

  static const char* const kNames[kInterfaces] = {"iAP Interface", "com.flir.rosebud.fileio", "com.flir.rosebud.frame"};
  std::vector<std::uint8_t>& c = d.configuration;
  c = {USB_DT_CONFIG_SIZE, USB_DT_CONFIG, 0, 0, kInterfaces, kConfiguration, 0, 0x80, 250};
  for (int i = 0; i < kInterfaces; ++i)
    for (std::uint8_t alt = 0; alt < 2; ++alt) {
      c.insert(c.end(), {USB_DT_INTERFACE_SIZE, USB_DT_INTERFACE, static_cast<std::uint8_t>(i), alt, 2,
                         USB_CLASS_VENDOR_SPEC, USB_CLASS_VENDOR_SPEC, 0, static_cast<std::uint8_t>(4 + i)});
      for (std::uint8_t address : {endpoints[i].in, endpoints[i].out}) {
        c.insert(c.end(), {USB_DT_ENDPOINT_SIZE, USB_DT_ENDPOINT, address, USB_ENDPOINT_XFER_BULK});
        put16(c, 512);
        c.push_back(0);
      }
    }
  c[2] = static_cast<std::uint8_t>(c.size() & 0xFF);
  c[3] = static_cast<std::uint8_t>(c.size() >> 8);

  d.strings.push_back({4, USB_DT_STRING, 0x09, 0x04});
  for (const char* s : {"FLIR Systems", "FLIR ONE Camera", "bolo-hil-emulated"}) d.strings.push_back(string_descriptor(s));
  for (const char* s : kNames) d.strings.push_back(string_descriptor(s));
  return d;
}

bool descriptor_for(const Descriptors& d, const usb_ctrlrequest& r, std::vector<std::uint8_t>& out) {
  const std::uint8_t type = static_cast<std::uint8_t>(r.wValue >> 8), index = static_cast<std::uint8_t>(r.wValue & 0xFF);
  if (type == USB_DT_DEVICE) out = d.device;
  else if (type == USB_DT_CONFIG && index == 0) out = d.configuration;
  else if (type == USB_DT_STRING && index < d.strings.size()) out = d.strings[index];
  else return false;
  if (out.size() > r.wLength) out.resize(r.wLength);
  return true;
}

}  // namespace bolo::hil::flirone

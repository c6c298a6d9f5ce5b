#include "flirone_usb.hpp"

#include <stdexcept>
#include <thread>

namespace bolo::hil::flirone {

namespace {
constexpr std::uint16_t kVendor = 0x09cb;
constexpr std::uint16_t kProduct = 0x1996;
constexpr int kFrameInterface = 2;
constexpr int kConfiguration = 3;
constexpr std::uint8_t kSetInterface = 0x0b;
constexpr std::uint8_t kStandardToInterface = 0x01;  // standard request, host to interface
}  // namespace

FlirOneUsb::FlirOneUsb() {
  if (libusb_init(&context_) != 0) throw std::runtime_error("libusb_init failed");
}

FlirOneUsb::~FlirOneUsb() {
  close();
  libusb_exit(context_);
}

void FlirOneUsb::close() {
  if (handle_ == nullptr) return;
  for (int i = 0; i <= kFrameInterface; ++i) libusb_release_interface(handle_, i);
  libusb_close(handle_);
  handle_ = nullptr;
}

bool FlirOneUsb::try_open(std::string& error, bool drivers_start) {
  // Without udevd (the HIL VM, minimal boards) libusb learns of no hot-plug: a fresh context
  // rescans sysfs, so a replugged device is seen.
  libusb_exit(context_);
  context_ = nullptr;
  if (libusb_init(&context_) != 0) throw std::runtime_error("libusb_init failed");
  handle_ = libusb_open_device_with_vid_pid(context_, kVendor, kProduct);
  if (handle_ == nullptr) {
    error = "09cb:1996 not found";
    return false;
  }
  // Configuration 3 before anything is claimed (the kernel refuses to change it under a claim).
  if (const int rc = libusb_set_configuration(handle_, kConfiguration); rc != 0) {
    error = std::string("SET_CONFIGURATION 3: ") + libusb_error_name(rc);
    close();
    return false;
  }
  libusb_config_descriptor* config = nullptr;
  if (libusb_get_active_config_descriptor(libusb_get_device(handle_), &config) != 0) {
    error = "no active configuration";
    close();
    return false;
  }
  endpoint_ = 0;
  if (config->bNumInterfaces > kFrameInterface) {
    const libusb_interface_descriptor& alt = config->interface[kFrameInterface].altsetting[0];
    for (int e = 0; e < alt.bNumEndpoints; ++e) {
      const libusb_endpoint_descriptor& ep = alt.endpoint[e];
      if ((ep.bEndpointAddress & LIBUSB_ENDPOINT_IN) != 0 &&
          (ep.bmAttributes & 3) == LIBUSB_TRANSFER_TYPE_BULK)
        endpoint_ = ep.bEndpointAddress;
    }
  }
  libusb_free_config_descriptor(config);
  if (endpoint_ == 0) {
    error = "interface 2 has no bulk IN endpoint";
    close();
    return false;
  }
  for (int i = 0; i <= kFrameInterface; ++i) {
    const int rc = libusb_claim_interface(handle_, i);
    if (rc != 0) {
      error = "claim interface " + std::to_string(i) + ": " + libusb_error_name(rc);
      close();
      return false;
    }
  }
  if (!drivers_start) {
    vendor_start_result_ = libusb_control_transfer(handle_, 0x41, kSetInterface, 1, kFrameInterface, nullptr, 0, 1000);
    return true;
  }
  // The public drivers' start sequence, standard SET_INTERFACE requests sent as control
  // transfers: stop frames, stop file I/O, start file I/O, start frames.
  const std::pair<std::uint16_t, std::uint16_t> sequence[] = {{0, 2}, {0, 1}, {1, 1}, {1, 2}};
  for (const auto& [value, interface] : sequence) {
    const int rc = libusb_control_transfer(handle_, kStandardToInterface, kSetInterface, value, interface,
                                           nullptr, 0, 1000);
    if (rc < 0) {
      error = "SET_INTERFACE " + std::to_string(interface) + " alt " + std::to_string(value) + ": " +
              libusb_error_name(rc);
      close();
      return false;
    }
  }
  return true;
}

bool FlirOneUsb::open(std::chrono::milliseconds patience, std::string& error) {
  const auto deadline = std::chrono::steady_clock::now() + patience;
  for (;;) {
    if (try_open(error, true)) return true;
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

int FlirOneUsb::open_with_vendor_start(std::chrono::milliseconds patience, std::string& error) {
  const auto deadline = std::chrono::steady_clock::now() + patience;
  vendor_start_result_ = 1;
  while (!try_open(error, false)) {
    if (std::chrono::steady_clock::now() >= deadline) return 1;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return vendor_start_result_;
}

ReadStatus FlirOneUsb::read(std::uint8_t* buffer, int size, int& transferred, unsigned timeout_ms) {
  transferred = 0;
  const int rc = libusb_bulk_transfer(handle_, endpoint_, buffer, size, &transferred, timeout_ms);
  if (rc == 0) return ReadStatus::data;
  if (rc == LIBUSB_ERROR_TIMEOUT) return transferred > 0 ? ReadStatus::data : ReadStatus::timeout;
  if (rc == LIBUSB_ERROR_PIPE) return ReadStatus::stall;
  return ReadStatus::gone;
}

void FlirOneUsb::clear_stall() { libusb_clear_halt(handle_, endpoint_); }

}  // namespace bolo::hil::flirone

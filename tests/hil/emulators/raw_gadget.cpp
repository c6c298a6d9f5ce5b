#include "raw_gadget.hpp"
#include "udc.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace bolo::hil {

namespace {

// The UDC's driver name: dummy_hcd's UDC "dummy_udc.0" belongs to driver "dummy_udc".
std::string udc_driver(const std::string& device) {
  const std::string link = "/sys/class/udc/" + device + "/device/driver";
  char target[512];
  const ssize_t n = ::readlink(link.c_str(), target, sizeof target - 1);
  if (n <= 0) throw std::runtime_error(link + ": " + std::strerror(errno));
  target[n] = 0;
  const std::string name = target;
  return name.substr(name.rfind('/') + 1);
}

}  // namespace

RawGadget::RawGadget(std::string device) {
  if (device.empty()) device = first_udc();
  const std::string driver = udc_driver(device);
  fd_ = ::open("/dev/raw-gadget", O_RDWR);
  if (fd_ < 0) throw std::runtime_error(std::string("/dev/raw-gadget: ") + std::strerror(errno) + " (raw_gadget.ko loaded?)");
  usb_raw_init init{};
  std::strncpy(reinterpret_cast<char*>(init.driver_name), driver.c_str(), UDC_NAME_LENGTH_MAX - 1);
  std::strncpy(reinterpret_cast<char*>(init.device_name), device.c_str(), UDC_NAME_LENGTH_MAX - 1);
  init.speed = USB_SPEED_HIGH;
  if (::ioctl(fd_, USB_RAW_IOCTL_INIT, &init) < 0)
    throw std::runtime_error("raw-gadget: init on " + driver + "/" + device + ": " + std::strerror(errno));
  if (::ioctl(fd_, USB_RAW_IOCTL_RUN, 0) < 0) throw std::runtime_error(std::string("raw-gadget: run: ") + std::strerror(errno));
}

RawGadget::~RawGadget() {
  if (fd_ >= 0) ::close(fd_);
}

RawEvent RawGadget::next_event() {
  // The event header, then room for its data (a setup packet).
  alignas(usb_raw_event) std::uint8_t buffer[sizeof(usb_raw_event) + sizeof(usb_ctrlrequest)] = {};
  auto* event = reinterpret_cast<usb_raw_event*>(buffer);
  event->length = sizeof(usb_ctrlrequest);
  RawEvent out;
  if (::ioctl(fd_, USB_RAW_IOCTL_EVENT_FETCH, event) < 0) {
    if (errno == EINTR) {
      out.type = RawEvent::Type::interrupted;
      return out;
    }
    throw std::runtime_error(std::string("raw-gadget: event fetch: ") + std::strerror(errno));
  }
  if (event->type == USB_RAW_EVENT_CONNECT) out.type = RawEvent::Type::connect;
  if (event->type == USB_RAW_EVENT_CONTROL) {
    out.type = RawEvent::Type::control;
    std::memcpy(&out.setup, buffer + sizeof(usb_raw_event), sizeof out.setup);
  }
  return out;
}

std::vector<RawEndpoint> RawGadget::endpoints() {
  usb_raw_eps_info info{};
  const int n = ::ioctl(fd_, USB_RAW_IOCTL_EPS_INFO, &info);
  if (n < 0) throw std::runtime_error(std::string("raw-gadget: endpoint info: ") + std::strerror(errno));
  std::vector<RawEndpoint> out;
  for (int i = 0; i < n; ++i) {
    const usb_raw_ep_info& e = info.eps[i];
    RawEndpoint ep;
    ep.name = reinterpret_cast<const char*>(e.name);
    ep.number = static_cast<std::uint8_t>(e.addr);
    ep.bulk = e.caps.type_bulk;
    ep.interrupt = e.caps.type_int;
    ep.in = e.caps.dir_in;
    ep.out = e.caps.dir_out;
    out.push_back(ep);
  }
  return out;
}

bool RawGadget::ack_out(std::size_t length) {
  std::vector<std::uint8_t> buffer(sizeof(usb_raw_ep_io) + length);
  auto* io = reinterpret_cast<usb_raw_ep_io*>(buffer.data());
  io->ep = 0;
  io->flags = 0;
  io->length = static_cast<std::uint32_t>(length);
  return ::ioctl(fd_, USB_RAW_IOCTL_EP0_READ, io) >= 0;
}

bool RawGadget::reply_in(const std::vector<std::uint8_t>& data) {
  std::vector<std::uint8_t> buffer(sizeof(usb_raw_ep_io) + data.size());
  auto* io = reinterpret_cast<usb_raw_ep_io*>(buffer.data());
  io->ep = 0;
  io->flags = 0;
  io->length = static_cast<std::uint32_t>(data.size());
  std::memcpy(buffer.data() + sizeof(usb_raw_ep_io), data.data(), data.size());
  return ::ioctl(fd_, USB_RAW_IOCTL_EP0_WRITE, io) >= 0;
}

void RawGadget::stall() { (void)::ioctl(fd_, USB_RAW_IOCTL_EP0_STALL, 0); }

int RawGadget::enable(const usb_endpoint_descriptor& descriptor) {
  const int handle = ::ioctl(fd_, USB_RAW_IOCTL_EP_ENABLE, &descriptor);
  if (handle < 0)
    throw std::runtime_error("raw-gadget: enabling endpoint " + std::to_string(descriptor.bEndpointAddress) + ": " +
                             std::strerror(errno));
  return handle;
}

void RawGadget::configure() {
  (void)::ioctl(fd_, USB_RAW_IOCTL_VBUS_DRAW, 100);  // 2 mA units: 200 mA
  (void)::ioctl(fd_, USB_RAW_IOCTL_CONFIGURE, 0);
}

bool RawGadget::write(int ep, const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> buffer(sizeof(usb_raw_ep_io) + size);
  auto* io = reinterpret_cast<usb_raw_ep_io*>(buffer.data());
  io->ep = static_cast<std::uint16_t>(ep);
  io->flags = 0;
  io->length = static_cast<std::uint32_t>(size);
  std::memcpy(buffer.data() + sizeof(usb_raw_ep_io), data, size);
  for (;;) {
    const int n = ::ioctl(fd_, USB_RAW_IOCTL_EP_WRITE, io);
    if (n >= 0) return static_cast<std::size_t>(n) == size;
    if (errno != EINTR) return false;
  }
}

void RawGadget::halt(int ep) { (void)::ioctl(fd_, USB_RAW_IOCTL_EP_SET_HALT, ep); }

}  // namespace bolo::hil

#include "functionfs.hpp"

#include <fcntl.h>
#include <linux/usb/functionfs.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace bolo::hil {

namespace {

void put_le16(std::vector<std::uint8_t>& out, std::uint32_t v) {
  out.push_back(static_cast<std::uint8_t>(v));
  out.push_back(static_cast<std::uint8_t>(v >> 8));
}

void put_le32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  put_le16(out, v & 0xFFFF);
  put_le16(out, v >> 16);
}

void set_le32(std::vector<std::uint8_t>& out, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out[at + i] = static_cast<std::uint8_t>(v >> (8 * i));
}

// One speed's descriptor list; returns how many descriptors were appended.
std::uint32_t append_descriptors(std::vector<std::uint8_t>& out,
                                 const std::vector<InterfaceSpec>& interfaces,
                                 std::uint16_t bulk_packet) {
  std::uint32_t count = 0;
  std::uint8_t endpoint_number = 1;
  for (std::size_t i = 0; i < interfaces.size(); ++i) {
    const InterfaceSpec& spec = interfaces[i];
    out.insert(out.end(), {USB_DT_INTERFACE_SIZE, USB_DT_INTERFACE, static_cast<std::uint8_t>(i), 0,
                           static_cast<std::uint8_t>(spec.endpoints.size()), spec.interface_class,
                           spec.interface_subclass, spec.interface_protocol,
                           static_cast<std::uint8_t>(i + 1)});
    ++count;
    for (const EndpointSpec& ep : spec.endpoints) {
      const bool interrupt = (ep.attributes & USB_ENDPOINT_XFERTYPE_MASK) == USB_ENDPOINT_XFER_INT;
      out.insert(out.end(), {USB_DT_ENDPOINT_SIZE, USB_DT_ENDPOINT,
                             static_cast<std::uint8_t>((ep.in ? USB_DIR_IN : USB_DIR_OUT) | endpoint_number++),
                             ep.attributes});
      put_le16(out, interrupt ? 64 : bulk_packet);
      out.push_back(interrupt ? 4 : 0);
      ++count;
    }
  }
  return count;
}

}  // namespace

FunctionFs::FunctionFs(std::string instance, std::string mount_dir)
    : instance_(std::move(instance)), mount_dir_(std::move(mount_dir)) {
  if (::mkdir(mount_dir_.c_str(), 0755) != 0 && errno != EEXIST)
    throw std::runtime_error(mount_dir_ + ": " + std::strerror(errno));
  if (::mount(instance_.c_str(), mount_dir_.c_str(), "functionfs", 0, nullptr) != 0)
    throw std::runtime_error("mount functionfs '" + instance_ + "' on " + mount_dir_ + ": " +
                             std::strerror(errno));
  mounted_ = true;
  const std::string ep0 = mount_dir_ + "/ep0";
  ep0_ = ::open(ep0.c_str(), O_RDWR);
  if (ep0_ < 0) throw std::runtime_error(ep0 + ": " + std::strerror(errno));
}

FunctionFs::~FunctionFs() {
  for (int fd : endpoints_) ::close(fd);
  if (ep0_ >= 0) ::close(ep0_);
  if (mounted_) ::umount(mount_dir_.c_str());
}

void FunctionFs::describe(const std::vector<InterfaceSpec>& interfaces, bool all_control_requests) {
  std::vector<std::uint8_t> blob;
  put_le32(blob, FUNCTIONFS_DESCRIPTORS_MAGIC_V2);
  put_le32(blob, 0);  // length, set below
  std::uint32_t flags = FUNCTIONFS_HAS_FS_DESC | FUNCTIONFS_HAS_HS_DESC;
  if (all_control_requests) flags |= FUNCTIONFS_ALL_CTRL_RECIP;
  put_le32(blob, flags);
  const std::size_t counts_at = blob.size();
  put_le32(blob, 0);
  put_le32(blob, 0);
  const std::uint32_t fs = append_descriptors(blob, interfaces, 64);
  const std::uint32_t hs = append_descriptors(blob, interfaces, 512);
  set_le32(blob, 4, static_cast<std::uint32_t>(blob.size()));
  set_le32(blob, counts_at, fs);
  set_le32(blob, counts_at + 4, hs);
  if (::write(ep0_, blob.data(), blob.size()) != static_cast<ssize_t>(blob.size()))
    throw std::runtime_error(mount_dir_ + "/ep0: descriptors refused: " + std::strerror(errno));

  std::vector<std::uint8_t> strings;
  put_le32(strings, FUNCTIONFS_STRINGS_MAGIC);
  put_le32(strings, 0);
  put_le32(strings, static_cast<std::uint32_t>(interfaces.size()));
  put_le32(strings, 1);
  put_le16(strings, 0x0409);
  for (const InterfaceSpec& spec : interfaces) {
    strings.insert(strings.end(), spec.name.begin(), spec.name.end());
    strings.push_back(0);
  }
  set_le32(strings, 4, static_cast<std::uint32_t>(strings.size()));
  if (::write(ep0_, strings.data(), strings.size()) != static_cast<ssize_t>(strings.size()))
    throw std::runtime_error(mount_dir_ + "/ep0: strings refused: " + std::strerror(errno));

  endpoint_count_ = 0;
  for (const InterfaceSpec& spec : interfaces) endpoint_count_ += spec.endpoints.size();
}

const std::vector<int>& FunctionFs::open_endpoints() {
  for (std::size_t i = 1; i <= endpoint_count_; ++i) {
    const std::string path = mount_dir_ + "/ep" + std::to_string(i);
    const int fd = ::open(path.c_str(), O_RDWR);
    if (fd < 0) throw std::runtime_error(path + ": " + std::strerror(errno));
    endpoints_.push_back(fd);
  }
  return endpoints_;
}

FfsEvent FunctionFs::next_event() {
  constexpr int kLinkDownPollMicroseconds = 2000;
  constexpr int kLinkDownReads = 15000;  // 30 s
  int link_down_reads = 0;
  usb_functionfs_event raw{};
  for (;;) {
    const ssize_t n = ::read(ep0_, &raw, sizeof raw);
    if (n == static_cast<ssize_t>(sizeof raw)) break;
    if (n < 0 && errno == EINTR) continue;
    // EIDRM: the setup request this program had not answered yet was cancelled (the host gave up
    // on it and went on: a new request or a reset came first). FunctionFS reports that once, on
    // the next ep0 read; the events that follow are read as usual.
    if (n < 0 && errno == EIDRM) continue;
    // EL2HLT: an IN request whose answer never went out was still pending; this read stalled it
    // and cleared it, so the next read returns events again.
    if (n < 0 && errno == EL2HLT) continue;
    // ESHUTDOWN: an OUT request's data stage could not be queued because the link went down
    // (an unplug raced the request). The request stays pending, so the read tries to queue it
    // again until FunctionFS sees the unplug's event and cancels it (EIDRM above); only a link
    // that stays down for long is an error.
    if (n < 0 && errno == ESHUTDOWN) {
      if (link_down_reads == 0)
        std::fprintf(stderr, "%s/ep0: link down with a request pending; waiting for the unplug\n",
                     mount_dir_.c_str());
      if (++link_down_reads <= kLinkDownReads) {
        ::usleep(kLinkDownPollMicroseconds);
        continue;
      }
    }
    throw std::runtime_error(mount_dir_ + "/ep0: event read failed: " + std::strerror(errno));
  }
  FfsEvent event;
  switch (raw.type) {
    case FUNCTIONFS_BIND: event.type = FfsEventType::bind; break;
    case FUNCTIONFS_UNBIND: event.type = FfsEventType::unbind; break;
    case FUNCTIONFS_ENABLE: event.type = FfsEventType::enable; break;
    case FUNCTIONFS_DISABLE: event.type = FfsEventType::disable; break;
    case FUNCTIONFS_SETUP: event.type = FfsEventType::setup; event.setup = raw.u.setup; break;
    case FUNCTIONFS_SUSPEND: event.type = FfsEventType::suspend; break;
    case FUNCTIONFS_RESUME: event.type = FfsEventType::resume; break;
    default: event.type = FfsEventType::other; break;
  }
  return event;
}

std::vector<std::uint8_t> FunctionFs::accept_setup(std::size_t length) {
  std::vector<std::uint8_t> data(length);
  // A read on ep0 acknowledges a host-to-device request (and fetches its data stage).
  const ssize_t n = ::read(ep0_, data.data(), data.size());
  if (n < 0) return {};
  data.resize(static_cast<std::size_t>(n));
  return data;
}

void FunctionFs::reply_setup(const std::vector<std::uint8_t>& data) {
  (void)::write(ep0_, data.data(), data.size());
}

void FunctionFs::stall_setup(const usb_ctrlrequest& request) {
  // I/O against the request's direction makes FunctionFS stall it.
  std::uint8_t byte = 0;
  if ((request.bRequestType & USB_DIR_IN) != 0)
    (void)::read(ep0_, &byte, 0);
  else
    (void)::write(ep0_, &byte, 0);
}

void FunctionFs::halt_in_endpoint(int fd) {
  // Reading an IN endpoint file is FunctionFS's way to set its halt feature.
  std::uint8_t byte = 0;
  (void)::read(fd, &byte, 1);
}

}  // namespace bolo::hil

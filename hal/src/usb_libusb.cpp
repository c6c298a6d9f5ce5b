#include "bolo/hal/usb_libusb.hpp"

#include <libusb.h>
#include <time.h>

#include <chrono>
#include <cstring>
#include <deque>
#include <iterator>
#include <stdexcept>
#include <thread>

#include "bolo/hal/seek_frame_parser.hpp"

namespace bolo::hal {
namespace {

std::int64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

std::string hex4(std::uint16_t v) {
  char s[8];
  std::snprintf(s, sizeof s, "%04x", v);
  return s;
}

constexpr std::uint8_t kVendorToInterface = 0x40 | 0x01;  // host-to-device, vendor, interface
constexpr std::uint8_t kVendorFromDevice = 0x80 | 0x40;   // device-to-host, vendor (| recipient)
constexpr std::uint8_t kRecipientInterface = 0x01, kRecipientDevice = 0x00;
constexpr std::uint8_t kStandardToInterface = 0x00 | 0x01;  // host-to-device, standard, interface
constexpr std::uint8_t kSetInterface = 0x0b;

TransferStatus status_of(int libusb_error) {
  switch (libusb_error) {
    case LIBUSB_SUCCESS: return TransferStatus::ok;
    case LIBUSB_ERROR_TIMEOUT: return TransferStatus::timeout;
    case LIBUSB_ERROR_NO_DEVICE: return TransferStatus::disconnected;
    default: return TransferStatus::error;
  }
}

}  // namespace

struct LibusbTransport::Impl {
  struct Slot {
    libusb_transfer* transfer = nullptr;
    std::vector<std::uint8_t> buffer;
    bool busy = false;
    Impl* owner = nullptr;
  };
  struct Done {
    Slot* slot;
    TransferStatus status;
    std::size_t bytes;
    std::int64_t arrival_ns;
  };

  LibusbConfig config;
  libusb_context* ctx = nullptr;
  libusb_device_handle* handle = nullptr;
  std::vector<int> claimed;
  std::uint8_t endpoint = 0;
  std::vector<Slot> slots;
  std::deque<Done> done;
  bool gone = false;
  // Set when transfers were still in flight at close: libusb keeps pointers to them, to their
  // buffers, the device handle and the context, so none of those may be freed (a bounded leak
  // per unplug in that rare case, instead of a use-after-free).
  bool context_pinned = false;
  std::vector<std::vector<std::uint8_t>> retired_buffers;

  static void LIBUSB_CALL on_complete(libusb_transfer* t) {
    Slot* slot = static_cast<Slot*>(t->user_data);
    if (!slot) return;  // retired (see retire_in_flight): nobody owns it any more
    slot->busy = false;
    TransferStatus s = TransferStatus::error;
    switch (t->status) {
      case LIBUSB_TRANSFER_COMPLETED: s = TransferStatus::ok; break;
      case LIBUSB_TRANSFER_TIMED_OUT: s = TransferStatus::timeout; break;
      case LIBUSB_TRANSFER_NO_DEVICE: s = TransferStatus::disconnected; break;
      case LIBUSB_TRANSFER_CANCELLED: return;  // closing: nobody waits for it
      case LIBUSB_TRANSFER_STALL: slot->owner->stalled = true; break;
      default: s = TransferStatus::error; break;
    }
    if (s == TransferStatus::disconnected) slot->owner->gone = true;
    slot->owner->done.push_back({slot, s, static_cast<std::size_t>(t->actual_length), monotonic_ns()});
  }

  // Opens the first matching device; false when there is none (or it cannot be opened yet).
  bool open(LibusbOpened& opened, std::string& why) {
    libusb_device** list = nullptr;
    const ssize_t n = libusb_get_device_list(ctx, &list);
    libusb_device* found = nullptr;
    libusb_device_descriptor desc{};
    for (ssize_t i = 0; i < n && !found; ++i) {
      if (libusb_get_device_descriptor(list[i], &desc) != 0 || desc.idVendor != config.vendor_id) continue;
      for (std::uint16_t pid : config.product_ids)
        if (desc.idProduct == pid) found = list[i];
    }
    if (!found) {
      libusb_free_device_list(list, 1);
      why = "no device";
      return false;
    }
    int rc = libusb_open(found, &handle);
    if (rc != 0) {
      libusb_free_device_list(list, 1);
      why = libusb_error_name(rc);
      handle = nullptr;
      return false;
    }
    opened.vendor_id = desc.idVendor;
    opened.product_id = desc.idProduct;
    opened.bus = libusb_get_bus_number(found);
    opened.address = libusb_get_device_address(found);
    if (!find_endpoint(found, opened)) {
      libusb_free_device_list(list, 1);
      close();
      why = "no bulk IN endpoint in the configuration descriptor";
      return false;
    }
    libusb_free_device_list(list, 1);
    libusb_set_auto_detach_kernel_driver(handle, 1);
    if (!bring_up(why)) {
      close();
      return false;
    }
    if (!alloc_transfers()) {
      close();
      why = "cannot allocate transfers";
      return false;
    }
    gone = false;
    endpoint = opened.endpoint;
    return true;
  }

  // The configuration's start steps, or interface 0 claimed; `why` names the step refused.
  bool bring_up(std::string& why) {
    if (config.start.empty()) {
      if (setup.claim_interface(0)) return true;
      why = std::string("claiming interface 0: ") + libusb_error_name(setup.last_error);
      return false;
    }
    const std::size_t done = run_usb_setup(setup, config.start);
    if (done == config.start.size()) return true;
    char step[48];
    describe_usb_step(config.start[done], step, sizeof step);
    why = std::string(step) + ": " + libusb_error_name(setup.last_error);
    return false;
  }

  // The first bulk IN endpoint of each interface; the configuration picks the lowest or the
  // highest interface that has one.
  bool find_endpoint(libusb_device* dev, LibusbOpened& opened) const {
    libusb_config_descriptor* cfg = nullptr;
    if (libusb_get_active_config_descriptor(dev, &cfg) != 0 &&
        libusb_get_config_descriptor(dev, 0, &cfg) != 0)
      return false;
    for (int i = 0; i < cfg->bNumInterfaces; ++i) {
      if (cfg->interface[i].num_altsetting < 1) continue;
      const libusb_interface_descriptor& alt = cfg->interface[i].altsetting[0];
      for (int e = 0; e < alt.bNumEndpoints; ++e) {
        const libusb_endpoint_descriptor& ep = alt.endpoint[e];
        const bool bulk_in = (ep.bEndpointAddress & LIBUSB_ENDPOINT_IN) &&
                             (ep.bmAttributes & LIBUSB_TRANSFER_TYPE_MASK) == LIBUSB_TRANSFER_TYPE_BULK;
        if (!bulk_in) continue;
        const bool better = opened.endpoint == 0 ||
                            (config.endpoint == EndpointChoice::last_bulk_in
                                 ? alt.bInterfaceNumber > opened.interface_number
                                 : alt.bInterfaceNumber < opened.interface_number);
        if (better) {
          opened.interface_number = alt.bInterfaceNumber;
          opened.endpoint = ep.bEndpointAddress;
        }
        break;
      }
    }
    libusb_free_config_descriptor(cfg);
    return opened.endpoint != 0;
  }

  bool any_busy() const {
    for (const Slot& s : slots)
      if (s.busy) return true;
    return false;
  }

  // Cancels every transfer and waits, by time not by event count (each call returns at the first
  // event, and an unplug brings many), until libusb has given them all back (at most 2 s; what is
  // still in flight then stays busy).
  void cancel_all() {
    for (Slot& s : slots)
      if (s.busy) libusb_cancel_transfer(s.transfer);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
    while (any_busy() && std::chrono::steady_clock::now() < deadline) {
      timeval tv{0, 10000};
      libusb_handle_events_timeout_completed(ctx, &tv, nullptr);
    }
    done.clear();
  }

  // libusb transfers belong to one opened device: a submitted transfer keeps a reference to its
  // device until it is submitted again or freed (libusb_submit_transfer drops the old reference,
  // libusb_free_transfer the last one), and dropping the last reference reaches into the
  // device's context. A transfer therefore never outlives the context it was submitted in: the
  // slots get fresh transfers at each open and free them at close, before the context is exited.
  // Reusing them across a reconnect freed the old device inside the exited context on the first
  // submission after a replug: the intermittent segfault after "destroy device" (docs/hil.md).
  bool alloc_transfers() {
    for (Slot& s : slots) {
      if (!s.transfer) s.transfer = libusb_alloc_transfer(0);
      if (!s.transfer) return false;
    }
    return true;
  }

  // At close, with the device's context still alive. Transfers libusb still holds (cancelled but
  // not given back) are retired instead: never freed, their buffers kept, and the handle and
  // context they point at pinned; their callback finds no slot.
  void free_transfers() {
    for (Slot& s : slots) {
      if (!s.transfer) continue;
      if (s.busy) {
        s.transfer->user_data = nullptr;
        retired_buffers.push_back(std::move(s.buffer));
        s.buffer.assign(config.transfer_bytes, 0);
        s.busy = false;
        context_pinned = true;
      } else {
        libusb_free_transfer(s.transfer);
      }
      s.transfer = nullptr;
    }
  }

  // The standard requests of the start and stop steps, on this handle. SET_INTERFACE goes out as
  // a plain control transfer, as the public FLIR ONE drivers send it: the kernel keeps its view
  // of the interface (alternate setting 0 and its endpoints) instead of switching it.
  struct Setup final : UsbDeviceSetup {
    Impl& m;
    int last_error = 0;
    explicit Setup(Impl& impl) : m(impl) {}
    bool done(int rc) {
      last_error = rc;
      if (rc == LIBUSB_ERROR_NO_DEVICE) m.gone = true;
      return rc >= 0;
    }
    bool set_configuration(std::uint8_t configuration) override {
      return done(libusb_set_configuration(m.handle, configuration));
    }
    bool claim_interface(std::uint8_t interface) override {
      if (!done(libusb_claim_interface(m.handle, interface))) return false;
      m.claimed.push_back(interface);
      return true;
    }
    bool set_interface(std::uint8_t interface, std::uint8_t alternate) override {
      return done(libusb_control_transfer(m.handle, kStandardToInterface, kSetInterface, alternate, interface,
                                          nullptr, 0, 1000));
    }
  } setup{*this};
  std::uint64_t failed_steps = 0;
  bool stalled = false;  // the endpoint halted: cleared before the next submission

  // A halted endpoint fails every later transfer until the halt is cleared.
  void clear_stall() {
    if (!stalled || !handle) return;
    stalled = false;
    if (libusb_clear_halt(handle, endpoint) == LIBUSB_ERROR_NO_DEVICE) gone = true;
  }

  void close() {
    if (!handle) return;
    cancel_all();
    if (!gone && run_usb_setup(setup, config.stop) < config.stop.size()) ++failed_steps;
    for (int iface : claimed) libusb_release_interface(handle, iface);
    claimed.clear();
    free_transfers();
    if (!context_pinned) libusb_close(handle);  // else in-flight transfers still point at it
    handle = nullptr;
    done.clear();  // completions seen while stopping belong to the closed device
  }

  // The context is exited only when nothing of ours can still be inside it.
  void drop_context() {
    if (ctx && !context_pinned) libusb_exit(ctx);
    ctx = nullptr;
    context_pinned = false;
  }

  bool submit(Slot& s, std::uint32_t timeout_ms) {
    clear_stall();
    libusb_fill_bulk_transfer(s.transfer, handle, endpoint, s.buffer.data(), static_cast<int>(s.buffer.size()),
                              on_complete, &s, config.streaming ? 0 : timeout_ms);
    const int rc = libusb_submit_transfer(s.transfer);
    if (rc == LIBUSB_ERROR_NO_DEVICE) gone = true;
    if (rc == LIBUSB_ERROR_PIPE) stalled = true;
    s.busy = rc == 0;
    return s.busy;
  }
};

LibusbTransport::LibusbTransport(const LibusbConfig& config) : impl_(std::make_unique<Impl>()) {
  impl_->config = config;
  if (libusb_init(&impl_->ctx) != 0) throw std::runtime_error("libusb: cannot initialise");
  const int count = config.streaming ? (config.in_flight < 1 ? 1 : config.in_flight) : 1;
  impl_->slots.resize(static_cast<std::size_t>(count));
  for (auto& s : impl_->slots) {
    s.buffer.resize(config.transfer_bytes);
    s.owner = impl_.get();
  }
  std::string why;
  if (!impl_->open(opened_, why)) {
    std::string pids;
    for (auto p : config.product_ids) {
      if (!pids.empty()) pids += '/';
      pids += hex4(p);
    }
    const std::string message = "usb " + hex4(config.vendor_id) + ":" + pids + ": " + why;
    impl_->drop_context();
    throw std::runtime_error(message);
  }
}

LibusbTransport::~LibusbTransport() {
  impl_->close();
  impl_->drop_context();
}

Transfer LibusbTransport::next(std::span<std::uint8_t> buffer, std::uint32_t timeout_ms) {
  Impl& m = *impl_;
  Transfer out;
  // Transfers that completed before the unplug was seen are handed out first: they hold the end
  // of the last good frame (the kernel may have filled several while a submission found the
  // device gone). On a gone device every queued transfer comes back at once, with its data or
  // with `no device`: wait for them, a bounded time, without cancelling.
  if (m.handle && m.gone && m.done.empty()) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(500);
    while (m.done.empty() && m.any_busy() && std::chrono::steady_clock::now() < until) {
      timeval tv{0, 10000};
      libusb_handle_events_timeout_completed(m.ctx, &tv, nullptr);
    }
  }
  if (!m.handle || (m.gone && m.done.empty())) {
    out.status = TransferStatus::disconnected;
    return out;
  }
  if (m.done.empty()) {
    for (auto& s : m.slots)
      if (!s.busy && !m.submit(s, timeout_ms) && m.gone) {
        out.status = TransferStatus::disconnected;
        return out;
      }
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    while (m.done.empty()) {
      const auto left = deadline - std::chrono::steady_clock::now();
      if (left <= std::chrono::steady_clock::duration::zero()) {
        if (!m.config.streaming) m.cancel_all();
        out.status = TransferStatus::timeout;
        return out;
      }
      const auto us = std::chrono::duration_cast<std::chrono::microseconds>(left).count();
      timeval tv{static_cast<time_t>(us / 1'000'000), static_cast<suseconds_t>(us % 1'000'000)};
      const int rc = libusb_handle_events_timeout_completed(m.ctx, &tv, nullptr);
      if (rc == LIBUSB_ERROR_NO_DEVICE) m.gone = true;
      if (m.gone && m.done.empty()) {
        out.status = TransferStatus::disconnected;
        return out;
      }
    }
  }
  const Impl::Done d = m.done.front();
  m.done.pop_front();
  out.status = d.status;
  out.arrival_ns = d.arrival_ns;
  if (d.status == TransferStatus::ok) {
    if (d.bytes > buffer.size()) {
      out.status = TransferStatus::error;
    } else {
      std::memcpy(buffer.data(), d.slot->buffer.data(), d.bytes);
      out.bytes = d.bytes;
    }
  }
  if (m.config.streaming && !m.gone) m.submit(*d.slot, timeout_ms);
  return out;
}

bool LibusbTransport::reconnect(std::uint32_t timeout_ms) {
  Impl& m = *impl_;
  m.close();
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    // A fresh context each attempt: without udev (minimal boards, the HIL VM) a context gets no
    // hot-plug events and never lists the replugged device.
    m.drop_context();
    if (libusb_init(&m.ctx) != 0) {
      m.ctx = nullptr;
      return false;
    }
    LibusbOpened opened;
    std::string why;
    if (m.open(opened, why)) {
      opened_ = opened;
      return true;
    }
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

Transfer LibusbTransport::control_out(std::uint8_t code, std::span<const std::uint8_t> data) {
  Transfer out;
  if (!impl_->handle) {
    out.status = TransferStatus::disconnected;
    return out;
  }
  const int rc = libusb_control_transfer(
      impl_->handle, kVendorToInterface, code, 0, 0,
      const_cast<unsigned char*>(data.data()), static_cast<std::uint16_t>(data.size()), 1000);
  out.status = rc < 0 ? status_of(rc) : TransferStatus::ok;
  out.bytes = rc < 0 ? 0 : static_cast<std::size_t>(rc);
  if (out.status == TransferStatus::disconnected) impl_->gone = true;
  return out;
}

// Public drivers read with the interface or the device as recipient: try one, then the other.
Transfer LibusbTransport::control_in(std::uint8_t code, std::span<std::uint8_t> data) {
  Transfer out;
  if (!impl_->handle) {
    out.status = TransferStatus::disconnected;
    return out;
  }
  int rc = LIBUSB_ERROR_PIPE;
  for (std::uint8_t recipient : {kRecipientInterface, kRecipientDevice}) {
    rc = libusb_control_transfer(impl_->handle, static_cast<std::uint8_t>(kVendorFromDevice | recipient),
                                 code, 0, 0, data.data(), static_cast<std::uint16_t>(data.size()), 1000);
    if (rc >= 0 || rc == LIBUSB_ERROR_NO_DEVICE) break;
  }
  out.status = rc < 0 ? status_of(rc) : TransferStatus::ok;
  out.bytes = rc < 0 ? 0 : static_cast<std::size_t>(rc);
  if (out.status == TransferStatus::disconnected) impl_->gone = true;
  return out;
}

LibusbConfig flirone_libusb_config() {
  LibusbConfig c;
  c.vendor_id = 0x09cb;
  c.product_ids = {0x1996};
  c.endpoint = EndpointChoice::last_bulk_in;
  c.start.assign(std::begin(flirone::kStartSteps), std::end(flirone::kStartSteps));
  c.stop.assign(std::begin(flirone::kStopSteps), std::end(flirone::kStopSteps));
  c.streaming = true;
  c.transfer_bytes = std::size_t{64} * 1024;
  c.in_flight = 4;
  return c;
}

LibusbConfig seek_libusb_config() {
  LibusbConfig c;
  c.vendor_id = kSeekVendorId;
  c.product_ids = {kSeekCompact.product_id, kSeekCompactPro.product_id};
  c.endpoint = EndpointChoice::first_bulk_in;
  // A frame's chunks are read through 4 queued reads: one round trip per frame instead of one
  // per chunk (2-4x the frame rate in the HIL VM). Each read ends at a chunk's short packet, so
  // chunks still arrive one per read, in order.
  c.streaming = true;
  c.in_flight = 4;
  c.transfer_bytes = kSeekCompact.chunk_bytes > kSeekCompactPro.chunk_bytes ? kSeekCompact.chunk_bytes
                                                                            : kSeekCompactPro.chunk_bytes;
  return c;
}

std::vector<UsbDeviceEntry> list_known_usb_devices() {
  struct Known {
    std::uint16_t vid, pid;
    const char* what;
  };
  static constexpr Known kKnown[] = {
      {0x09cb, 0x1996, "usb:flirone (FLIR ONE Pro)"},
      {0x289d, 0x0010, "usb:seek (Seek Thermal Compact / CompactXR)"},
      {0x289d, 0x0011, "usb:seek (Seek Thermal CompactPro / Nano 300)"},
      {0x1e4e, 0x0100, "PureThermal (FLIR Lepton, UVC: use its v4l2 node)"},
      {0x09cb, 0x4007, "FLIR Boson control (CDC serial; video through its v4l2 node)"},
  };
  std::vector<UsbDeviceEntry> out;
  libusb_context* ctx = nullptr;
  if (libusb_init(&ctx) != 0) return out;
  libusb_device** list = nullptr;
  const ssize_t n = libusb_get_device_list(ctx, &list);
  for (ssize_t i = 0; i < n; ++i) {
    libusb_device_descriptor d{};
    if (libusb_get_device_descriptor(list[i], &d) != 0) continue;
    for (const Known& k : kKnown) {
      if (k.vid != d.idVendor || k.pid != d.idProduct) continue;
      std::string what = k.what;
      for (const SeekModel* m : {&kSeekCompact, &kSeekCompactPro})  // the size usb:seek delivers
        if (k.vid == kSeekVendorId && k.pid == m->product_id)
          what += " " + std::to_string(m->crop.width) + "x" + std::to_string(m->crop.height);
      out.push_back({d.idVendor, d.idProduct, libusb_get_bus_number(list[i]), libusb_get_device_address(list[i]),
                     what});
    }
  }
  if (n >= 0) libusb_free_device_list(list, 1);
  libusb_exit(ctx);
  return out;
}

}  // namespace bolo::hal

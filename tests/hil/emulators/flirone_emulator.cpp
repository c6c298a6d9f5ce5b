// FLIR ONE Pro emulator on FunctionFS: plays the real camera's USB side through the kernel's
// gadget framework. Replays a captured transfer sequence as it was captured, or streams
// simulated frames in the same framing, with device faults on demand. Every frame it sends is
// logged (index, fault, FNV-1a of the bytes, frame counter) so the host side can check what
// arrived bit for bit.
//
//   flirone_emulator --capture DIR --log FILE [--replay | --frames N] [--jpeg-bytes N]
//                    [--fault-rate R --faults all|a,b --seed S] [--quiet-ms MS] [--fps F]
//                    [--autostart]
//
// Interfaces as on the real device: 0 config (bulk in/out), 1 file I/O (bulk in/out), 2 frames
// (bulk in; 0x85 on the real device, the UDC picks the number here: hosts read it from the
// descriptors). Streaming starts on vendor request 0x0b (wValue 1) to interface 2, stops with
// wValue 0; the real device takes the same request as a standard SET_INTERFACE, which the
// kernel's composite layer refuses for FunctionFS functions without get_alt. --autostart streams
// as soon as the host configures the device (for hosts that send no start request).

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

#include "configfs_gadget.hpp"
#include "fault_plan.hpp"
#include "flirone_frames.hpp"
#include "functionfs.hpp"

namespace {

using namespace bolo::hil;
using flirone::Bytes;

constexpr std::uint8_t kStartStopRequest = 0x0b;
constexpr std::uint16_t kFrameInterface = 2;

struct Options {
  std::string log = "/tmp/flirone-sent.log";
  std::string capture;  // the real capture: replayed, or the template of simulated frames
  bool replay = false;
  bool autostart = false;  // stream once configured, without the start request
  std::uint64_t frames = 100;
  std::size_t jpeg_bytes = 1u << 30;
  double fault_rate = 0;
  std::string faults = "all";
  std::uint64_t seed = 1;
  int quiet_ms = 1500;  // a "timeout" fault is this much silence mid-frame
  double fps = 0;       // 0: as fast as the host reads
  std::string ready = "/tmp/flirone.ready";
  std::string done = "/tmp/flirone.done";
  std::string finished = "/tmp/flirone.finished";  // the host is through: unplug and exit
  std::string name = "flirone";                    // gadget and FunctionFS instance name
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error(a + " needs a value");
      return argv[++i];
    };
    if (a == "--log") o.log = value();
    else if (a == "--capture") o.capture = value();
    else if (a == "--replay") o.replay = true;
    else if (a == "--autostart") o.autostart = true;
    else if (a == "--frames") o.frames = std::stoull(value());
    else if (a == "--jpeg-bytes") o.jpeg_bytes = std::stoull(value());
    else if (a == "--fault-rate") o.fault_rate = std::stod(value());
    else if (a == "--faults") o.faults = value();
    else if (a == "--seed") o.seed = std::stoull(value());
    else if (a == "--quiet-ms") o.quiet_ms = std::stoi(value());
    else if (a == "--fps") o.fps = std::stod(value());
    else if (a == "--ready") o.ready = value();
    else if (a == "--done") o.done = value();
    else if (a == "--finished") o.finished = value();
    else if (a == "--name") o.name = value();
    else throw std::runtime_error("unknown option " + a);
  }
  if (o.capture.empty()) throw std::runtime_error("--capture DIR is required");
  return o;
}

// Host-visible state, driven by ep0 events.
struct Link {
  std::mutex mutex;
  std::condition_variable changed;
  bool enabled = false;
  bool streaming = false;
};

void serve_ep0(FunctionFs& ffs, Link& link, bool autostart) {
  for (;;) {
    const FfsEvent event = ffs.next_event();
    std::unique_lock lock(link.mutex);
    switch (event.type) {
      case FfsEventType::enable:
        link.enabled = true;
        if (autostart) link.streaming = true;
        break;
      case FfsEventType::disable:
      case FfsEventType::unbind: link.enabled = false; link.streaming = false; break;
      case FfsEventType::setup: {
        const usb_ctrlrequest& r = event.setup;
        const bool vendor = (r.bRequestType & USB_TYPE_MASK) == USB_TYPE_VENDOR;
        const bool to_host = (r.bRequestType & USB_DIR_IN) != 0;
        if (vendor && !to_host && r.bRequest == kStartStopRequest) {
          lock.unlock();
          ffs.accept_setup(r.wLength);
          lock.lock();
          if ((r.wIndex & 0xFF) == kFrameInterface) link.streaming = r.wValue != 0;
        } else if (to_host) {
          lock.unlock();
          ffs.reply_setup(Bytes(std::min<std::size_t>(r.wLength, 4), 0));  // status: all zero
          lock.lock();
        } else {
          lock.unlock();
          ffs.accept_setup(r.wLength);  // other vendor writes (file I/O): accepted and ignored
          lock.lock();
        }
        break;
      }
      default: break;
    }
    link.changed.notify_all();
  }
}

class Emulator {
 public:
  Emulator(const Options& options, ConfigfsGadget& gadget, int frame_endpoint, Link& link)
      : o_(options), gadget_(gadget), ep_(frame_endpoint), link_(link), log_(options.log) {
    if (!log_) throw std::runtime_error(options.log + ": cannot write");
  }

  void wait_streaming() {
    std::unique_lock lock(link_.mutex);
    link_.changed.wait(lock, [&] { return link_.enabled && link_.streaming; });
  }

  // One bulk transfer; false when the host went away under it.
  bool send(const std::uint8_t* data, std::size_t size) {
    while (size > 0) {
      const ssize_t n = ::write(ep_, data, size);
      if (n < 0) {
        if (errno == EINTR) continue;
        return false;
      }
      data += n;
      size -= static_cast<std::size_t>(n);
    }
    return true;
  }

  // The frame in 32 KiB transfers. (The real device sends header and thermal part as transfers
  // of their own, as the replay does; here a frame without JPEG is one transfer, so a host
  // must also cope with a frame that does not end at a transfer boundary it expects.)
  bool send_frame(const Bytes& f, std::size_t stop_after) {
    for (std::size_t at = 0; at < stop_after;) {
      const std::size_t n = std::min<std::size_t>(32768, stop_after - at);
      if (!send(f.data() + at, n)) return false;
      at += n;
    }
    return true;
  }

  void record(std::uint64_t index, Fault fault, const Bytes& f) {
    char line[160];
    std::snprintf(line, sizeof line, "frame %llu %s %016llx %u %zu %016llx\n",
                  static_cast<unsigned long long>(index), fault_name(fault),
                  static_cast<unsigned long long>(flirone::fnv1a(f)), flirone::frame_counter(f), f.size(),
                  static_cast<unsigned long long>(flirone::image_hash(f)));
    log_ << line;
    log_.flush();
  }

  void pace() {
    if (o_.fps <= 0) return;
    next_ += std::chrono::nanoseconds(static_cast<std::int64_t>(1e9 / o_.fps));
    std::this_thread::sleep_until(next_);
  }

  void replay(const std::vector<Bytes>& transfers) {
    wait_streaming();
    next_ = std::chrono::steady_clock::now();
    std::uint64_t index = 0;
    for (const Bytes& frame : flirone::split_frames(transfers)) record(index++, Fault::none, frame);
    for (const Bytes& t : transfers) {
      if (t.empty()) continue;  // a zero-length read in the capture: nothing to send
      if (flirone::starts_with_magic(t)) pace();
      if (!send(t.data(), t.size())) throw std::runtime_error("replay: the host went away");
    }
  }

  void simulate(const flirone::SimulatedFrames& frames, const FaultPlan& plan) {
    wait_streaming();
    next_ = std::chrono::steady_clock::now();
    std::uint32_t counter = 16606;  // where the real capture's core counter starts
    for (std::uint64_t i = 0; i < o_.frames; ++i) {
      const Fault fault = plan.at(i);
      if (fault == Fault::frame_id_jump) counter += 1'000'003;  // a core restart, seen from the host
      Bytes f = frames.frame(i, counter);
      counter += 3;  // the core runs 3x faster than the USB export
      if (fault == Fault::corrupt) flirone::set_packet_row(f, 30, 31);  // CRC left as it was
      pace();
      record(i, fault, f);
      send_with_fault(f, fault);
      if (fault == Fault::duplicate) send_with_fault(f, Fault::none);
    }
  }

 private:
  void send_with_fault(const Bytes& f, Fault fault) {
    const std::size_t part = flirone::kHeaderBytes + flirone::kThermalBytes / 2;  // mid-frame
    bool ok = true;
    switch (fault) {
      case Fault::short_transfer: ok = send_frame(f, part); break;
      case Fault::stall:
        ok = send_frame(f, part);
        FunctionFs::halt_in_endpoint(ep_);
        break;
      case Fault::timeout:
        ok = send_frame(f, part);
        std::this_thread::sleep_for(std::chrono::milliseconds(o_.quiet_ms));
        break;
      case Fault::disconnect:
        ok = send_frame(f, part);
        gadget_.unbind();
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
        gadget_.bind();
        wait_streaming();
        break;
      default: ok = send_frame(f, f.size()); break;
    }
    if (!ok) {
      // The host vanished under a frame we did not mean to break: logged so the check fails
      // loudly instead of counting it as an injected fault.
      log_ << "lost-by-emulator\n";
      log_.flush();
      wait_streaming();
    }
  }

  const Options& o_;
  ConfigfsGadget& gadget_;
  int ep_;
  Link& link_;
  std::ofstream log_;
  std::chrono::steady_clock::time_point next_;
};

void touch(const std::string& path) { std::ofstream(path) << "1\n"; }

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    const std::vector<Bytes> capture = flirone::load_capture(o.capture);

    GadgetIdentity id;
    id.vendor_id = 0x09cb;
    id.product_id = 0x1996;
    id.manufacturer = "FLIR Systems";
    id.product = "FLIR ONE Camera";
    id.serial = "bolo-hil-emulated";
    ConfigfsGadget gadget(o.name, id);
    gadget.add_function("ffs", o.name);
    FunctionFs ffs(o.name, "/dev/ffs-" + o.name);
    ffs.describe({{0xFF, 0xFF, 0, "iAP Interface", {{true}, {false}}},
                  {0xFF, 0xFF, 0, "com.flir.rosebud.fileio", {{true}, {false}}},
                  {0xFF, 0xFF, 0, "com.flir.rosebud.frame", {{true}}}},
                 true);
    const std::vector<int>& endpoints = ffs.open_endpoints();
    Link link;
    std::thread ep0([&] {
      try {
        serve_ep0(ffs, link, o.autostart);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "flirone_emulator: ep0: %s\n", e.what());
      }
    });
    ep0.detach();
    gadget.bind();
    touch(o.ready);
    // Whenever the host side is through (also when it gave up early), unplug and exit. The ep0
    // thread sits in a read that closing cannot interrupt, so the process ends without
    // unwinding; the VM is throw-away and the next run uses another gadget name.
    std::thread([&] {
      while (::access(o.finished.c_str(), F_OK) != 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
      try {
        gadget.unbind();
      } catch (const std::exception& e) {
        std::fprintf(stderr, "flirone_emulator: %s\n", e.what());
      }
      std::fflush(nullptr);
      std::_Exit(::access(o.done.c_str(), F_OK) == 0 ? 0 : 3);
    }).detach();

    Emulator emulator(o, gadget, endpoints[4], link);
    if (o.replay) {
      emulator.replay(capture);
    } else {
      flirone::SimulatedFrames frames(flirone::split_frames(capture).at(0), o.jpeg_bytes);
      emulator.simulate(frames, FaultPlan(o.fault_rate, o.seed, parse_fault_list(o.faults)));
    }
    touch(o.done);
    for (;;) pause();  // plugged in until the host is through (the thread above)
  } catch (const std::exception& e) {
    std::fprintf(stderr, "flirone_emulator: %s\n", e.what());
    return 1;
  }
}

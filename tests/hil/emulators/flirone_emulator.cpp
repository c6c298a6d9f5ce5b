// FLIR ONE Pro emulator on Raw Gadget: plays the real camera's USB side, every control request
// answered here (flirone_control.hpp: its descriptors, its start-up check). Replays a captured
// transfer sequence as it was captured, or streams simulated frames in the same framing, with
// device faults on demand. Every frame it sends is logged (index, fault, FNV-1a of the bytes,
// frame counter) so the host side can check what arrived bit for bit; the log ends with
// "# refused-requests N" (control requests off the public drivers' start-up, stalled).
//
//   flirone_emulator --capture DIR --log FILE [--replay | --frames N] [--jpeg-bytes N]
//                    [--fault-rate R --faults all|a,b --seed S] [--quiet-ms MS] [--fps F]
//
// Interfaces as on the real device: 0 iAP, 1 file I/O, 2 frames, each with alternate settings
// 0 and 1 and a bulk IN and OUT endpoint; the UDC's endpoint list (USB_RAW_IOCTL_EPS_INFO)
// decides the numbers (dummy_hcd has no bulk 0x85): hosts read them from the descriptors.
// Frames flow on interface 2's IN endpoint only while the host has started it: SET_CONFIGURATION
// 3, then SET_INTERFACE 2 alt 0, 1 alt 0, 1 alt 1, 2 alt 1.

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

#include "fault_plan.hpp"
#include "flirone_control.hpp"
#include "flirone_frames.hpp"
#include "raw_gadget.hpp"

namespace {

using namespace bolo::hil;
using flirone::Bytes;

struct Options {
  std::string log = "/tmp/flirone-sent.log";
  std::string capture;  // the real capture: replayed, or the template of simulated frames
  bool replay = false;
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
    else throw std::runtime_error("unknown option " + a);
  }
  if (o.capture.empty()) throw std::runtime_error("--capture DIR is required");
  return o;
}

// The camera on the bus: one RawGadget per plug-in, its ep0 served by a thread of its own, the
// start-up checked by the StartupChecker (under `mutex`, shared with the frame thread).
class Camera {
 public:
  Camera() {
    struct sigaction wake {};
    wake.sa_handler = [](int) {};  // only to cut the ep0 thread's blocking fetch (no SA_RESTART)
    sigaction(SIGUSR1, &wake, nullptr);
    plug();
  }

  // Blocks until the host has started the frames (the drivers' sequence went through).
  void wait_streaming() {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return checker_.streaming(); });
  }
  int frame_endpoint() const { return frame_ep_; }
  RawGadget& gadget() { return *gadget_; }
  std::uint64_t refused() {
    std::lock_guard lock(mutex_);
    return checker_.refused();
  }

  // Unplug (the gadget closed: the host sees the device leave), `away` off the bus, plug in again.
  void replug(std::chrono::milliseconds away) {
    stop_ = true;
    while (!ep0_done_) {  // again and again: a signal between the loop's check and its fetch is lost
      pthread_kill(ep0_.native_handle(), SIGUSR1);
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ep0_.join();
    gadget_.reset();
    {
      std::lock_guard lock(mutex_);
      checker_.unplugged();
    }
    std::this_thread::sleep_for(away);
    plug();
  }

 private:
  void plug() {
    stop_ = false;
    ep0_done_ = false;
    frame_ep_ = -1;
    gadget_ = std::make_unique<RawGadget>();
    ep0_ = std::thread([this] {
      try {
        serve_ep0();
      } catch (const std::exception& e) {
        std::fprintf(stderr, "flirone_emulator: ep0: %s\n", e.what());
      }
      ep0_done_ = true;
    });
  }

  // Endpoints for interfaces 0-2, the real camera's numbers (0x81/0x02, 0x83/0x04, 0x85/0x06)
  // where the UDC has them as bulk endpoints, else its next free bulk endpoint of that direction.
  void choose_endpoints() {
    const std::vector<RawEndpoint> eps = gadget_->endpoints();
    std::vector<bool> used_in(16, false), used_out(16, false);
    auto pick = [&](bool in, std::uint8_t wanted) -> std::uint8_t {
      std::vector<bool>& used = in ? used_in : used_out;
      for (int pass = 0; pass < 2; ++pass)
        for (const RawEndpoint& e : eps) {
          if (!e.bulk || (in ? !e.in : !e.out)) continue;
          std::uint8_t n = e.number;
          if (n == USB_RAW_EP_ADDR_ANY) n = wanted;
          if (n == 0 || n > 15 || used[n] || (pass == 0 && n != wanted)) continue;
          used[n] = true;
          return static_cast<std::uint8_t>(n | (in ? USB_DIR_IN : 0));
        }
      throw std::runtime_error("the UDC has no free bulk " + std::string(in ? "IN" : "OUT") + " endpoint");
    };
    for (int i = 0; i < flirone::kInterfaces; ++i) {
      endpoints_[i].in = pick(true, static_cast<std::uint8_t>(1 + 2 * i));
      endpoints_[i].out = pick(false, static_cast<std::uint8_t>(2 + 2 * i));
    }
    descriptors_ = flirone::make_descriptors(endpoints_);
  }

  // At the first SET_CONFIGURATION 3 of a plug-in: the endpoints of the descriptors, enabled.
  void enable_endpoints() {
    if (enabled_) return;
    for (int i = 0; i < flirone::kInterfaces; ++i)
      for (std::uint8_t address : {endpoints_[i].in, endpoints_[i].out}) {
        usb_endpoint_descriptor d{};
        d.bLength = USB_DT_ENDPOINT_SIZE;
        d.bDescriptorType = USB_DT_ENDPOINT;
        d.bEndpointAddress = address;
        d.bmAttributes = USB_ENDPOINT_XFER_BULK;
        d.wMaxPacketSize = 512;
        const int handle = gadget_->enable(d);
        if (i == 2 && (address & USB_DIR_IN)) frame_ep_ = handle;
      }
    gadget_->configure();
    enabled_ = true;
  }

  void serve_ep0() {
    enabled_ = false;
    while (!stop_) {
      const RawEvent event = gadget_->next_event();
      if (event.type == RawEvent::Type::connect) choose_endpoints();
      if (event.type != RawEvent::Type::control) continue;
      const usb_ctrlrequest& r = event.setup;
      const bool in = (r.bRequestType & USB_DIR_IN) != 0;
      if ((r.bRequestType & USB_TYPE_MASK) == USB_TYPE_STANDARD && r.bRequest == USB_REQ_GET_DESCRIPTOR && in) {
        std::vector<std::uint8_t> answer;
        if (flirone::descriptor_for(descriptors_, r, answer)) {
          gadget_->reply_in(answer);
        } else {
          gadget_->stall();  // a descriptor the camera does not have: not a start-up request
          std::fprintf(stderr, "flirone_emulator: no descriptor 0x%04x\n", r.wValue);
        }
        continue;
      }
      std::unique_lock lock(mutex_);
      const bool accepted = checker_.take(r);
      if (!accepted) std::fprintf(stderr, "flirone_emulator: refused %s\n", checker_.last_refusal().c_str());
      const bool configure = accepted && checker_.configured() && r.bRequest == USB_REQ_SET_CONFIGURATION;
      lock.unlock();
      if (configure) enable_endpoints();
      if (!accepted) gadget_->stall();
      else if (in) gadget_->reply_in({});
      else gadget_->ack_out(r.wLength);
      changed_.notify_all();
    }
  }

  std::unique_ptr<RawGadget> gadget_;
  std::thread ep0_;
  std::atomic<bool> stop_{false}, ep0_done_{false};
  bool enabled_ = false;
  int frame_ep_ = -1;
  flirone::EndpointPair endpoints_[flirone::kInterfaces];
  flirone::Descriptors descriptors_;
  std::mutex mutex_;
  std::condition_variable changed_;
  flirone::StartupChecker checker_;
};

class Emulator {
 public:
  Emulator(const Options& options, Camera& camera) : o_(options), camera_(camera), log_(options.log) {
    if (!log_) throw std::runtime_error(options.log + ": cannot write");
  }

  void wait_streaming() { camera_.wait_streaming(); }

  // One bulk transfer on the frame endpoint; false when the host went away under it.
  bool send(const std::uint8_t* data, std::size_t size) {
    return camera_.gadget().write(camera_.frame_endpoint(), data, size);
  }

  // The start-up requests refused so far, for the host side (which requires none).
  void record_refused() {
    log_ << "# refused-requests " << camera_.refused() << "\n";
    log_.flush();
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
      if (flirone::starts_with_magic(t)) {
        wait_streaming();  // frames flow only while the host has them started
        pace();
      }
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
      wait_streaming();
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
        camera_.gadget().halt(camera_.frame_endpoint());
        break;
      case Fault::timeout:
        ok = send_frame(f, part);
        std::this_thread::sleep_for(std::chrono::milliseconds(o_.quiet_ms));
        break;
      case Fault::disconnect:
        ok = send_frame(f, part);
        camera_.replug(std::chrono::milliseconds(200));
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
  Camera& camera_;
  std::ofstream log_;
  std::chrono::steady_clock::time_point next_;
};

void touch(const std::string& path) { std::ofstream(path) << "1\n"; }

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    const std::vector<Bytes> capture = flirone::load_capture(o.capture);

    Camera camera;
    touch(o.ready);
    // Whenever the host side is through (also when it gave up early), unplug and exit: status 0
    // when every frame went out and no control request was refused (the host's stop sequence
    // included), 4 when requests were refused, else 3 when the frames did not all go out.
    std::thread([&] {
      while (::access(o.finished.c_str(), F_OK) != 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
      const std::uint64_t refused = camera.refused();
      if (refused > 0) std::fprintf(stderr, "flirone_emulator: %llu requests refused\n", static_cast<unsigned long long>(refused));
      std::fflush(nullptr);
      std::_Exit(refused > 0 ? 4 : ::access(o.done.c_str(), F_OK) != 0 ? 3 : 0);
    }).detach();

    Emulator emulator(o, camera);
    if (o.replay) {
      emulator.replay(capture);
    } else {
      flirone::SimulatedFrames frames(flirone::split_frames(capture).at(0), o.jpeg_bytes);
      emulator.simulate(frames, FaultPlan(o.fault_rate, o.seed, parse_fault_list(o.faults)));
    }
    emulator.record_refused();
    touch(o.done);
    for (;;) pause();  // plugged in until the host is through (the thread above)
  } catch (const std::exception& e) {
    std::fprintf(stderr, "flirone_emulator: %s\n", e.what());
    return 1;
  }
}

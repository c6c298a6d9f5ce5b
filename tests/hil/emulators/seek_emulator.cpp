// Seek Thermal Compact emulator on FunctionFS: answers the vendor control requests of the
// protocol facts, serves one frame per START_GET_IMAGE_TRANSFER in 16224-byte chunks, runs the
// boot frame sequence (start-up frame with dead pixels first), a shutter cycle every
// --shutter-period images, and injects device faults on demand. Image frames are logged like
// the FLIR ONE emulator's (send_log.hpp); other frames as "# type T counter C" lines.
//
//   seek_emulator --log FILE [--frames N] [--fault-rate R --faults a,b --seed S]
//                 [--shutter-period N] [--quiet-ms MS] [--name NAME]
//                 [--ready F --done F --finished F]

#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

#include "configfs_gadget.hpp"
#include "fault_plan.hpp"
#include "flirone_frames.hpp"
#include "functionfs.hpp"
#include "seek_frames.hpp"

namespace {

using namespace bolo::hil;
using seek::Bytes;

enum Request : std::uint8_t {
  kGetErrorCode = 53, kReadChipId = 54, kGetOperationMode = 61, kGetFirmwareInfo = 78,
  kStartGetImageTransfer = 83, kGetFactorySettings = 88,
};

struct Options {
  std::string log = "/tmp/seek-sent.log";
  std::uint64_t frames = 100;  // image frames
  double fault_rate = 0;
  std::string faults = "short_transfer,stall,timeout,disconnect,frame_id_jump,duplicate";
  std::uint64_t seed = 1;
  std::uint32_t shutter_period = 100;
  int quiet_ms = 1500;
  std::string name = "seek";
  std::string ready = "/tmp/seek.ready", done = "/tmp/seek.done", finished = "/tmp/seek.finished";
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
    else if (a == "--frames") o.frames = std::stoull(value());
    else if (a == "--fault-rate") o.fault_rate = std::stod(value());
    else if (a == "--faults") o.faults = value();
    else if (a == "--seed") o.seed = std::stoull(value());
    else if (a == "--shutter-period") o.shutter_period = static_cast<std::uint32_t>(std::stoul(value()));
    else if (a == "--quiet-ms") o.quiet_ms = std::stoi(value());
    else if (a == "--name") o.name = value();
    else if (a == "--ready") o.ready = value();
    else if (a == "--done") o.done = value();
    else if (a == "--finished") o.finished = value();
    else throw std::runtime_error("unknown option " + a);
  }
  return o;
}

// Host-visible state, driven by ep0 events: enabled, and frame requests not yet served.
struct Link {
  std::mutex mutex;
  std::condition_variable changed;
  bool enabled = false;
  std::uint64_t plugs = 0;        // configurations seen (a replug restarts the boot sequence)
  std::deque<std::uint32_t> requests;  // pixel counts asked for
};

Bytes answer(std::uint8_t request, std::size_t length) {
  Bytes data(length, 0);
  if (request == kGetFirmwareInfo)
    for (std::size_t i = 0; i < length; ++i) data[i] = static_cast<std::uint8_t>(0x11 * (i + 1));
  if (request == kReadChipId)
    for (std::size_t i = 0; i < length; ++i) data[i] = static_cast<std::uint8_t>(0xC0 + i);
  if (request == kGetOperationMode && length > 0) data[0] = 1;
  return data;  // GET_ERROR_CODE 0, factory settings zero
}

void serve_ep0(FunctionFs& ffs, Link& link) {
  for (;;) {
    const FfsEvent event = ffs.next_event();
    if (event.type == FfsEventType::setup) {
      const usb_ctrlrequest& r = event.setup;
      if ((r.bRequestType & USB_DIR_IN) != 0) {
        ffs.reply_setup(answer(r.bRequest, r.wLength));
        continue;
      }
      const Bytes data = ffs.accept_setup(r.wLength);
      if (r.bRequest == kStartGetImageTransfer && data.size() == 4) {
        std::lock_guard lock(link.mutex);
        link.requests.push_back(static_cast<std::uint32_t>(data[0] | data[1] << 8 | data[2] << 16 |
                                                           static_cast<std::uint32_t>(data[3]) << 24));
        link.changed.notify_all();
      }
      continue;
    }
    std::lock_guard lock(link.mutex);
    if (event.type == FfsEventType::enable) {
      link.enabled = true;
      ++link.plugs;
    }
    if (event.type == FfsEventType::disable || event.type == FfsEventType::unbind) {
      link.enabled = false;
      link.requests.clear();
    }
    link.changed.notify_all();
  }
}

class Emulator {
 public:
  Emulator(const Options& o, ConfigfsGadget& gadget, int ep, Link& link)
      : o_(o), gadget_(gadget), ep_(ep), link_(link), log_(o.log), types_(o.shutter_period) {
    if (!log_) throw std::runtime_error(o.log + ": cannot write");
  }

  void run(const FaultPlan& plan) {
    std::uint16_t counter = 1;
    std::uint64_t plug_seen = 0;
    std::uint64_t image = 0;
    Bytes repeat;
    while (image < o_.frames) {
      const std::uint64_t plug = wait_request();
      if (plug != plug_seen) {  // a (re)plugged camera boots again
        plug_seen = plug;
        types_ = seek::FrameTypes(o_.shutter_period);
      }
      if (!repeat.empty()) {  // the second copy of a duplicate
        send_chunks(repeat, repeat.size());
        repeat.clear();
        continue;
      }
      const std::uint16_t type = types_.next();
      if (type != seek::kImage) {
        Bytes f = seek::make_frame(image, type, counter++);
        log_ << "# type " << type << " counter " << counter - 1 << "\n";
        send_chunks(f, f.size());
        continue;
      }
      const Fault fault = plan.at(image);
      if (fault == Fault::frame_id_jump) counter = static_cast<std::uint16_t>(counter + 5000);
      Bytes f = seek::make_frame(image, type, counter++);
      char line[160];
      const unsigned long long hash = flirone::fnv1a(f);
      std::snprintf(line, sizeof line, "frame %llu %s %016llx %u %zu %016llx\n",
                    static_cast<unsigned long long>(image), fault_name(fault), hash,
                    static_cast<unsigned>(counter - 1), f.size(), hash);
      log_ << line;
      log_.flush();
      ++image;
      send_with_fault(f, fault);
      if (fault == Fault::duplicate) repeat = f;
    }
    log_.flush();
  }

 private:
  std::uint64_t wait_request() {
    std::unique_lock lock(link_.mutex);
    link_.changed.wait(lock, [&] { return link_.enabled && !link_.requests.empty(); });
    link_.requests.pop_front();
    return link_.plugs;
  }

  void send_chunks(const Bytes& f, std::size_t stop_after) {
    for (std::size_t at = 0; at < stop_after;) {
      const std::size_t n = std::min<std::size_t>(seek::kChunkBytes, stop_after - at);
      if (::write(ep_, f.data() + at, n) < 0) {
        log_ << "lost-by-emulator\n";
        return;
      }
      at += n;
    }
  }

  void send_with_fault(const Bytes& f, Fault fault) {
    switch (fault) {
      case Fault::short_transfer:
        send_chunks(f, 2 * seek::kChunkBytes);
        (void)::write(ep_, f.data(), 0);  // the zero-length read a host must abort on
        break;
      case Fault::stall:
        send_chunks(f, seek::kChunkBytes);
        FunctionFs::halt_in_endpoint(ep_);
        break;
      case Fault::timeout:
        send_chunks(f, seek::kChunkBytes);
        std::this_thread::sleep_for(std::chrono::milliseconds(o_.quiet_ms));
        drop_requests();
        break;
      case Fault::disconnect:
        send_chunks(f, seek::kChunkBytes);
        gadget_.unbind();
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
        gadget_.bind();
        break;
      default: send_chunks(f, f.size()); break;
    }
  }

  // Requests the host made while the camera was silent belong to the frame it gave up on.
  void drop_requests() {
    std::lock_guard lock(link_.mutex);
    if (link_.requests.size() > 1) link_.requests.erase(link_.requests.begin(), link_.requests.end() - 1);
  }

  const Options& o_;
  ConfigfsGadget& gadget_;
  int ep_;
  Link& link_;
  std::ofstream log_;
  seek::FrameTypes types_;
};

void touch(const std::string& path) { std::ofstream(path) << "1\n"; }

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    GadgetIdentity id;
    id.vendor_id = seek::kVendor;
    id.product_id = seek::kCompact;
    id.manufacturer = "Seek Thermal";
    id.product = "PIR206 Thermal Camera";
    id.serial = "bolo-hil-emulated";
    ConfigfsGadget gadget(o.name, id);
    gadget.add_function("ffs", o.name);
    FunctionFs ffs(o.name, "/dev/ffs-" + o.name);
    ffs.describe({{0xFF, 0xF0, 0, "Seek Thermal", {{true}}}}, true);
    const std::vector<int>& endpoints = ffs.open_endpoints();
    Link link;
    std::thread([&] {
      try {
        serve_ep0(ffs, link);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "seek_emulator: ep0: %s\n", e.what());
      }
    }).detach();
    gadget.bind();
    touch(o.ready);
    std::thread([&] {  // unplug and exit once the host side is through (see flirone_emulator)
      while (::access(o.finished.c_str(), F_OK) != 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
      try {
        gadget.unbind();
      } catch (const std::exception&) {
      }
      std::fflush(nullptr);
      std::_Exit(::access(o.done.c_str(), F_OK) == 0 ? 0 : 3);
    }).detach();
    Emulator emulator(o, gadget, endpoints[0], link);
    emulator.run(FaultPlan(o.fault_rate, o.seed, parse_fault_list(o.faults)));
    touch(o.done);
    for (;;) pause();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "seek_emulator: %s\n", e.what());
    return 1;
  }
}

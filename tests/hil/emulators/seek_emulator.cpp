// Seek Thermal Compact / CompactPro emulator on FunctionFS: demands the public driver's start-up sequence (its
// own list below; a request out of order is stalled, an OUT request whose payload is wrong
// leaves the camera refusing frames until it is started again; both counted), then serves one
// frame per START_GET_IMAGE_TRANSFER in the model's chunks: the boot frame sequence (start-up
// frame with dead pixels first, a shutter cycle), a shutter cycle every --shutter-period images,
// with an offset pattern that changes at each shutter event (seek_frames.hpp); injects device
// faults on demand. Image frames are logged like the FLIR ONE emulator's (send_log.hpp), the
// image hash being that of the image a host must deliver (expected_image); other frames as
// "# type T counter C" lines; at the end "# refused-requests N".
//
//   seek_emulator --log FILE [--model compact|compactpro] [--frames N] [--fault-rate R --faults a,b --seed S]
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
#include "fnv1a.hpp"
#include "functionfs.hpp"
#include "seek_frames.hpp"

namespace {

using namespace bolo::hil;
using seek::Bytes;

enum Request : std::uint8_t {
  kGetErrorCode = 53, kReadChipId = 54, kToggleShutter = 55, kSetOperationMode = 60, kGetOperationMode = 61,
  kGetFirmwareInfo = 78, kStartGetImageTransfer = 83, kTargetPlatform = 84, kGetFactorySettings = 88,
};

// The start-up as libseek-thermal sends it: OUT requests with their payload, IN requests with
// their length. Written here on its own: the check must not reuse the HAL's table.
struct Expected {
  bool in;
  std::uint8_t request;
  Bytes payload;        // OUT
  std::uint16_t length;  // IN
};
const std::vector<Expected> kCompactStartup = {
    {false, 84, {0x01}, 0},
    {false, 60, {0x00, 0x00}, 0},
    {true, 78, {}, 4},
    {true, 54, {}, 12},
    {false, 86, {0x20, 0x00, 0x30, 0x00, 0x00, 0x00}, 0},
    {true, 88, {}, 64},
    {false, 86, {0x20, 0x00, 0x50, 0x00, 0x00, 0x00}, 0},
    {true, 88, {}, 64},
    {false, 86, {0x0c, 0x00, 0x70, 0x00, 0x00, 0x00}, 0},
    {true, 88, {}, 24},
    {false, 86, {0x06, 0x00, 0x08, 0x00, 0x00, 0x00}, 0},
    {true, 88, {}, 12},
    {false, 62, {0x08, 0x00}, 0},
    {true, 61, {}, 2},
    {false, 62, {0x08, 0x00}, 0},
    {false, 60, {0x01, 0x00}, 0},
    {true, 61, {}, 2},
};

std::vector<Expected> compact_pro_startup() {
  std::vector<Expected> steps = {
      {false, 84, {0x01}, 0},
      {false, 60, {0x00, 0x00}, 0},
      {true, 78, {}, 4},
      {true, 54, {}, 12},
      {false, 86, {0x06, 0x00, 0x08, 0x00, 0x00, 0x00}, 0},
      {true, 88, {}, 12},
      {false, 85, {0x17, 0x00}, 0},
      {true, 78, {}, 64},
      {false, 86, {0x01, 0x00, 0x00, 0x06, 0x00, 0x00}, 0},
      {true, 88, {}, 2},
      {false, 86, {0x01, 0x00, 0x01, 0x06, 0x00, 0x00}, 0},
      {true, 88, {}, 2},
  };
  for (std::uint32_t block = 0; block < 80; ++block) {  // factory settings, 32 words a block
    const std::uint32_t address = block * 32;
    steps.push_back({false, 86, {0x20, 0x00, static_cast<std::uint8_t>(address), static_cast<std::uint8_t>(address >> 8), 0x00, 0x00}, 0});
    steps.push_back({true, 88, {}, 64});
  }
  steps.push_back({false, 85, {0x15, 0x00}, 0});
  steps.push_back({true, 78, {}, 64});
  steps.push_back({false, 62, {0x08, 0x00}, 0});
  steps.push_back({false, 60, {0x01, 0x00}, 0});
  return steps;
}

struct Options {
  std::string log = "/tmp/seek-sent.log";
  std::string model = "compact";
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
    else if (a == "--model") o.model = value();
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

// Host-visible state, driven by ep0 events: enabled, the start-up sequence, and frame requests
// not yet served.
struct Link {
  const seek::Layout* layout = nullptr;
  std::vector<Expected> startup;
  std::mutex mutex;
  std::condition_variable changed;
  bool enabled = false;
  std::size_t position = 0;  // the next start-up step expected (0: only TARGET_PLATFORM starts one)
  bool running = false;      // the sequence went through: frames are served
  std::uint64_t boots = 0;   // sequences completed (each boots the frame sequence again)
  std::uint64_t refused = 0;
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

void refuse(Link& link, const usb_ctrlrequest& r, const char* why) {
  ++link.refused;
  std::fprintf(stderr, "seek_emulator: refused request %u (%s, wLength %u) at start-up step %zu: %s\n",
               static_cast<unsigned>(r.bRequest), (r.bRequestType & USB_DIR_IN) ? "in" : "out",
               static_cast<unsigned>(r.wLength), link.position, why);
}

// One start-up step done; the last one boots the camera.
void advance(Link& link) {
  if (++link.position < link.startup.size()) return;
  link.running = true;
  ++link.boots;
  link.requests.clear();
  link.changed.notify_all();
}

const Expected* expected_step(const Link& link) {
  return link.position > 0 && link.position < link.startup.size() ? &link.startup[link.position] : nullptr;
}

// An OUT request is judged by its code and length before its data is read (a stall must come
// before the data stage); then by its payload.
bool out_acceptable(const Link& link, const usb_ctrlrequest& r) {
  const Expected* e = expected_step(link);
  if (e && !e->in && e->request == r.bRequest && e->payload.size() == r.wLength) return true;
  if (r.bRequest == kTargetPlatform && r.wLength == 1) return true;
  if (r.bRequest == kSetOperationMode && r.wLength == 2) return true;  // the close sequence
  return link.running && (r.bRequest == kStartGetImageTransfer || r.bRequest == kToggleShutter) && r.wLength == 4;
}

void serve_ep0(FunctionFs& ffs, Link& link) {
  for (;;) {
    const FfsEvent event = ffs.next_event();
    if (event.type == FfsEventType::setup) {
      const usb_ctrlrequest& r = event.setup;
      if ((r.bRequestType & USB_DIR_IN) != 0) {
        bool ok = false;
        {
          std::lock_guard lock(link.mutex);
          const Expected* e = expected_step(link);
          ok = e && e->in && e->request == r.bRequest && e->length == r.wLength;
          if (ok) advance(link);
          else refuse(link, r, "not the next step");
        }
        if (ok) ffs.reply_setup(answer(r.bRequest, r.wLength));
        else ffs.stall_setup(r);
        continue;
      }
      {
        std::lock_guard lock(link.mutex);
        if (!out_acceptable(link, r)) {
          refuse(link, r, "not the next step");
          ffs.stall_setup(r);
          continue;
        }
      }
      const Bytes data = ffs.accept_setup(r.wLength);
      // A data stage cut short by an unplug (the emulator's own disconnect fault) is no request to judge.
      if (data.size() != r.wLength) continue;
      std::lock_guard lock(link.mutex);
      const Expected* e = expected_step(link);
      const std::uint32_t pixels = link.layout->pixels();
      const Bytes count = {static_cast<std::uint8_t>(pixels), static_cast<std::uint8_t>(pixels >> 8),
                           static_cast<std::uint8_t>(pixels >> 16), 0};
      if (r.bRequest == kTargetPlatform && data == Bytes{0x01}) {
        link.position = 1;  // a (re)start
        link.running = false;
      } else if (e && !e->in && e->request == r.bRequest && e->payload == data) {
        advance(link);
      } else if (r.bRequest == kSetOperationMode && data == Bytes{0x00, 0x00}) {
        link.position = 0;  // closed
        link.running = false;
        link.requests.clear();
      } else if (link.running && r.bRequest == kStartGetImageTransfer && data == count) {
        link.requests.push_back(pixels);
        link.changed.notify_all();
      } else if (link.running && r.bRequest == kToggleShutter && data == Bytes{0xFC, 0x00, 0x04, 0x00}) {
      } else {
        // Too late to stall: the camera errs instead, serving nothing until started again.
        refuse(link, r, "wrong payload");
        link.position = 0;
        link.running = false;
        link.requests.clear();
      }
      continue;
    }
    std::lock_guard lock(link.mutex);
    if (event.type == FfsEventType::enable) link.enabled = true;
    if (event.type == FfsEventType::disable || event.type == FfsEventType::unbind) {
      link.enabled = false;  // unplugged: the camera waits for its start-up sequence again
      link.position = 0;
      link.running = false;
      link.requests.clear();
    }
    link.changed.notify_all();
  }
}

class Emulator {
 public:
  Emulator(const Options& o, ConfigfsGadget& gadget, int ep, Link& link)
      : o_(o), gadget_(gadget), ep_(ep), link_(link), l_(*link.layout), log_(o.log), types_(o.shutter_period) {
    if (!log_) throw std::runtime_error(o.log + ": cannot write");
  }

  void run(const FaultPlan& plan) {
    std::uint16_t counter = 1;
    std::uint64_t boot_seen = 0;
    std::uint64_t image = 0;
    std::uint32_t epoch = 0;  // of the offset pattern: one more at each shutter frame
    Bytes repeat, shutter;
    while (image < o_.frames) {
      const std::uint64_t boot = wait_request();
      if (boot != boot_seen) {  // a (re)started camera boots again: start-up frame first
        boot_seen = boot;
        types_ = seek::FrameTypes(o_.shutter_period);
        repeat.clear();
        shutter.clear();
      }
      if (!repeat.empty()) {  // the second copy of a duplicate
        send_chunks(repeat, repeat.size());
        repeat.clear();
        continue;
      }
      const std::uint16_t type = types_.next();
      if (type == seek::kShutter) ++epoch;
      if (type != seek::kImage) {
        Bytes f = seek::make_frame(l_, image, type, counter++, epoch);
        if (type == seek::kShutter) shutter = f;
        log_ << "# type " << type << " counter " << counter - 1 << "\n";
        send_chunks(f, f.size());
        continue;
      }
      const Fault fault = plan.at(image);
      if (fault == Fault::frame_id_jump) counter = static_cast<std::uint16_t>(counter + 5000);
      Bytes f = seek::make_frame(l_, image, type, counter++, epoch);
      char line[160];
      const unsigned long long hash = flirone::fnv1a(f);
      // What the host must deliver: this image minus the latest shutter frame (none: 0).
      const unsigned long long delivered =
          shutter.empty() ? 0 : fnv1a_add_pixels_le(kFnvOffset, seek::expected_image(l_, f, shutter));
      std::snprintf(line, sizeof line, "frame %llu %s %016llx %u %zu %016llx\n",
                    static_cast<unsigned long long>(image), fault_name(fault), hash,
                    static_cast<unsigned>(counter - 1), f.size(), delivered);
      log_ << line;
      log_.flush();
      ++image;
      send_with_fault(f, fault);
      if (fault == Fault::duplicate) repeat = f;
    }
    std::lock_guard lock(link_.mutex);
    log_ << "# refused-requests " << link_.refused << "\n";
    log_.flush();
  }

 private:
  std::uint64_t wait_request() {
    std::unique_lock lock(link_.mutex);
    link_.changed.wait(lock, [&] { return link_.enabled && link_.running && !link_.requests.empty(); });
    link_.requests.pop_front();
    return link_.boots;
  }

  void send_chunks(const Bytes& f, std::size_t stop_after) {
    for (std::size_t at = 0; at < stop_after;) {
      const std::size_t n = std::min<std::size_t>(l_.chunk_bytes, stop_after - at);
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
        send_chunks(f, 2 * l_.chunk_bytes);
        (void)::write(ep_, f.data(), 0);  // the zero-length read a host must abort on
        break;
      case Fault::stall:
        send_chunks(f, l_.chunk_bytes);
        FunctionFs::halt_in_endpoint(ep_);
        break;
      case Fault::timeout:
        send_chunks(f, l_.chunk_bytes);
        std::this_thread::sleep_for(std::chrono::milliseconds(o_.quiet_ms));
        drop_requests();
        break;
      case Fault::disconnect:
        send_chunks(f, l_.chunk_bytes);
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
  const seek::Layout& l_;
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
    if (o.model != "compact" && o.model != "compactpro") throw std::runtime_error("--model: compact or compactpro");
    const seek::Layout& layout = o.model == "compact" ? seek::kCompact : seek::kCompactPro;
    id.product_id = layout.product_id;
    id.manufacturer = "Seek Thermal";
    id.product = o.model == "compact" ? "PIR206 Thermal Camera" : "Seek Thermal CompactPro (emulated)";
    id.serial = "bolo-hil-emulated";
    ConfigfsGadget gadget(o.name, id);
    gadget.add_function("ffs", o.name);
    FunctionFs ffs(o.name, "/dev/ffs-" + o.name);
    ffs.describe({{0xFF, 0xF0, 0, "Seek Thermal", {{true}}}}, true);
    const std::vector<int>& endpoints = ffs.open_endpoints();
    Link link;
    link.layout = &layout;
    link.startup = o.model == "compact" ? kCompactStartup : compact_pro_startup();
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

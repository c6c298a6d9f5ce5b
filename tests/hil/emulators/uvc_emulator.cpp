// PureThermal (FLIR Lepton, UVC Y16) emulator on the kernel's configfs UVC gadget function
// (usb_f_uvc built with bulk streaming, toolchain/vm/uvc-gadget.sh): the host sees it through
// the real uvcvideo driver. Answers the probe/commit negotiation, streams frames of a recording
// (or simulated ones) once the host commits, with Lepton telemetry rows on the 160x122 frame,
// and injects faults on demand. Every frame goes to the send log (send_log.hpp):
// "frame INDEX FAULT HASH COUNTER SIZE IMAGE_HASH", COUNTER being the telemetry frame counter.
//
//   uvc_emulator --log FILE [--frames N] [--recording DIR] [--buffers N] [--ffc-period N]
//                [--fault-rate R --faults short_transfer,duplicate,timeout,disconnect --seed S]
//                [--quiet-ms MS] [--fps F] [--credit FILE:N] [--name NAME]
//                [--xu-log FILE] [--refuse-xu] [--ready F --done F --finished F]
//
// The Lepton command interface (uvc_lepton.hpp) answers on the extension units of the patched
// usb_f_uvc; each request and its answer is printed. A SYS Run FFC puts an FFC (a new "time at
// last FFC" in the telemetry) into the next frame made, as --ffc-period does; --xu-log gets
// "ffc INDEX COUNTER" for each such frame and, at the end, "xu answered N refused M other K
// ffc F". --refuse-xu stalls every extension-unit request (a board that does not answer).
//
// Frames go out at --fps (0: as fast as the host takes them). A bulk UVC host keeps reading
// whether or not its application has a buffer free, and uvcvideo drops a frame it has no buffer
// for (counted as a skipped sequence number), exactly as with a camera: the rate is what the
// host side must keep up with. Under TCG on a shared machine no fixed rate is safe, so with
// --credit the emulator stays at most N deliverable frames ahead of the count the host program
// writes into FILE (a test-harness side channel, no part of UVC): a loss is then the stack's.
//
// Faults: short_transfer (the buffer carries half the frame: uvcvideo flags it and, without
// its nodrop option, drops it; its sequence number is skipped), duplicate (the frame twice),
// timeout (the frame is skipped and the device stays silent --quiet-ms), disconnect (the
// function leaves the bus: the emulator closes the node, 0.2 s later opens it again and waits
// for the host's next commit; frames the host had not taken are logged as lost).

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <deque>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>

#include "configfs_gadget.hpp"
#include "fault_plan.hpp"
#include "uvc_control.hpp"
#include "uvc_device.hpp"
#include "uvc_frames.hpp"
#include "uvc_function.hpp"
#include "uvc_lepton.hpp"
#include "whole_number.hpp"

namespace {

using namespace bolo::hil;
using Clock = std::chrono::steady_clock;

struct Options {
  std::string log = "/tmp/uvc-sent.log";
  std::uint64_t frames = 100;
  std::string recording;
  std::uint32_t buffers = 4;
  std::uint32_t ffc_period = 0;  // frames between FFCs in the telemetry (0: none)
  double fault_rate = 0;
  std::string faults = "short_transfer,duplicate,timeout";
  std::uint64_t seed = 1;
  int quiet_ms = 1500;
  double fps = 0;
  std::string credit_file;
  std::uint64_t credit = 0;
  std::string name = "uvc";
  std::string xu_log;
  bool refuse_xu = false;
  std::string ready = "/tmp/uvc.ready", done = "/tmp/uvc.done", finished = "/tmp/uvc.finished";
};

double real(const std::string& option, const std::string& text) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || v < 0) throw std::runtime_error(option + ": '" + text + "' is not a number >= 0");
  return v;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error(a + " needs a value");
      return argv[++i];
    };
    if (a == "--log") o.log = value();
    else if (a == "--frames") o.frames = whole_number(a, value());
    else if (a == "--recording") o.recording = value();
    else if (a == "--buffers") o.buffers = static_cast<std::uint32_t>(std::min<std::uint64_t>(whole_number(a, value()), 1000));
    else if (a == "--ffc-period") o.ffc_period = static_cast<std::uint32_t>(std::min<std::uint64_t>(whole_number(a, value()), 1u << 30));
    else if (a == "--fault-rate") o.fault_rate = real(a, value());
    else if (a == "--faults") o.faults = value();
    else if (a == "--seed") o.seed = whole_number(a, value());
    else if (a == "--quiet-ms") o.quiet_ms = static_cast<int>(std::min<std::uint64_t>(whole_number(a, value()), 600000));
    else if (a == "--fps") o.fps = real(a, value());
    else if (a == "--credit") {
      const std::string v = value();
      const auto colon = v.rfind(':');
      if (colon == std::string::npos) throw std::runtime_error("--credit wants FILE:N");
      o.credit_file = v.substr(0, colon);
      o.credit = whole_number(a, v.substr(colon + 1));
      if (o.credit == 0) throw std::runtime_error("--credit N must be at least 1");
    }
    else if (a == "--name") o.name = value();
    else if (a == "--xu-log") o.xu_log = value();
    else if (a == "--refuse-xu") o.refuse_xu = true;
    else if (a == "--ready") o.ready = value();
    else if (a == "--done") o.done = value();
    else if (a == "--finished") o.finished = value();
    else throw std::runtime_error("unknown option " + a);
  }
  if (o.buffers < 2 || o.buffers > 32) throw std::runtime_error("--buffers must be within 2..32");
  for (Fault f : parse_fault_list(o.faults))
    if (f != Fault::short_transfer && f != Fault::duplicate && f != Fault::timeout && f != Fault::disconnect)
      throw std::runtime_error(std::string("fault '") + fault_name(f) + "' is not emulated for UVC");
  return o;
}

bool exists(const std::string& path) { return ::access(path.c_str(), F_OK) == 0; }
void touch(const std::string& path) { std::ofstream(path) << "1\n"; }

class Emulator {
 public:
  Emulator(const Options& o, const uvc::FrameFeed& feed, std::uint32_t payload, std::string function_name)
      : o_(o), feed_(feed), payload_(payload), function_(std::move(function_name)), log_(o.log),
        plan_(o.fault_rate, o.seed, parse_fault_list(o.faults)),
        lepton_(uvc::Telemetry{}.fpa_temp_ck, uvc::Telemetry{}.housing_temp_ck, o.refuse_xu) {
    if (!log_) throw std::runtime_error(o.log + ": cannot write");
    if (!o.xu_log.empty()) {
      xu_log_.open(o.xu_log);
      if (!xu_log_) throw std::runtime_error(o.xu_log + ": cannot write");
    }
    probe_ = commit_ = uvc::default_control(payload_);
  }

  // Runs until the host side is finished; true when every frame was sent.
  bool run() {
    open_node();
    touch(o_.ready);
    bool done = false;
    while (!exists(o_.finished)) {
      device_->wait(wait_ms());
      while (auto event = device_->next_event()) handle(*event);
      if (!device_->streaming()) continue;
      while (auto index = device_->take_done()) {
        free_.push_back(*index);
        in_flight_.erase(*index);
      }
      feed_frames();
      if (!done && sent_ == o_.frames && !repeat_ && free_.size() == device_->buffer_count()) {
        log_.flush();
        touch(o_.done);
        done = true;
      }
    }
    char summary[160];
    std::snprintf(summary, sizeof summary, "xu answered %llu refused %llu other %llu ffc %llu\n",
                  static_cast<unsigned long long>(lepton_.answered()), static_cast<unsigned long long>(lepton_.refused()),
                  static_cast<unsigned long long>(lepton_.refused_other()),
                  static_cast<unsigned long long>(lepton_.ffc_runs()));
    std::printf("uvc_emulator: %s", summary);
    xu_log_ << summary << std::flush;
    return done;
  }

 private:
  void open_node() {
    const auto deadline = Clock::now() + std::chrono::seconds(5);
    std::string node;
    while ((node = uvc::find_gadget_node(function_)).empty()) {
      if (Clock::now() > deadline) throw std::runtime_error("no V4L2 node of " + function_ + " after 5 s");
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    device_ = std::make_unique<uvc::UvcDevice>(node);
  }

  void handle(const uvc::Event& e) {
    switch (e.type) {
      case uvc::EventType::setup: setup(e.setup); break;
      case uvc::EventType::data: data(e.data); break;
      case uvc::EventType::disconnect:
        // The host went away (bus reset, unbind): what it had not taken is lost with it.
        stop_stream();
        break;
      default: break;  // connect; stream on/off only come with isochronous alternate settings
    }
  }

  void setup(const usb_ctrlrequest& r) {
    const std::uint8_t selector = static_cast<std::uint8_t>(r.wValue >> 8);
    const bool class_request = (r.bRequestType & USB_TYPE_MASK) == USB_TYPE_CLASS;
    const bool to_interface = (r.bRequestType & USB_RECIP_MASK) == USB_RECIP_INTERFACE;
    // Probe/commit go to the streaming interface (1); the Lepton commands to the control
    // interface (0), wIndex's high byte naming the unit.
    const bool streaming = class_request && to_interface && (r.wIndex & 0xFF) == 1;
    const bool control = class_request && to_interface && (r.wIndex & 0xFF) == 0;
    pending_selector_ = 0;
    pending_unit_.reset();
    if (control) {
      lepton_request(r, static_cast<std::uint8_t>(r.wIndex >> 8), selector);
      return;
    }
    if (!streaming) {
      device_->respond(std::nullopt);
      return;
    }
    if ((r.bRequestType & USB_DIR_IN) == 0) {
      if (r.bRequest == uvc::kSetCur && (selector == uvc::kProbe || selector == uvc::kCommit)) {
        pending_selector_ = selector;
        device_->accept_out(r.wLength);
      } else {
        device_->respond(std::nullopt);
      }
      return;
    }
    const uvc::StreamingControl& current = selector == uvc::kCommit ? commit_ : probe_;
    device_->respond(uvc::answer(r.bRequest, selector, r.wLength, current, payload_));
  }

  void lepton_request(const usb_ctrlrequest& r, std::uint8_t unit, std::uint8_t selector) {
    if (r.bRequestType & USB_DIR_IN) {
      device_->respond(lepton_.get(r.bRequest, unit, selector, r.wLength));
      report();
    } else if (lepton_.accepts_set(r.bRequest, unit, selector, r.wLength)) {
      pending_unit_ = unit;
      pending_selector_ = selector;
      device_->accept_out(r.wLength);
    } else {
      device_->respond(std::nullopt);
      report();
    }
  }

  // uvcvideo's probes of the standard controls at each enumeration are left out.
  void report() {
    if (lepton_.last_was_standard()) return;
    std::printf("uvc_emulator: %s\n", lepton_.last().c_str());
    std::fflush(stdout);
  }

  void data(const std::vector<std::uint8_t>& bytes) {
    const std::uint8_t selector = pending_selector_;
    pending_selector_ = 0;
    if (pending_unit_) {
      lepton_.set(*pending_unit_, selector, bytes);
      pending_unit_.reset();
      report();
      return;
    }
    if (selector == uvc::kProbe) {
      probe_ = uvc::settle(uvc::StreamingControl::decode(bytes, probe_), payload_);
    } else if (selector == uvc::kCommit) {
      commit_ = uvc::settle(uvc::StreamingControl::decode(bytes, commit_), payload_);
      start_stream();
    }
  }

  // Bulk has no alternate setting to select: the commit is the host's "stream on".
  void start_stream() {
    const uvc::FrameSize size = uvc::frame_of(commit_);
    if (device_->streaming() && size.width == size_.width && size.height == size_.height) return;
    stop_stream();
    size_ = size;
    // After an unplug the host has delivered all it will of the frames before: credit restarts.
    if (!o_.credit_file.empty()) deliverable_ = host_delivered();
    device_->start(size_, o_.buffers);
    free_.clear();
    for (std::uint32_t i = 0; i < device_->buffer_count(); ++i) free_.push_back(i);
    std::printf("uvc_emulator: streaming %ux%u Y16, payload %u\n", size_.width, size_.height, payload_);
    std::fflush(stdout);
  }

  void stop_stream() {
    for (const auto& [index, frame] : in_flight_) {
      (void)index;
      (void)frame;
      log_ << "lost-by-emulator\n";  // queued, never taken by the host
    }
    in_flight_.clear();
    free_.clear();
    device_->stop();
  }

  // What the host program has delivered so far (its --progress file; 0 before it exists).
  std::uint64_t host_delivered() const {
    std::ifstream in(o_.credit_file);
    std::uint64_t n = 0;
    in >> n;
    return n;
  }

  // Until the next frame is due (at most 20 ms: events are polled in between; 2 ms while the
  // host's credit is used up).
  int wait_ms() const {
    if (!o_.credit_file.empty() && device_ && device_->streaming()) return 2;
    const auto due = std::max(quiet_until_, next_due_);
    const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(due - Clock::now()).count();
    return static_cast<int>(std::clamp<long long>(ms, 1, 20));
  }

  // Paced: one frame per 1/fps; after a silence or a stall the schedule restarts from now
  // instead of catching up in a burst.
  bool due() {
    const auto now = Clock::now();
    if (now < quiet_until_ || now < next_due_) return false;
    if (!o_.credit_file.empty() && deliverable_ >= host_delivered() + o_.credit) return false;
    if (o_.fps > 0) {
      const auto period = std::chrono::nanoseconds(static_cast<long long>(1e9 / o_.fps));
      next_due_ = (now - next_due_ > std::chrono::milliseconds(50) ? now : next_due_) + period;
    }
    return true;
  }

  void feed_frames() {
    while (!free_.empty() && (sent_ < o_.frames || repeat_) && due()) {
      const std::uint32_t buffer = free_.front();
      if (repeat_) {  // the second copy of a duplicate
        device_->queue(buffer, last_);
        ++deliverable_;
        in_flight_.emplace(buffer, sent_ - 1);
        free_.pop_front();
        repeat_ = false;
        continue;
      }
      const std::uint64_t index = sent_++;
      const Fault fault = plan_.at(index);
      uvc::Telemetry t;
      t.frame_counter = static_cast<std::uint32_t>(index + 1);
      t.uptime_ms = static_cast<std::uint32_t>(1000 + index * 111);
      // The periodic FFC's stamps, or the uptime of the frame after a Run FFC.
      if (o_.ffc_period > 0 && index % o_.ffc_period == 0)
        ffc_stamp_ms_ = static_cast<std::uint32_t>(index / o_.ffc_period) * 100 + 1;
      if (lepton_.take_ffc()) {
        ffc_stamp_ms_ = t.uptime_ms;
        xu_log_ << "ffc " << index << " " << t.frame_counter << "\n" << std::flush;
        std::printf("uvc_emulator: Run FFC shown in frame %llu (counter %u)\n", static_cast<unsigned long long>(index),
                    t.frame_counter);
      }
      t.time_at_last_ffc_ms = ffc_stamp_ms_;
      last_ = feed_.frame(index, size_, t);
      const std::uint64_t image = uvc::fnv1a(last_.data(), uvc::FrameFeed::kPixels * 2);
      char line[160];
      std::snprintf(line, sizeof line, "frame %llu %s %016llx %u %zu %016llx\n", static_cast<unsigned long long>(index),
                    fault_name(fault), static_cast<unsigned long long>(uvc::fnv1a(last_.data(), last_.size())),
                    t.frame_counter, last_.size(), static_cast<unsigned long long>(image));
      log_ << line;
      if (fault == Fault::timeout) {
        quiet_until_ = Clock::now() + std::chrono::milliseconds(o_.quiet_ms);
        return;
      }
      if (fault == Fault::disconnect) {
        unplug();
        return;
      }
      const std::size_t bytes = fault == Fault::short_transfer ? last_.size() / 2 : last_.size();
      device_->queue(buffer, std::span<const std::uint8_t>(last_.data(), bytes));
      if (fault != Fault::short_transfer) ++deliverable_;
      in_flight_.emplace(buffer, index);
      free_.pop_front();
      repeat_ = fault == Fault::duplicate;
    }
  }

  // Unplug: the frames queued before are sent first; then the node is closed (usb_f_uvc leaves
  // the bus when its last subscriber goes), and opened again 0.2 s later (it comes back; the host
  // enumerates it anew and commits again).
  void unplug() {
    const auto deadline = Clock::now() + std::chrono::seconds(2);
    while (!in_flight_.empty() && Clock::now() < deadline) {
      device_->wait(20);
      while (auto index = device_->take_done()) in_flight_.erase(*index);
    }
    stop_stream();
    device_.reset();
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    open_node();
  }

  const Options& o_;
  const uvc::FrameFeed& feed_;
  std::uint32_t payload_;
  std::string function_;
  std::ofstream log_;
  FaultPlan plan_;
  std::unique_ptr<uvc::UvcDevice> device_;
  uvc::StreamingControl probe_, commit_;
  std::uint8_t pending_selector_ = 0;
  std::optional<std::uint8_t> pending_unit_;  // a SET_CUR's data stage for this extension unit
  uvc::LeptonXu lepton_;
  std::ofstream xu_log_;
  std::uint32_t ffc_stamp_ms_ = 0;  // the telemetry's time at last FFC
  uvc::FrameSize size_{};
  std::deque<std::uint32_t> free_;
  std::map<std::uint32_t, std::uint64_t> in_flight_;  // buffer -> frame index
  std::uint64_t sent_ = 0;
  std::uint64_t deliverable_ = 0;  // buffers queued that the host will deliver
  uvc::Bytes last_;
  bool repeat_ = false;
  Clock::time_point quiet_until_{};
  Clock::time_point next_due_{};
};

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    const std::uint32_t payload = uvc::read_bulk_payload();
    const uvc::FrameFeed feed(o.recording);
    GadgetIdentity id;
    id.vendor_id = 0x1e4e;  // GroupGets PureThermal
    id.product_id = 0x0100;
    id.bcd_device = 0x0200;
    id.manufacturer = "GroupGets";
    id.product = "PureThermal (bolo HIL emulator)";
    id.serial = "bolo-hil-emulated";
    id.device_class = 0xEF;  // miscellaneous / interface association: UVC
    id.device_subclass = 2;
    id.device_protocol = 1;
    std::unique_ptr<ConfigfsGadget> gadget = std::make_unique<ConfigfsGadget>(o.name, id);
    gadget->add_function("uvc", o.name, uvc::describe_purethermal);
    gadget->bind();
    bool done = false;
    {
      Emulator emulator(o, feed, payload, "uvc." + o.name);
      done = emulator.run();
    }  // the node is closed before the unbind, which waits for it
    gadget->unbind();
    return done ? 0 : 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uvc_emulator: %s\n", e.what());
    return 1;
  }
}

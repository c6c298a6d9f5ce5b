// HIL test, host side, for the FLIR ONE: streams from the device (the emulator inside the HIL
// VM, or a real camera), reassembles frames, counts every fault and, against an emulator, checks
// that exactly the frames it sent whole arrived, bit for bit and in order, and that every fault
// it injected was counted. Prints one summary line; exit 0 = pass.
//
//   hil_flirone --send-log FILE --done FILE [--capture DIR] [--min-frames N]
//   hil_flirone --real --frames N          (a real camera: every frame valid, nothing lost)

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <optional>
#include <span>
#include <stdexcept>
#include <cstdio>
#include <string>
#include <vector>

#include "emulators/flirone_frames.hpp"
#include "flirone_assembler.hpp"
#include "flirone_usb.hpp"
#include "send_log.hpp"

namespace {

using namespace bolo::hil;
using Clock = std::chrono::steady_clock;

struct Options {
  std::string send_log;
  std::string done;
  std::string capture;  // replay run: delivered frames must equal the capture's frames
  std::uint64_t min_frames = 1;
  std::uint64_t real_frames = 0;  // > 0: real camera mode
  unsigned timeout_ms = 500;
  bool wrong_start = false;  // the refusal check: the vendor request alone must get no frames
  double max_recovery_s = 2.0;
};

struct Counts {
  std::uint64_t frames = 0, short_frames = 0, corrupt = 0, stalls = 0, timeouts = 0, disconnects = 0;
  std::uint64_t duplicates = 0, id_surprises = 0;
  double max_recovery_s = 0;
};

bool exists(const std::string& path) {
  struct stat st {};
  return !path.empty() && stat(path.c_str(), &st) == 0;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error(a + " needs a value");
      return argv[++i];
    };
    if (a == "--send-log") o.send_log = value();
    else if (a == "--done") o.done = value();
    else if (a == "--capture") o.capture = value();
    else if (a == "--min-frames") o.min_frames = std::stoull(value());
    else if (a == "--real") o.real_frames = 1;
    else if (a == "--frames") o.real_frames = std::stoull(value());
    else if (a == "--wrong-start") o.wrong_start = true;
    else if (a == "--timeout-ms") o.timeout_ms = static_cast<unsigned>(std::stoul(value()));
    else throw std::runtime_error("unknown option " + a);
  }
  return o;
}

class Stream {
 public:
  Stream(const Options& o, Counts& c) : o_(o), c_(c), buffer_(1 << 16) {}

  // Reads until the emulator is done (or, on a real camera, enough frames have arrived).
  void run() {
    std::string error;
    if (!usb_.open(std::chrono::seconds(20), error)) throw std::runtime_error("FLIR ONE: " + error);
    for (;;) {
      if (o_.real_frames > 0 && c_.frames >= o_.real_frames) return;
      int n = 0;
      switch (usb_.read(buffer_.data(), static_cast<int>(buffer_.size()), n, o_.timeout_ms)) {
        case flirone::ReadStatus::data: take({buffer_.data(), static_cast<std::size_t>(n)}); break;
        case flirone::ReadStatus::timeout:
          if (assembler_.drop_partial()) ++c_.timeouts;
          else if (exists(o_.done)) return;
          break;
        case flirone::ReadStatus::stall:
          ++c_.stalls;
          assembler_.drop_partial();
          usb_.clear_stall();
          break;
        case flirone::ReadStatus::gone: reconnect(); break;
      }
    }
  }

  std::vector<flirone::Bytes> kept;  // delivered frames, kept only for a replay comparison
  std::vector<std::uint64_t> hashes;
  std::vector<std::uint32_t> counters;

 private:
  void reconnect() {
    ++c_.disconnects;
    assembler_.drop_partial();
    usb_.close();
    lost_at_ = Clock::now();
    std::string error;
    if (!usb_.open(std::chrono::seconds(10), error))
      throw std::runtime_error("FLIR ONE did not come back within 10 s: " + error);
  }

  void take(std::span<const std::uint8_t> transfer) {
    pieces_.clear();
    frames_.clear();
    assembler_.feed(transfer, pieces_, frames_);
    std::size_t next = 0;
    for (flirone::Piece p : pieces_) {
      if (p == flirone::Piece::short_frame) ++c_.short_frames;
      if (p == flirone::Piece::corrupt) ++c_.corrupt;
      if (p == flirone::Piece::frame) deliver(std::move(frames_[next++]));
    }
  }

  void deliver(flirone::Bytes frame) {
    if (lost_at_) {
      const double s = std::chrono::duration<double>(Clock::now() - *lost_at_).count();
      c_.max_recovery_s = std::max(c_.max_recovery_s, s);
      lost_at_.reset();
    }
    const std::uint64_t hash = flirone::fnv1a(frame);
    const std::uint32_t counter = flirone::frame_counter(frame);
    if (!hashes.empty() && hash == hashes.back()) ++c_.duplicates;
    if (!counters.empty() && counter_surprise(counters.back(), counter)) ++c_.id_surprises;
    hashes.push_back(hash);
    counters.push_back(counter);
    ++c_.frames;
    if (!o_.capture.empty()) kept.push_back(std::move(frame));
  }

  const Options& o_;
  Counts& c_;
  flirone::FlirOneUsb usb_;
  flirone::FrameAssembler assembler_;
  std::vector<std::uint8_t> buffer_;
  std::vector<flirone::Piece> pieces_;
  std::vector<flirone::Bytes> frames_;
  std::optional<Clock::time_point> lost_at_;
};

int failures = 0;
void expect(bool ok, const std::string& what) {
  if (!ok) {
    ++failures;
    std::printf("hil_flirone: FAIL %s\n", what.c_str());
  }
}

std::string vs(std::uint64_t got, std::uint64_t want) {
  return "got " + std::to_string(got) + ", want " + std::to_string(want);
}

void check_against_emulator(const Options& o, const Counts& c, const Stream& s) {
  const Expectation e = read_send_log(o.send_log);
  expect(e.lost_by_emulator == 0, "the emulator lost frames it did not mean to lose: " +
                                      std::to_string(e.lost_by_emulator));
  expect(e.refused_requests == 0, "the emulator refused " + std::to_string(e.refused_requests) +
                                      " start-up requests (-1: not reported)");
  expect(c.frames == e.deliver.size(), "frames delivered: " + vs(c.frames, e.deliver.size()));
  std::size_t first_mismatch = e.deliver.size();
  for (std::size_t i = 0; i < std::min(e.deliver.size(), s.hashes.size()); ++i)
    if (s.hashes[i] != e.deliver[i].hash) {
      first_mismatch = i;
      break;
    }
  expect(first_mismatch == e.deliver.size(),
         "delivered frame " + std::to_string(first_mismatch) + " differs from emulator frame " +
             (first_mismatch < e.deliver.size() ? std::to_string(e.deliver[first_mismatch].index) : "-"));
  auto injected = [&](Fault f) { return e.injected[static_cast<std::size_t>(f)]; };
  expect(c.short_frames == injected(Fault::short_transfer), "short frames: " + vs(c.short_frames, injected(Fault::short_transfer)));
  expect(c.corrupt == injected(Fault::corrupt), "corrupt frames: " + vs(c.corrupt, injected(Fault::corrupt)));
  expect(c.stalls == injected(Fault::stall), "stalls: " + vs(c.stalls, injected(Fault::stall)));
  expect(c.timeouts == injected(Fault::timeout), "timeouts: " + vs(c.timeouts, injected(Fault::timeout)));
  expect(c.disconnects == injected(Fault::disconnect), "disconnects: " + vs(c.disconnects, injected(Fault::disconnect)));
  std::uint64_t want_dups = 0, want_surprises = 0;
  for (std::size_t i = 1; i < e.deliver.size(); ++i) {
    want_dups += e.deliver[i].hash == e.deliver[i - 1].hash;
    want_surprises += counter_surprise(e.deliver[i - 1].counter, e.deliver[i].counter);
  }
  expect(c.duplicates == want_dups, "duplicates: " + vs(c.duplicates, want_dups));
  expect(c.id_surprises == want_surprises, "frame-id surprises: " + vs(c.id_surprises, want_surprises));
  expect(c.frames >= o.min_frames, "frames: " + vs(c.frames, o.min_frames) + " at least");
  expect(c.max_recovery_s <= o.max_recovery_s, "replug recovery " + std::to_string(c.max_recovery_s) + " s > 2 s");
  std::printf("hil_flirone: emulator sent %llu frames; injected short %llu corrupt %llu stall %llu timeout %llu "
              "disconnect %llu id-jump %llu duplicate %llu\n",
              static_cast<unsigned long long>(e.frames_sent),
              static_cast<unsigned long long>(injected(Fault::short_transfer)),
              static_cast<unsigned long long>(injected(Fault::corrupt)),
              static_cast<unsigned long long>(injected(Fault::stall)),
              static_cast<unsigned long long>(injected(Fault::timeout)),
              static_cast<unsigned long long>(injected(Fault::disconnect)),
              static_cast<unsigned long long>(injected(Fault::frame_id_jump)),
              static_cast<unsigned long long>(injected(Fault::duplicate)));
}

void check_against_capture(const Options& o, const Stream& s) {
  const std::vector<flirone::Bytes> frames = flirone::split_frames(flirone::load_capture(o.capture));
  expect(s.kept.size() == frames.size(), "replayed frames: " + vs(s.kept.size(), frames.size()));
  for (std::size_t i = 0; i < std::min(frames.size(), s.kept.size()); ++i)
    expect(s.kept[i] == frames[i], "replayed frame " + std::to_string(i) + " differs from the capture");
  // The emulator's simulated frames carry CRCs computed as the real camera computes them.
  for (std::size_t i = 0; i < frames.size(); ++i) {
    flirone::Bytes resealed = frames[i];
    flirone::seal_packets(resealed);
    expect(resealed == frames[i], "capture frame " + std::to_string(i) + ": VoSPI CRC model disagrees");
  }
}

}  // namespace

// A host that starts the camera the way the emulator once accepted (vendor request 0x41/0x0b
// instead of the drivers' SET_INTERFACE sequence) must see the request stalled and no frame.
int check_wrong_start() {
  flirone::FlirOneUsb usb;
  std::string error;
  const int rc = usb.open_with_vendor_start(std::chrono::seconds(10), error);
  expect(rc != 1, "the device never appeared: " + error);
  expect(rc == LIBUSB_ERROR_PIPE, std::string("the vendor request was not stalled: ") +
                                      (rc < 0 ? libusb_error_name(rc) : std::to_string(rc)));
  std::vector<std::uint8_t> buffer(1 << 16);
  int got = 0;
  const flirone::ReadStatus r = usb.is_open() ? usb.read(buffer.data(), static_cast<int>(buffer.size()), got, 1500)
                                              : flirone::ReadStatus::gone;
  expect(r == flirone::ReadStatus::timeout && got == 0,
         "frames flowed without the drivers' start-up (" + std::to_string(got) + " bytes)");
  std::printf("hil_flirone: %s: vendor request alone: %s, no frame in 1.5 s\n", failures == 0 ? "PASS" : "FAIL",
              rc < 0 ? libusb_error_name(rc) : "accepted");
  return failures == 0 ? 0 : 1;
}

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    if (o.wrong_start) return check_wrong_start();
    Counts c;
    Stream stream(o, c);
    const auto start = Clock::now();
    stream.run();
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    if (o.real_frames > 0) {
      expect(c.corrupt == 0 && c.short_frames == 0 && c.stalls == 0 && c.disconnects == 0,
             "a real camera without injected faults lost frames");
    } else {
      check_against_emulator(o, c, stream);
    }
    if (!o.capture.empty()) check_against_capture(o, stream);
    std::printf("hil_flirone: %s: %llu frames in %.1f s (%.0f/s); counted short %llu corrupt %llu stall %llu "
                "timeout %llu disconnect %llu duplicate %llu id-surprise %llu; max replug recovery %.3f s\n",
                failures == 0 ? "PASS" : "FAIL", static_cast<unsigned long long>(c.frames), seconds,
                static_cast<double>(c.frames) / seconds, static_cast<unsigned long long>(c.short_frames),
                static_cast<unsigned long long>(c.corrupt), static_cast<unsigned long long>(c.stalls),
                static_cast<unsigned long long>(c.timeouts), static_cast<unsigned long long>(c.disconnects),
                static_cast<unsigned long long>(c.duplicates), static_cast<unsigned long long>(c.id_surprises),
                c.max_recovery_s);
    return failures == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::printf("hil_flirone: FAIL %s\n", e.what());
    return 1;
  }
}

// HIL test through the project's Seek backend: bolo::hal::SeekSource over LibusbTransport
// streaming from the Seek Compact emulator. Every delivered 207x154 image must equal, bit for
// bit and in order, what the emulator computed for an image frame it sent whole: that frame's
// active area minus the latest shutter frame sent (0x4000 + image - shutter), its dead pixels
// filled (seek_frames.hpp, written apart from the HAL). The emulator must have refused no
// request (its start-up sequence check); shutter frames must show up as FFC events, the
// start-up frame's dead pixels in the dead-pixel map, broken frames in the counters.
// On a real camera (no send log to compare with) every image must arrive whole and in sequence:
// nothing dropped, duplicated, short or corrupt, no disconnect, no timeout once streaming.
//
//   hil_seek_hal --send-log FILE --done FILE [--min-frames N] [--shutters N] [--dead-pixels N]
//   hil_seek_hal --real --frames N

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "bolo/hal/seek_source.hpp"
#include "bolo/hal/usb_libusb.hpp"
#include "real_stream.hpp"
#include "send_log.hpp"
#include "emulators/fnv1a.hpp"

namespace {

using namespace bolo;
using Clock = std::chrono::steady_clock;

bool exists(const std::string& path) {
  struct stat st {};
  return stat(path.c_str(), &st) == 0;
}

// Hashes the pushed lines as little-endian bytes (how the emulator hashed its frame words).
class HashingSink final : public fw::LineSink {
 public:
  void begin_frame(const fw::FrameHeader& header) override {
    hash_ = hil::kFnvOffset;
    ffc_ = header.ffc;
  }
  void push_line(std::uint32_t, fw::LineView line) override {
    hash_ = hil::fnv1a_add_pixels_le(hash_, line);
  }
  void end_frame() override {
    hashes.push_back(hash_);
    if (ffc_ == fw::FfcState::completed) ++after_ffc;
  }
  std::vector<std::uint64_t> hashes;
  std::uint64_t after_ffc = 0;

 private:
  std::uint64_t hash_ = 0;
  fw::FfcState ffc_ = fw::FfcState::unknown;
};

// A real camera: `frames` images, each whole and in sequence. Timeouts before the first image are
// the camera's start-up (it boots, then calibrates) and are only reported.
int stream_real_camera(hal::SeekSource& source, HashingSink& sink, const hal::SeekModel& model,
                       std::uint64_t frames) {
  const bolo::hil::RealStreamRun run =
      bolo::hil::stream_real(source, sink, frames, [&] { return sink.hashes.size(); });
  const double seconds = run.seconds;
  const hal::SourceStats st = source.stats();
  std::uint64_t repeated = 0;  // a sensor's noise makes two equal images in a row a duplicate
  for (std::size_t i = 1; i < sink.hashes.size(); ++i) repeated += sink.hashes[i] == sink.hashes[i - 1] ? 1 : 0;
  const std::uint64_t startup_timeouts = run.startup_timeouts(st);
  int failures = 0;
  auto expect = [&](bool ok, const std::string& what) {
    if (!ok) {
      ++failures;
      std::printf("hil_seek_hal: FAIL %s\n", what.c_str());
    }
  };
  expect(sink.hashes.size() == frames,
         "images delivered: got " + std::to_string(sink.hashes.size()) + ", want " + std::to_string(frames) +
             " (none for 15 s)");
  expect(st.dropped == 0 && source.counters().counter_jumps == 0,
         std::to_string(st.dropped) + " images dropped, " + std::to_string(source.counters().counter_jumps) +
             " frame counter jumps");
  expect(st.duplicates == 0 && repeated == 0,
         std::to_string(st.duplicates) + " duplicate frame ids, " + std::to_string(repeated) + " repeated images");
  expect(st.short_transfers == 0 && st.corrupt_transfers == 0,
         std::to_string(st.short_transfers) + " short, " + std::to_string(st.corrupt_transfers) + " corrupt transfers");
  expect(st.disconnects == 0, std::to_string(st.disconnects) + " disconnects");
  expect(st.timeouts == startup_timeouts,
         std::to_string(st.timeouts - startup_timeouts) + " timeouts after the first image");
  expect(source.dead_pixels() < model.crop.pixels() / 100,
         "dead-pixel map marks " + std::to_string(source.dead_pixels()) + " pixels (>= 1 %)");
  std::printf("hil_seek_hal: %s: real Seek %s, %zu images in %.1f s (%.1f/s); shutter frames %llu, dead pixels %u, "
              "start-up timeouts %llu\n",
              failures == 0 ? "PASS" : "FAIL", model.name, sink.hashes.size(), seconds,
              static_cast<double>(sink.hashes.size()) / seconds,
              static_cast<unsigned long long>(source.counters().shutter_frames), source.dead_pixels(),
              static_cast<unsigned long long>(startup_timeouts));
  return failures == 0 ? 0 : 1;
}

// The emulator's "# refused-requests N" line (start-up requests out of order or with a wrong
// payload); -1 when there is none.
long refused_requests(const std::string& send_log) {
  std::ifstream in(send_log);
  const std::string tag = "# refused-requests ";
  long refused = -1;
  for (std::string line; std::getline(in, line);)
    if (line.rfind(tag, 0) == 0) refused = std::stol(line.substr(tag.size()));
  return refused;
}

}  // namespace

int main(int argc, char** argv) {
  std::string send_log, done;
  std::uint64_t min_frames = 1, want_shutters = 0, want_dead = 0, real_frames = 0;
  for (int i = 1; i < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--real") {
      real_frames = std::max<std::uint64_t>(real_frames, 1);
      --i;  // no value
      continue;
    }
    if (i + 1 >= argc) {
      std::printf("hil_seek_hal: FAIL option %s needs a value\n", a.c_str());
      return 2;
    }
    if (a == "--frames") real_frames = std::stoull(argv[i + 1]);
    else if (a == "--send-log") send_log = argv[i + 1];
    else if (a == "--done") done = argv[i + 1];
    else if (a == "--min-frames") min_frames = std::stoull(argv[i + 1]);
    else if (a == "--shutters") want_shutters = std::stoull(argv[i + 1]);
    else if (a == "--dead-pixels") want_dead = std::stoull(argv[i + 1]);
    else {
      std::printf("hil_seek_hal: FAIL unknown option %s\n", a.c_str());
      return 2;
    }
  }
  if (real_frames == 0 && (send_log.empty() || done.empty())) {
    std::printf("hil_seek_hal: FAIL give --send-log and --done (emulator) or --real --frames N (camera)\n");
    return 2;
  }
  try {
    std::unique_ptr<hal::LibusbTransport> transport;
    const auto patience = Clock::now() + std::chrono::seconds(20);
    for (;;) {
      try {
        transport = std::make_unique<hal::LibusbTransport>(hal::seek_libusb_config());
        break;
      } catch (const std::exception&) {
        if (Clock::now() > patience) throw;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
    }
    hal::SeekSourceConfig config;
    config.transfer_timeout_ms = 500;
    const hal::SeekModel& model = transport->opened().product_id == hal::kSeekCompactPro.product_id
                                      ? hal::kSeekCompactPro
                                      : hal::kSeekCompact;
    hal::SeekSource source(*transport, model, config);
    HashingSink sink;
    if (real_frames > 0) return stream_real_camera(source, sink, model, real_frames);
    const auto start = Clock::now();
    std::optional<bolo::hil::Expectation> expected;
    auto last_progress = Clock::now();
    std::size_t before = 0;
    for (;;) {
      source.stream_frame(sink);
      if (sink.hashes.size() != before) {
        before = sink.hashes.size();
        last_progress = Clock::now();
      } else if (Clock::now() - last_progress > std::chrono::seconds(15)) {
        std::printf("hil_seek_hal: FAIL no frame for 15 s after %zu frames\n", sink.hashes.size());
        break;
      }
      if (!expected && exists(done)) expected = bolo::hil::read_send_log(send_log);
      if (expected && sink.hashes.size() >= expected->deliver.size()) break;
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    if (!expected) throw std::runtime_error("the emulator never finished (no " + done + ")");
    int failures = 0;
    auto expect = [&](bool ok, const std::string& what) {
      if (!ok) {
        ++failures;
        std::printf("hil_seek_hal: FAIL %s\n", what.c_str());
      }
    };
    std::uint64_t broken = 0;
    for (std::size_t f = 0; f < expected->injected.size(); ++f)
      if (bolo::hil::fault_loses_frame(static_cast<bolo::hil::Fault>(f))) broken += expected->injected[f];
    expect(sink.hashes.size() == expected->deliver.size(), "images delivered: got " + std::to_string(sink.hashes.size()) +
                                                               ", want " + std::to_string(expected->deliver.size()));
    for (std::size_t i = 0; i < std::min(sink.hashes.size(), expected->deliver.size()); ++i)
      if (sink.hashes[i] != expected->deliver[i].image_hash) {
        expect(false, "delivered image " + std::to_string(i) + " differs from emulator image " +
                          std::to_string(expected->deliver[i].index));
        break;
      }
    const hal::SourceStats st = source.stats();
    const long refused = refused_requests(send_log);
    expect(refused == 0, "the emulator refused " + std::to_string(refused) + " requests (-1: not reported)");
    const std::uint64_t counted = st.timeouts + st.short_transfers + st.corrupt_transfers + st.disconnects;
    expect(counted >= broken, "faults counted " + std::to_string(counted) + " < frames broken " + std::to_string(broken));
    expect(sink.hashes.size() >= min_frames, "fewer than " + std::to_string(min_frames) + " images");
    const std::uint64_t unplugs = expected->injected[static_cast<std::size_t>(bolo::hil::Fault::disconnect)];
    expect(st.disconnects == unplugs, "disconnects counted " + std::to_string(st.disconnects) + ", injected " +
                                          std::to_string(unplugs));
    // Duplicates are delivered and counted; a copy whose twin was lost to an unplug is not one.
    const std::uint64_t dups = expected->injected[static_cast<std::size_t>(bolo::hil::Fault::duplicate)];
    expect(st.duplicates <= dups && st.duplicates + unplugs >= dups,
           "duplicates counted " + std::to_string(st.duplicates) + ", injected " + std::to_string(dups));
    const std::uint64_t jumps = expected->injected[static_cast<std::size_t>(bolo::hil::Fault::frame_id_jump)];
    expect(source.counters().counter_jumps >= jumps, "frame counter jumps counted " +
                                                         std::to_string(source.counters().counter_jumps) +
                                                         " < injected " + std::to_string(jumps));
    if (want_shutters > 0)
      expect(source.counters().shutter_frames == want_shutters,
             "shutter frames: got " + std::to_string(source.counters().shutter_frames) + ", want " +
                 std::to_string(want_shutters));
    if (want_dead > 0)
      expect(source.dead_pixels() == want_dead, "dead pixels: got " + std::to_string(source.dead_pixels()) +
                                                    ", want " + std::to_string(want_dead));
    std::printf("hil_seek_hal: %s: SeekSource delivered %zu images in %.1f s (%.0f/s), %llu after FFC; shutter "
                "frames %llu, dead pixels %u, images before a shutter frame %llu; emulator broke %llu, refused %ld; counted timeouts %llu short %llu corrupt %llu "
                "disconnects %llu duplicates %llu counter jumps %llu (dropped %llu)\n",
                failures == 0 ? "PASS" : "FAIL", sink.hashes.size(), seconds,
                static_cast<double>(sink.hashes.size()) / seconds, static_cast<unsigned long long>(sink.after_ffc),
                static_cast<unsigned long long>(source.counters().shutter_frames), source.dead_pixels(),
                static_cast<unsigned long long>(source.counters().images_before_shutter),
                static_cast<unsigned long long>(broken), refused, static_cast<unsigned long long>(st.timeouts),
                static_cast<unsigned long long>(st.short_transfers), static_cast<unsigned long long>(st.corrupt_transfers),
                static_cast<unsigned long long>(st.disconnects), static_cast<unsigned long long>(st.duplicates),
                static_cast<unsigned long long>(source.counters().counter_jumps),
                static_cast<unsigned long long>(st.dropped));
    return failures == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::printf("hil_seek_hal: FAIL %s\n", e.what());
    return 1;
  }
}

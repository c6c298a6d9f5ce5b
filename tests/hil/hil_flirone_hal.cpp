// HIL test through the project's own backend: bolo::hal::FlirOneSource over LibusbTransport
// (what `bolo capture --device usb:flirone` uses) streaming from the FLIR ONE emulator. Every
// delivered 80x60 image must equal, bit for bit and in order, an image the emulator sent whole;
// every frame the emulator broke must show up in the source's fault counters. On a real camera
// (no send log to compare with) every frame must arrive whole and in sequence.
//
//   hil_flirone_hal --send-log FILE --done FILE [--min-frames N]
//   hil_flirone_hal --real --frames N

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <span>
#include <thread>
#include <stdexcept>
#include <string>
#include <vector>

#include "bolo/hal/flirone_source.hpp"
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

// Hashes the pushed lines the way the emulator hashed its image rows (little-endian pixels);
// an image not of the expected size (the emulator's 80x60, or a real camera's format) hashes 0.
class HashingSink final : public fw::LineSink {
 public:
  void begin_frame(const fw::FrameHeader& header) override {
    hash_ = hil::kFnvOffset;
    rows_ = 0;
    width_ok_ = header.width == width && header.height == height;
  }
  void push_line(std::uint32_t row, fw::LineView line) override {
    if (row != rows_ || line.size() != width) width_ok_ = false;
    hash_ = hil::fnv1a_add_pixels_le(hash_, line);
    ++rows_;
  }
  void end_frame() override {
    hashes.push_back(width_ok_ && rows_ == height ? hash_ : 0);
  }
  std::vector<std::uint64_t> hashes;
  std::uint32_t width = 80, height = 60;

 private:
  std::uint64_t hash_ = 0;
  std::uint32_t rows_ = 0;
  bool width_ok_ = false;
};

// Between the source and the transport: when the transport first reported an unplug, and the
// longest single reconnect() that succeeded.
class TimedTransport final : public hal::BulkInTransport {
 public:
  explicit TimedTransport(hal::BulkInTransport& inner) : inner_(inner) {}
  hal::Transfer next(std::span<std::uint8_t> buffer, std::uint32_t timeout_ms) override {
    const hal::Transfer t = inner_.next(buffer, timeout_ms);
    if (t.status == hal::TransferStatus::disconnected && !gone_at) gone_at = Clock::now();
    return t;
  }
  bool reconnect(std::uint32_t timeout_ms) override {
    const auto start = Clock::now();
    const bool ok = inner_.reconnect(timeout_ms);
    if (ok) max_reconnect_s = std::max(max_reconnect_s, std::chrono::duration<double>(Clock::now() - start).count());
    return ok;
  }
  std::optional<Clock::time_point> gone_at;  // reset by the caller once recovered
  double max_reconnect_s = 0;

 private:
  hal::BulkInTransport& inner_;
};

// A real camera: `frames` images, each whole (in the geometry of its first frame: 80x60 or
// 160x120) and in sequence. Timeouts before the first image are the camera's start-up and are
// only reported; the core exports some frames twice
// (same counter, the shared capture has them), so duplicates are reported, not failed.
int stream_real_camera(hal::FlirOneSource& source, HashingSink& sink, std::uint64_t frames) {
  source.probe();  // the first frame's geometry, as usb:flirone opens it
  sink.width = source.format().width;
  sink.height = source.format().height;
  const bolo::hil::RealStreamRun run =
      bolo::hil::stream_real(source, sink, frames, [&] { return sink.hashes.size(); });
  const double seconds = run.seconds;
  const hal::SourceStats st = source.stats();
  const std::uint64_t startup_timeouts = run.startup_timeouts(st);
  const auto malformed = static_cast<std::uint64_t>(std::count(sink.hashes.begin(), sink.hashes.end(), 0u));
  int failures = 0;
  auto expect = [&](bool ok, const std::string& what) {
    if (!ok) {
      ++failures;
      std::printf("hil_flirone_hal: FAIL %s\n", what.c_str());
    }
  };
  expect(sink.hashes.size() == frames, "images delivered: got " + std::to_string(sink.hashes.size()) + ", want " +
                                           std::to_string(frames) + " (none for 15 s)");
  expect(malformed == 0, std::to_string(malformed) + " images not " + std::to_string(sink.width) + "x" +
                             std::to_string(sink.height) + " with every row in order");
  expect(st.short_transfers == 0 && st.corrupt_transfers == 0,
         std::to_string(st.short_transfers) + " short, " + std::to_string(st.corrupt_transfers) + " corrupt transfers");
  expect(st.disconnects == 0, std::to_string(st.disconnects) + " disconnects");
  expect(st.timeouts == startup_timeouts,
         std::to_string(st.timeouts - startup_timeouts) + " timeouts after the first image");
  expect(source.skipped_in_camera() == 0 && source.counter_jumps() == 0,
         std::to_string(source.skipped_in_camera()) + " frames skipped in the camera, " +
             std::to_string(source.counter_jumps()) + " frame counter jumps");
  std::printf("hil_flirone_hal: %s: real FLIR ONE (%ux%u), %zu images in %.1f s (%.1f/s); duplicates %llu, start-up "
              "timeouts %llu\n",
              failures == 0 ? "PASS" : "FAIL", sink.width, sink.height, sink.hashes.size(), seconds,
              static_cast<double>(sink.hashes.size()) / seconds, static_cast<unsigned long long>(st.duplicates),
              static_cast<unsigned long long>(startup_timeouts));
  return failures == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  std::string send_log, done;
  std::uint64_t min_frames = 1, real_frames = 0;
  for (int i = 1; i < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--real") {
      real_frames = std::max<std::uint64_t>(real_frames, 1);
      --i;  // no value
      continue;
    }
    if (i + 1 >= argc) {
      std::printf("hil_flirone_hal: FAIL option %s needs a value\n", a.c_str());
      return 2;
    }
    if (a == "--frames") real_frames = std::stoull(argv[i + 1]);
    else if (a == "--send-log") send_log = argv[i + 1];
    else if (a == "--done") done = argv[i + 1];
    else if (a == "--min-frames") min_frames = std::stoull(argv[i + 1]);
    else {
      std::printf("hil_flirone_hal: FAIL unknown option %s\n", a.c_str());
      return 2;
    }
  }
  if (real_frames == 0 && (send_log.empty() || done.empty())) {
    std::printf("hil_flirone_hal: FAIL give --send-log and --done (emulator) or --real --frames N (camera)\n");
    return 2;
  }
  try {
    std::unique_ptr<hal::LibusbTransport> transport;
    const auto patience = Clock::now() + std::chrono::seconds(20);
    for (;;) {
      try {
        transport = std::make_unique<hal::LibusbTransport>(hal::flirone_libusb_config());
        break;
      } catch (const std::exception& e) {
        if (Clock::now() > patience) throw;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
    }
    hal::FlirOneSourceConfig config;
    config.transfer_timeout_ms = 500;
    config.reconnect_timeout_ms = 2000;
    TimedTransport timed(*transport);
    hal::FlirOneSource source(timed, config);
    HashingSink sink;
    if (real_frames > 0) return stream_real_camera(source, sink, real_frames);
    const auto start = Clock::now();
    std::uint64_t faults = 0, ends = 0;
    std::optional<bolo::hil::Expectation> expected;
    std::optional<Clock::time_point> done_seen;
    auto last_progress = Clock::now();
    std::size_t delivered_before = 0;
    // Replug recovery, bounded from above: from the last frame delivered before an unplug (the
    // source counts the unplug only once it has reconnected) to the first one after it, divided
    // by the unplugs in between (back-to-back faults unplug again before a frame gets through).
    // It includes the emulator's 0.2 s away and the broken frame's first half.
    std::uint64_t disconnects_before = 0, unplugs_in_gap = 0;
    std::optional<Clock::time_point> unplugged;
    Clock::time_point last_frame = Clock::now();
    double max_recovery_s = 0, max_detect_s = 0;
    for (;;) {
      const hal::StreamStatus status = source.stream_frame(sink);
      if (status == hal::StreamStatus::fault) ++faults;
      if (source.stats().disconnects != disconnects_before) {
        unplugs_in_gap += source.stats().disconnects - disconnects_before;
        disconnects_before = source.stats().disconnects;
        if (!unplugged) unplugged = last_frame;
      }
      if (sink.hashes.size() != delivered_before) {
        delivered_before = sink.hashes.size();
        last_progress = Clock::now();
        last_frame = last_progress;
        if (unplugged) {
          const double gap = std::chrono::duration<double>(last_progress - *unplugged).count();
          max_recovery_s = std::max(max_recovery_s, gap / static_cast<double>(unplugs_in_gap));
          if (timed.gone_at && unplugs_in_gap == 1)
            max_detect_s = std::max(max_detect_s, std::chrono::duration<double>(*timed.gone_at - *unplugged).count());
          timed.gone_at.reset();
          unplugs_in_gap = 0;
          unplugged.reset();
        }
      } else if (Clock::now() - last_progress > std::chrono::seconds(15)) {
        const hal::SourceStats st = source.stats();
        std::printf("hil_flirone_hal: FAIL no frame for 15 s after %zu frames (timeouts %llu short %llu "
                    "corrupt %llu disconnects %llu)\n", sink.hashes.size(),
                    static_cast<unsigned long long>(st.timeouts), static_cast<unsigned long long>(st.short_transfers),
                    static_cast<unsigned long long>(st.corrupt_transfers),
                    static_cast<unsigned long long>(st.disconnects));
        return 1;
      }
      if (status == hal::StreamStatus::end_of_stream && ++ends > 3) break;
      if (!expected && exists(done)) {
        expected = bolo::hil::read_send_log(send_log);
        done_seen = Clock::now();
      }
      if (expected && sink.hashes.size() >= expected->deliver.size()) break;
      if (done_seen && Clock::now() - *done_seen > std::chrono::seconds(5)) break;  // frames missing
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    const hal::SourceStats st = source.stats();
    int failures = 0;
    auto expect = [&](bool ok, const std::string& what) {
      if (!ok) {
        ++failures;
        std::printf("hil_flirone_hal: FAIL %s\n", what.c_str());
      }
    };
    if (!expected) throw std::runtime_error("the emulator never finished (no " + done + ")");
    std::uint64_t injected_losses = 0;
    for (std::size_t f = 0; f < expected->injected.size(); ++f)
      if (bolo::hil::fault_loses_frame(static_cast<bolo::hil::Fault>(f))) injected_losses += expected->injected[f];
    expect(sink.hashes.size() == expected->deliver.size(),
           "frames delivered: got " + std::to_string(sink.hashes.size()) + ", want " +
               std::to_string(expected->deliver.size()));
    for (std::size_t i = 0; i < std::min(sink.hashes.size(), expected->deliver.size()); ++i)
      if (sink.hashes[i] != expected->deliver[i].image_hash) {
        expect(false, "delivered image " + std::to_string(i) + " differs from emulator frame " +
                          std::to_string(expected->deliver[i].index));
        break;
      }
    const std::uint64_t counted = st.timeouts + st.short_transfers + st.corrupt_transfers + st.disconnects;
    expect(counted >= injected_losses, "faults counted " + std::to_string(counted) + " < injected " +
                                           std::to_string(injected_losses));
    expect(expected->refused_requests == 0, "the emulator refused " + std::to_string(expected->refused_requests) +
                                                " start-up requests (-1: not reported)");
    expect(sink.hashes.size() >= min_frames, "fewer than " + std::to_string(min_frames) + " frames");
    const std::uint64_t unplugs = expected->injected[static_cast<std::size_t>(bolo::hil::Fault::disconnect)];
    expect(st.disconnects == unplugs, "disconnects counted " + std::to_string(st.disconnects) + ", injected " +
                                          std::to_string(unplugs));
    // The emulator never skips a frame it numbered: every one missing from the telemetry counter
    // was lost on the wire and counted there. A jump right after an unplug is a new start instead.
    expect(source.skipped_in_camera() == 0,
           "frames skipped in the camera: " + std::to_string(source.skipped_in_camera()) + ", want 0");
    const std::uint64_t jumps = expected->injected[static_cast<std::size_t>(bolo::hil::Fault::frame_id_jump)];
    expect(source.counter_jumps() <= jumps && source.counter_jumps() + unplugs >= jumps,
           "counter jumps counted " + std::to_string(source.counter_jumps()) + ", injected " + std::to_string(jumps));
    expect(max_recovery_s <= 2.0, "replug recovery took " + std::to_string(max_recovery_s) + " s (> 2 s)");
    std::printf("hil_flirone_hal: %s: FlirOneSource delivered %zu frames in %.1f s (%.0f/s); emulator broke %llu "
                "frames, jumped its counter %llu times; source counted timeouts %llu short %llu corrupt %llu "
                "disconnects %llu (%llu fault returns), skipped in camera %llu, counter jumps %llu; "
                "max replug recovery %.3f s (of which at most: unplug seen %.3f s, reopened %.3f s)\n",
                failures == 0 ? "PASS" : "FAIL", sink.hashes.size(), seconds,
                static_cast<double>(sink.hashes.size()) / seconds,
                static_cast<unsigned long long>(injected_losses), static_cast<unsigned long long>(jumps),
                static_cast<unsigned long long>(st.timeouts), static_cast<unsigned long long>(st.short_transfers),
                static_cast<unsigned long long>(st.corrupt_transfers),
                static_cast<unsigned long long>(st.disconnects), static_cast<unsigned long long>(faults),
                static_cast<unsigned long long>(source.skipped_in_camera()),
                static_cast<unsigned long long>(source.counter_jumps()),
                max_recovery_s, max_detect_s, timed.max_reconnect_s);
    return failures == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::printf("hil_flirone_hal: FAIL %s\n", e.what());
    return 1;
  }
}

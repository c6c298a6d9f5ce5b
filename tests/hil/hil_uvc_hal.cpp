// HIL test through the project's V4L2 backend: bolo::hal::V4l2Source streaming from the
// PureThermal emulator (uvc_emulator) through the kernel's uvcvideo driver. Every delivered
// 160x120 image must equal, bit for bit and in order, a frame the emulator sent whole; with the
// 160x122 format its telemetry frame counter must be the one sent, and FFC events must appear
// exactly where the telemetry's FFC time changes. Faults must show in the source's counters:
// short frames as skipped sequence numbers (uvcvideo drops them), silences as timeouts,
// unplugs as disconnects with a reconnect each; with telemetry rows, frames the camera skipped
// (the silences: the counter steps over them, the driver's numbers do not) as skipped in the
// camera, and frames sent twice as duplicates.
//
//   hil_uvc_hal --send-log FILE --done FILE [--size 160x122|160x120] [--min-frames N]
//               [--buffers N] [--ffc-period N] [--lost-per-unplug N] [--progress FILE]
//   hil_uvc_hal --real [--device /dev/videoN] --frames N [--size ...] [--buffers N] [--progress FILE]
//
// --real: a camera without a send log (BOLO_HIL_DEVICE=v4l2:/dev/videoN): N frames, none dropped,
// corrupt or short, no disconnect, no timeout once streaming, no image twice in a row (a sensor's
// noise never repeats), and with telemetry rows every frame counter new, none skipped in the
// camera and no counter jump.
//
// --progress: the count of frames delivered so far, rewritten after each frame, for the
// emulator's --credit (it stays a bounded number of frames ahead of this program).

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "bolo/hal/v4l2_source.hpp"
#include "send_log.hpp"
#include "emulators/fnv1a.hpp"
#include "uvc_node.hpp"

namespace {

using namespace bolo;
using Clock = std::chrono::steady_clock;

bool exists(const std::string& path) {
  struct stat st {};
  return stat(path.c_str(), &st) == 0;
}

struct Received {
  std::uint64_t image_hash = 0;
  std::uint32_t counter = 0;
  bool ffc = false;
};

// Hashes the pushed lines as little-endian bytes (how the emulator hashed its image).
class HashingSink final : public fw::LineSink {
 public:
  void begin_frame(const fw::FrameHeader& header) override {
    hash_ = hil::kFnvOffset;
    ffc_ = header.ffc == fw::FfcState::completed;
  }
  void push_line(std::uint32_t, fw::LineView line) override {
    hash_ = hil::fnv1a_add_pixels_le(hash_, line);
  }
  void end_frame() override { frames.push_back({hash_, 0, ffc_}); }
  std::vector<Received> frames;

 private:
  std::uint64_t hash_ = 0;
  bool ffc_ = false;
};

// The --real check; see the top of the file.
int stream_real_camera(hal::V4l2Source& source, HashingSink& sink, bool telemetry, std::uint64_t frames,
                       int progress_fd) {
  const auto start = Clock::now();
  auto last_progress = start;
  std::optional<std::uint64_t> timeouts_at_first;
  while (sink.frames.size() < frames) {
    const std::size_t before = sink.frames.size();
    source.stream_frame(sink);
    if (sink.frames.size() == before) {
      if (Clock::now() - last_progress > std::chrono::seconds(15)) break;
      continue;
    }
    sink.frames.back().counter = source.last_telemetry().frame_counter;
    if (!timeouts_at_first) timeouts_at_first = source.stats().timeouts;
    last_progress = Clock::now();
    if (progress_fd >= 0) {
      const std::string text = std::to_string(sink.frames.size()) + "\n";
      if (::pwrite(progress_fd, text.data(), text.size(), 0) < 0) throw std::runtime_error("--progress: write failed");
    }
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const std::vector<Received>& got = sink.frames;
  std::uint64_t repeated = 0, reused_counters = 0;
  for (std::size_t i = 1; i < got.size(); ++i) repeated += got[i].image_hash == got[i - 1].image_hash ? 1 : 0;
  if (telemetry) {
    std::vector<std::uint32_t> counters;
    for (const Received& r : got) counters.push_back(r.counter);
    std::sort(counters.begin(), counters.end());
    reused_counters = static_cast<std::uint64_t>(counters.end() - std::unique(counters.begin(), counters.end()));
  }
  const hal::SourceStats st = source.stats();
  const std::uint64_t startup_timeouts = timeouts_at_first.value_or(st.timeouts);
  int failures = 0;
  auto expect = [&](bool ok, const std::string& what) {
    if (!ok) {
      ++failures;
      std::printf("hil_uvc_hal: FAIL %s\n", what.c_str());
    }
  };
  expect(got.size() == frames, "frames delivered: got " + std::to_string(got.size()) + ", want " +
                                   std::to_string(frames) + " (none for 15 s)");
  expect(st.dropped == 0, std::to_string(st.dropped) + " frames dropped (skipped sequence numbers)");
  expect(st.corrupt_transfers == 0 && st.short_transfers == 0,
         std::to_string(st.corrupt_transfers) + " corrupt, " + std::to_string(st.short_transfers) + " short frames");
  expect(st.disconnects == 0, std::to_string(st.disconnects) + " disconnects");
  expect(st.timeouts == startup_timeouts, std::to_string(st.timeouts - startup_timeouts) + " timeouts while streaming");
  expect(repeated == 0 && reused_counters == 0 && st.duplicates == 0,
         std::to_string(repeated) + " images repeated, " + std::to_string(reused_counters) +
             " frame counters reused (the source counted " + std::to_string(st.duplicates) + " duplicates)");
  expect(source.skipped_in_camera() == 0 && source.counter_jumps() == 0,
         std::to_string(source.skipped_in_camera()) + " frames skipped in the camera, " +
             std::to_string(source.counter_jumps()) + " frame counter jumps");
  std::printf("hil_uvc_hal: %s: real V4L2 camera, %zu frames in %.1f s (%.1f/s); out of order %llu, skipped in "
              "the camera %llu, duplicates %llu, counter jumps %llu, start-up timeouts %llu\n",
              failures == 0 ? "PASS" : "FAIL", got.size(), seconds, static_cast<double>(got.size()) / seconds,
              static_cast<unsigned long long>(source.out_of_order()),
              static_cast<unsigned long long>(source.skipped_in_camera()),
              static_cast<unsigned long long>(st.duplicates), static_cast<unsigned long long>(source.counter_jumps()),
              static_cast<unsigned long long>(startup_timeouts));
  return failures == 0 ? 0 : 1;
}

}  // namespace

// A whole non-negative number, or nothing (the caller names the option).
std::optional<std::uint64_t> number(const std::string& text) {
  std::size_t used = 0;
  try {
    const std::uint64_t v = std::stoull(text, &used);
    if (used == text.size() && text[0] != '-') return v;
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

int main(int argc, char** argv) {
  std::string send_log, done, progress, size = "160x122", device;
  std::uint64_t min_frames = 1, ffc_period = 0, lost_per_unplug = 0, real_frames = 0;
  bool real = false;
  std::uint32_t buffers = 4;
  for (int i = 1; i < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--real") {
      real = true;
      --i;  // no value
      continue;
    }
    if (i + 1 >= argc) {
      std::printf("hil_uvc_hal: FAIL %s needs a value\n", a.c_str());
      return 2;
    }
    const std::string v = argv[i + 1];
    std::uint64_t* numeric = a == "--min-frames" ? &min_frames : a == "--ffc-period" ? &ffc_period
                             : a == "--lost-per-unplug" ? &lost_per_unplug
                             : a == "--frames" ? &real_frames : nullptr;
    if (a == "--send-log") send_log = v;
    else if (a == "--done") done = v;
    else if (a == "--size") size = v;
    else if (a == "--progress") progress = v;
    else if (a == "--device") device = v;
    else if (numeric != nullptr || a == "--buffers") {
      const auto n = number(v);
      if (!n) {
        std::printf("hil_uvc_hal: FAIL %s: '%s' is not a whole number\n", a.c_str(), v.c_str());
        return 2;
      }
      if (numeric != nullptr) *numeric = *n;
      else buffers = static_cast<std::uint32_t>(std::min<std::uint64_t>(*n, 64));
    } else {
      std::printf("hil_uvc_hal: FAIL unknown option %s\n", a.c_str());
      return 2;
    }
  }
  if (real ? real_frames == 0 : (send_log.empty() || done.empty())) {
    std::printf("hil_uvc_hal: FAIL give --send-log and --done (emulator) or --real --frames N (camera)\n");
    return 2;
  }
  if (size != "160x122" && size != "160x120") {
    std::printf("hil_uvc_hal: FAIL --size must be 160x122 or 160x120, not %s\n", size.c_str());
    return 2;
  }
  const bool telemetry = size == "160x122";
  try {
    hal::V4l2Config config;
    config.path = device.empty() ? hil::find_uvc_node() : device;
    config.width = 160;
    config.height = 120;
    config.telemetry = telemetry ? hal::TelemetryRows::on : hal::TelemetryRows::off;
    config.buffers = buffers;
    hal::V4l2Source source(config);
    const hal::V4l2Negotiated& n = source.negotiated();
    std::printf("hil_uvc_hal: %s: %s (%s), %ux%u + %u telemetry rows, %u buffers\n", config.path.c_str(),
                n.card.c_str(), n.driver.c_str(), n.width, n.image_rows, n.telemetry_rows, n.buffers);
    HashingSink sink;
    const int progress_fd = progress.empty() ? -1 : ::open(progress.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (!progress.empty() && progress_fd < 0) throw std::runtime_error(progress + ": cannot create");
    if (real) return stream_real_camera(source, sink, telemetry, real_frames, progress_fd);
    const auto start = Clock::now();
    std::optional<bolo::hil::Expectation> expected;
    auto last_progress = Clock::now();
    std::uint64_t timeouts_before_last = 0;  // later ones: waiting for the emulator's done file
    std::uint64_t disconnects_seen = 0;
    double max_recovery = 0;  // s, from the last frame before an unplug to the first after it
    auto last_frame_at = Clock::now();
    for (;;) {
      const std::size_t before = sink.frames.size();
      source.stream_frame(sink);
      if (sink.frames.size() != before) {
        sink.frames.back().counter = source.last_telemetry().frame_counter;
        timeouts_before_last = source.stats().timeouts;
        const auto now = Clock::now();
        if (source.stats().disconnects != disconnects_seen && before > 0)  // time from the last frame before
          max_recovery = std::max(max_recovery, std::chrono::duration<double>(now - last_frame_at).count());
        disconnects_seen = source.stats().disconnects;
        last_frame_at = now;
        if (progress_fd >= 0) {
          const std::string text = std::to_string(sink.frames.size()) + "\n";
          if (::pwrite(progress_fd, text.data(), text.size(), 0) < 0) throw std::runtime_error(progress + ": write failed");
        }
        last_progress = Clock::now();
      } else if (Clock::now() - last_progress > std::chrono::seconds(15)) {
        std::printf("hil_uvc_hal: FAIL no frame for 15 s after %zu frames\n", sink.frames.size());
        break;
      }
      if (!expected && exists(done)) expected = bolo::hil::read_send_log(send_log);
      if (expected && sink.frames.size() >= expected->deliver.size()) break;
      // The emulator is through and nothing came for 3 s: what is missing is lost (the checks say).
      if (expected && Clock::now() - last_progress > std::chrono::seconds(3)) break;
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    if (!expected) throw std::runtime_error("the emulator never finished (no " + done + ")");
    int failures = 0;
    auto expect = [&](bool ok, const std::string& what) {
      if (!ok) {
        ++failures;
        std::printf("hil_uvc_hal: FAIL %s\n", what.c_str());
      }
    };
    using bolo::hil::Fault;
    auto injected = [&](Fault f) { return expected->injected[static_cast<std::size_t>(f)]; };
    const std::uint64_t unplugs = injected(Fault::disconnect);
    const std::vector<bolo::hil::SentFrame>& want = expected->deliver;
    const std::vector<Received>& got = sink.frames;
    // Bit-exact, each sent frame once, in order up to what uvcvideo swaps: it completes buffers
    // from copy work that runs in parallel (an unbound workqueue), and while one work item waits,
    // the other URBs go on completing frames (seen: 4 places late under load). A frame may come
    // up to kWindow places late, and the source must see it as late, not as a gap. An unplug may
    // cost the frames the host had not taken yet.
    constexpr std::size_t kWindow = 32;
    std::vector<bool> used(want.size(), false);
    std::size_t first = 0, late = 0, highest = 0;
    const std::size_t reach = kWindow + unplugs * lost_per_unplug;
    for (std::size_t g = 0; g < got.size(); ++g) {
      auto same = [&](std::size_t i) {
        return !used[i] && want[i].image_hash == got[g].image_hash && (!telemetry || want[i].counter == got[g].counter);
      };
      std::size_t j = first;
      while (j < want.size() && j < first + reach && !same(j)) ++j;
      if (j >= want.size() || j >= first + reach) {
        expect(false, "delivered frame " + std::to_string(g) + " (counter " + std::to_string(got[g].counter) +
                          ") is none of the emulator frames from " +
                          (first < want.size() ? std::to_string(want[first].index) : std::string("(none left)")) +
                          " on");
        std::string around;
        for (std::size_t k = g >= 8 ? g - 8 : 0; k < std::min(got.size(), g + 8); ++k)
          around.append(" ").append(std::to_string(got[k].counter));
        std::printf("hil_uvc_hal: counters delivered around it:%s\n", around.c_str());
        break;
      }
      used[j] = true;
      if (g > 0 && j < highest) ++late;  // behind a frame already delivered
      highest = std::max(highest, j);
      // Frames an unplug cost stay behind for good once the stream is a window past them.
      while (first < want.size() && (used[first] || (unplugs > 0 && first + kWindow < j))) ++first;
    }
    std::size_t missing = 0;
    for (bool u : used) missing += !u;
    expect(unplugs > 0 || expected->lost_by_emulator == 0,
           std::to_string(expected->lost_by_emulator) + " frames queued by the emulator were never taken");
    if (unplugs == 0)
      expect(missing == 0 && got.size() == want.size(), "frames delivered: got " + std::to_string(got.size()) + ", want " +
                                            std::to_string(want.size()));
    else
      expect(missing <= unplugs * lost_per_unplug, std::to_string(missing) + " frames lost to " +
                                                       std::to_string(unplugs) + " unplugs");
    expect(got.size() >= min_frames, "fewer than " + std::to_string(min_frames) + " frames");
    hal::SourceStats st = source.stats();
    st.timeouts = timeouts_before_last;
    const std::uint64_t shorts = injected(Fault::short_transfer);
    if (unplugs == 0)
      expect(st.dropped == shorts, "dropped (skipped sequence numbers) " + std::to_string(st.dropped) +
                                       ", short frames sent " + std::to_string(shorts));
    else
      expect(st.dropped >= shorts, "dropped " + std::to_string(st.dropped) + " < short frames " + std::to_string(shorts));
    expect(st.timeouts >= injected(Fault::timeout), "timeouts counted " + std::to_string(st.timeouts) + " < silences " +
                                                        std::to_string(injected(Fault::timeout)));
    if (injected(Fault::timeout) == 0) expect(st.timeouts == 0, "timeouts without a silence: " + std::to_string(st.timeouts));
    expect(max_recovery <= 2.0, "replug recovery " + std::to_string(max_recovery) + " s > 2 s");
    expect(st.disconnects == unplugs && st.reconnects == unplugs,
           "disconnects/reconnects " + std::to_string(st.disconnects) + "/" + std::to_string(st.reconnects) +
               ", unplugs " + std::to_string(unplugs));
    // An unplug fails the buffers uvcvideo had queued (error flag): counted corrupt then.
    expect((unplugs > 0 || st.corrupt_transfers == 0) && st.short_transfers == 0,
           "corrupt " + std::to_string(st.corrupt_transfers) + ", short " + std::to_string(st.short_transfers) +
               " (uvcvideo drops broken frames before the source sees them)");
    // (Across an unplug uvcvideo hands back failed buffers with old numbers: not compared then.
    // The two copies of a duplicate look the same: their swap is late by number only.)
    const std::uint64_t dups = injected(Fault::duplicate);
    if (unplugs == 0)
      expect(source.out_of_order() >= late && source.out_of_order() <= late + dups,
             "frames the source saw out of order " + std::to_string(source.out_of_order()) + ", late by content " +
                 std::to_string(late) + " (+ up to " + std::to_string(dups) + " swapped duplicates)");
    // The telemetry counter: a silence skips its frame inside the camera (the driver numbers
    // nothing for it; a short frame it drops is its own gap), a duplicate repeats the counter.
    // (A silence on the first or last frame would show no step; the scenario's plans have none.)
    const std::uint64_t silences = injected(Fault::timeout);
    if (telemetry && unplugs == 0) {
      expect(source.skipped_in_camera() == silences, "frames skipped in the camera " +
                                                         std::to_string(source.skipped_in_camera()) +
                                                         ", silences sent " + std::to_string(silences));
      expect(st.duplicates == dups, "duplicates counted " + std::to_string(st.duplicates) + ", sent " +
                                        std::to_string(dups));
      expect(source.counter_jumps() == 0, std::to_string(source.counter_jumps()) + " frame counter jumps");
    }
    std::uint64_t ffc_seen = 0, ffc_want = 0;
    if (telemetry && ffc_period > 0 && unplugs == 0) {
      auto stamp = [&](std::uint32_t counter) { return (counter - 1) / ffc_period; };
      for (std::size_t i = 0; i < got.size(); ++i) {
        const bool want_ffc = i > 0 && stamp(got[i].counter) != stamp(got[i - 1].counter);
        ffc_want += want_ffc;
        ffc_seen += got[i].ffc;
        if (got[i].ffc != want_ffc) {
          expect(false, "frame " + std::to_string(i) + ": FFC " + (got[i].ffc ? "reported" : "missed"));
          break;
        }
      }
    }
    std::printf("hil_uvc_hal: %s: V4l2Source delivered %zu frames in %.1f s (%.0f/s); sent %llu, broken %llu "
                "(short %llu, silent %llu, unplugs %llu), duplicates %llu, lost to unplugs %zu; counted dropped %llu "
                "timeouts %llu corrupt %llu disconnects %llu reconnects %llu (max recovery %.2f s); out of order %zu (uvcvideo); "
                "skipped in the camera %llu, duplicates %llu, counter jumps %llu; FFC %llu/%llu\n",
                failures == 0 ? "PASS" : "FAIL", got.size(), seconds, static_cast<double>(got.size()) / seconds,
                static_cast<unsigned long long>(expected->frames_sent),
                static_cast<unsigned long long>(shorts + injected(Fault::timeout) + unplugs),
                static_cast<unsigned long long>(shorts), static_cast<unsigned long long>(injected(Fault::timeout)),
                static_cast<unsigned long long>(unplugs), static_cast<unsigned long long>(injected(Fault::duplicate)),
                missing, static_cast<unsigned long long>(st.dropped), static_cast<unsigned long long>(st.timeouts),
                static_cast<unsigned long long>(st.corrupt_transfers), static_cast<unsigned long long>(st.disconnects),
                static_cast<unsigned long long>(st.reconnects), max_recovery, late,
                static_cast<unsigned long long>(source.skipped_in_camera()),
                static_cast<unsigned long long>(st.duplicates), static_cast<unsigned long long>(source.counter_jumps()),
                static_cast<unsigned long long>(ffc_seen), static_cast<unsigned long long>(ffc_want));
    return failures == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::printf("hil_uvc_hal: FAIL %s\n", e.what());
    return 1;
  }
}

// HIL test of the GPIO path through the project's libgpiod backend (GpiodLines) and the pipeline
// stage that uses it (GpioSyncedSource), on a gpio-sim chip inside the VM. This program is both
// sides: it drives the simulated inputs through gpio-sim's sysfs `pull` attributes (a frame-sync
// pulse before each frame, "FFC imminent" held over a range of frames) and reads the shutter
// output through the sim's `value` attribute while the backend pulses it.
//
//   hil_gpio --chip gpiochipN --sysfs /sys/bus/gpio/devices/gpiochipN [--frames N]
//
// Lines: 0 shutter/FFC trigger (output), 1 frame sync (input, rising edges), 2 FFC imminent
// (input). Checks, per frame: the sync edge the stage matched is the one this program made
// (its kernel timestamp lies between the CLOCK_MONOTONIC readings around the sysfs write; frames
// without a pulse match the previous edge), the latency is frame time - edge time, the
// FFC-imminent mark follows the input, and a requested shutter toggles the output line (seen
// high, then low, through sysfs) and marks exactly the next frame as an FFC frame.

#include <time.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "bolo/hal/gpio_lines.hpp"
#include "bolo/hal/gpio_synced_source.hpp"
#include "header_sink.hpp"

namespace {

using namespace bolo;

std::int64_t now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

void write_attr(const std::string& path, const char* text) {
  std::ofstream f(path);
  f << text;
  f.flush();
  if (!f) throw std::runtime_error(path + ": cannot write '" + text + "'");
}

std::string read_attr(const std::string& path) {
  std::ifstream f(path);
  std::string s;
  std::getline(f, s);
  if (!f) throw std::runtime_error(path + ": cannot read");
  return s;
}

// A 4x2 frame per call, stamped with CLOCK_MONOTONIC when it is pushed (as V4L2 stamps frames).
class TickSource final : public hal::FrameSource {
 public:
  hal::SourceFormat format() const override { return {4, 2, 16, hal::PixelUnits::counts, 0}; }
  hal::StreamStatus stream_frame(fw::LineSink& sink) override {
    fw::FrameHeader h;
    h.width = 4;
    h.height = 2;
    h.sequence = stats_.frames_delivered;
    h.sequence_valid = true;
    h.timestamp_ns = now_ns();
    h.timestamp_valid = true;
    sink.begin_frame(h);
    const fw::Pixel row[4] = {1, 2, 3, 4};
    for (std::uint32_t r = 0; r < 2; ++r) sink.push_line(r, fw::LineView(row, 4));
    sink.end_frame();
    ++stats_.frames_delivered;
    return hal::StreamStatus::frame;
  }
  hal::SourceStats stats() const override { return stats_; }

 private:
  hal::SourceStats stats_;
};

// Between the backend and the stage: edges are read from GpiodLines as soon as they can be read
// and handed to the stage when it drains. The kernel timestamps an edge at once (in the hard
// interrupt, on the sysfs write) but queues it from the interrupt thread a little later, so a
// frame pushed right after the write would not see it yet; waiting here for each edge makes the
// check exact (no edge lost, none extra) without guessing a delay.
class CollectingLines final : public hal::GpioLines {
 public:
  explicit CollectingLines(hal::GpioLines& inner) : inner_(inner) {}
  bool pulse_shutter() override { return inner_.pulse_shutter(); }
  bool ffc_imminent() override { return inner_.ffc_imminent(); }
  std::size_t drain_sync_edges(std::span<std::int64_t> out) override {
    collect();
    std::size_t n = 0;
    while (n < out.size() && taken_ < edges_.size()) out[n++] = edges_[taken_++];
    return n;
  }
  // Waits up to 2 s until `total` edges have arrived since the start; the time it took.
  bool wait_for(std::uint64_t total, std::int64_t& waited_ns) {
    const std::int64_t start = now_ns();
    for (;;) {
      collect();
      waited_ns = now_ns() - start;
      if (edges_.size() >= total) return true;
      if (waited_ns > 2'000'000'000) return false;
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
  }
  std::uint64_t received() const { return edges_.size(); }

 private:
  void collect() {
    std::int64_t batch[16];
    for (std::size_t n; (n = inner_.drain_sync_edges(batch)) > 0;) edges_.insert(edges_.end(), batch, batch + n);
  }
  hal::GpioLines& inner_;
  std::vector<std::int64_t> edges_;
  std::size_t taken_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  std::string chip, sysfs;
  int frames = 300;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--chip") chip = argv[i + 1];
    else if (a == "--sysfs") sysfs = argv[i + 1];
    else if (a == "--frames") frames = std::stoi(argv[i + 1]);
    else {
      std::printf("hil_gpio: FAIL unknown option %s\n", a.c_str());
      return 2;
    }
  }
  int failures = 0;
  auto expect = [&](bool ok, const std::string& what) {
    if (ok) return;
    if (++failures <= 10) std::printf("hil_gpio: FAIL %s\n", what.c_str());
  };
  try {
    const std::string shutter_value = sysfs + "/sim_gpio0/value";
    const std::string sync_pull = sysfs + "/sim_gpio1/pull";
    const std::string imminent_pull = sysfs + "/sim_gpio2/pull";
    write_attr(sync_pull, "pull-down");
    write_attr(imminent_pull, "pull-down");

    hal::GpioConfig config;
    config.chip = chip;
    config.shutter_line = 0;
    config.shutter_pulse_us = 30000;  // long enough to be seen by polling sysfs
    config.sync_line = 1;
    config.ffc_imminent_line = 2;
    hal::GpiodLines gpiod(config);
    CollectingLines gpio(gpiod);
    TickSource ticks;
    hal::GpioSyncedSource source(ticks, gpio);
    bolo::hil::HeaderSink sink;
    expect(read_attr(shutter_value) == "0", "shutter line not low after the request");

    const int imminent_from = frames / 3, imminent_to = frames / 3 + 10;
    std::int64_t last_edge_lo = 0, last_edge_hi = 0;
    std::uint64_t edges_made = 0, shutters = 0, ffc_frames = 0, imminent_frames = 0;
    bool shutter_requested = false;
    std::int64_t max_latency = 0, max_delivery = 0;
    for (int i = 0; i < frames; ++i) {
      // Every 7th frame comes without a sync pulse: it must match the previous edge.
      if (i % 7 != 3) {
        const std::int64_t lo = now_ns();
        write_attr(sync_pull, "pull-up");
        const std::int64_t hi = now_ns();
        write_attr(sync_pull, "pull-down");
        last_edge_lo = lo;
        last_edge_hi = hi;
        ++edges_made;
        std::int64_t waited = 0;
        expect(gpio.wait_for(edges_made, waited), "frame " + std::to_string(i) + ": sync edge " +
                                                       std::to_string(edges_made) + " not readable within 2 s");
        if (waited > max_delivery) max_delivery = waited;
      }
      const bool imminent = i >= imminent_from && i < imminent_to;
      write_attr(imminent_pull, imminent ? "pull-up" : "pull-down");
      if (imminent) ++imminent_frames;

      if (source.stream_frame(sink) != hal::StreamStatus::frame) {
        expect(false, "frame " + std::to_string(i) + " not delivered");
        continue;
      }
      const hal::GpioFrameMarks& m = source.last_marks();
      const std::string at = "frame " + std::to_string(i) + ": ";
      if (edges_made == 0) {
        expect(!m.sync_matched, at + "matched a sync edge before any was made");
      } else {
        expect(m.sync_matched, at + "no sync edge matched");
        expect(m.sync_ns >= last_edge_lo && m.sync_ns <= last_edge_hi,
               at + "sync edge at " + std::to_string(m.sync_ns) + " ns, made between " +
                   std::to_string(last_edge_lo) + " and " + std::to_string(last_edge_hi));
        expect(m.latency_ns == sink.header.timestamp_ns - m.sync_ns && m.latency_ns >= 0,
               at + "latency " + std::to_string(m.latency_ns) + " ns");
        if (m.latency_ns > max_latency) max_latency = m.latency_ns;
      }
      expect(m.ffc_imminent == imminent, at + "FFC imminent mark " + std::to_string(m.ffc_imminent) +
                                             ", input " + std::to_string(imminent));
      const bool ffc = sink.header.ffc == fw::FfcState::completed;
      expect(m.after_shutter == shutter_requested && ffc == shutter_requested,
             at + "FFC frame " + std::to_string(ffc) + ", shutter requested " + std::to_string(shutter_requested));
      if (ffc) ++ffc_frames;
      shutter_requested = false;

      if (i % 50 == 25) {  // a shutter pulse, watched on the sim's side of the output line
        std::atomic<bool> stop{false}, seen_high{false};
        std::thread watch([&] {
          while (!stop)
            if (read_attr(shutter_value) == "1") seen_high = true;
        });
        const bool ok = source.request_shutter();
        stop = true;
        watch.join();
        expect(ok, at + "request_shutter failed");
        expect(seen_high, at + "the shutter line was never seen high through sysfs");
        expect(read_attr(shutter_value) == "0", at + "the shutter line stayed high after the pulse");
        shutter_requested = ok;
        ++shutters;
      }
    }
    expect(source.imminent_frames() == imminent_frames,
           "imminent frames counted " + std::to_string(source.imminent_frames()) + ", held " +
               std::to_string(imminent_frames));
    expect(ffc_frames == shutters, "FFC frames " + std::to_string(ffc_frames) + ", shutter pulses " +
                                       std::to_string(shutters));
    expect(gpio.received() == edges_made, "edges read " + std::to_string(gpio.received()) + ", made " +
                                              std::to_string(edges_made));
    expect(source.unmatched_frames() == 0, std::to_string(source.unmatched_frames()) + " frames without a sync edge");
    std::printf("hil_gpio: %s: %d frames through GpioSyncedSource, %llu sync edges made (every one matched to "
                "its frame, latency mean %.1f us, max %.1f us; readable after at most %.1f ms), %llu shutter pulses seen high then low on "
                "line 0 (%llu FFC frames), FFC imminent on %llu frames; %d failures\n",
                failures == 0 ? "PASS" : "FAIL", frames, static_cast<unsigned long long>(edges_made),
                static_cast<double>(source.latency().mean_ns()) / 1e3, static_cast<double>(max_latency) / 1e3,
                static_cast<double>(max_delivery) / 1e6,
                static_cast<unsigned long long>(shutters), static_cast<unsigned long long>(ffc_frames),
                static_cast<unsigned long long>(source.imminent_frames()), failures);
    return failures == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::printf("hil_gpio: FAIL %s\n", e.what());
    return 1;
  }
}

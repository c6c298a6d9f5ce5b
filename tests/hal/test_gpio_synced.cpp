// GpioSyncedSource: frames matched to their sync edges (latency), FFC-imminent marks, a
// requested shutter marks the next frame as an FFC frame; lines driven through the GpioLines seam.

#include <catch2/catch.hpp>

#include <deque>
#include <vector>

#include "../firmware/frame_collector.hpp"
#include "bolo/hal/gpio_synced_source.hpp"

using namespace bolo;

namespace {

class FakeLines final : public hal::GpioLines {
 public:
  bool pulse_shutter() override {
    ++pulses;
    return shutter_ok;
  }
  bool ffc_imminent() override { return imminent; }
  std::size_t drain_sync_edges(std::span<std::int64_t> out) override {
    std::size_t n = 0;
    while (n < out.size() && !pending.empty()) {
      out[n++] = pending.front();
      pending.pop_front();
    }
    return n;
  }
  std::deque<std::int64_t> pending;
  bool imminent = false, shutter_ok = true;
  int pulses = 0;
};

// Frames with the given timestamps (4x2 pixels), then the end.
class TimedFrames final : public hal::FrameSource {
 public:
  explicit TimedFrames(std::vector<std::int64_t> t) : times(std::move(t)) {}
  hal::SourceFormat format() const override { return {4, 2, 16, hal::PixelUnits::counts, 0}; }
  hal::StreamStatus stream_frame(fw::LineSink& sink) override {
    if (next >= times.size()) return hal::StreamStatus::end_of_stream;
    fw::FrameHeader h;
    h.width = 4;
    h.height = 2;
    h.sequence = next;
    h.sequence_valid = true;
    h.timestamp_ns = times[next++];
    h.timestamp_valid = true;
    h.ffc = fw::FfcState::none;
    const fw::Pixel line[4] = {1, 2, 3, 4};
    sink.begin_frame(h);
    sink.push_line(0, line);
    sink.push_line(1, line);
    sink.end_frame();
    return hal::StreamStatus::frame;
  }
  hal::SourceStats stats() const override { return {}; }
  hal::ExtraCounters extra_counters() const override {
    hal::ExtraCounters c;
    c.add("counter_jumps", 4);
    return c;
  }
  std::vector<std::int64_t> times;
  std::size_t next = 0;
};

}  // namespace

TEST_CASE("gpio: latency from the latest sync edge before each frame", "[hal][gpio]") {
  FakeLines lines;
  TimedFrames frames({1'005'000, 2'007'000, 3'004'000, 3'500'000});
  hal::GpioSyncedSource source(frames, lines);
  test::HashingCollector sink(4, 2);
  lines.pending = {1'000'000, 2'000'000, 2'100'000'000};  // the last one is after every frame
  REQUIRE(source.stream_frame(sink) == hal::StreamStatus::frame);
  CHECK(source.last_marks().latency_ns == 5'000);
  REQUIRE(source.stream_frame(sink) == hal::StreamStatus::frame);
  CHECK(source.last_marks().sync_ns == 2'000'000);
  CHECK(source.last_marks().latency_ns == 7'000);
  lines.pending = {3'000'000};
  REQUIRE(source.stream_frame(sink) == hal::StreamStatus::frame);
  CHECK(source.last_marks().latency_ns == 4'000);
  CHECK(source.latency().count == 3);
  CHECK(source.latency().min_ns == 4'000);
  CHECK(source.latency().max_ns == 7'000);
  CHECK(source.latency().mean_ns() == 5'333);
  REQUIRE(source.stream_frame(sink) == hal::StreamStatus::frame);  // no new edge: reuses 3.0 ms
  CHECK(source.last_marks().latency_ns == 500'000);
  CHECK(source.stream_frame(sink) == hal::StreamStatus::end_of_stream);
}

TEST_CASE("gpio: frames with no edge before them are counted unmatched", "[hal][gpio]") {
  FakeLines lines;
  TimedFrames frames({10, 20});
  hal::GpioSyncedSource source(frames, lines);
  test::HashingCollector sink(4, 2);
  lines.pending = {15};
  REQUIRE(source.stream_frame(sink) == hal::StreamStatus::frame);
  CHECK_FALSE(source.last_marks().sync_matched);
  REQUIRE(source.stream_frame(sink) == hal::StreamStatus::frame);
  CHECK(source.last_marks().latency_ns == 5);
  CHECK(source.unmatched_frames() == 1);
}

TEST_CASE("gpio: extra counters are the inner source's, then the GPIO ones", "[hal][gpio]") {
  FakeLines lines;
  TimedFrames frames({10, 20});
  hal::GpioSyncedSource source(frames, lines);
  test::HashingCollector sink(4, 2);
  lines.imminent = true;
  REQUIRE(source.stream_frame(sink) == hal::StreamStatus::frame);
  const hal::ExtraCounters extra = source.extra_counters();
  REQUIRE(extra.items().size() == 3);
  CHECK(extra.items()[0].name == "counter_jumps");
  CHECK(extra.items()[0].value == 4);
  CHECK(extra.items()[1].name == "ffc_imminent_frames");
  CHECK(extra.items()[1].value == 1);
  CHECK(extra.items()[2].name == "sync_unmatched_frames");
  CHECK(extra.items()[2].value == 1);
}

TEST_CASE("gpio: shutter on request marks the next frame, FFC-imminent frames are marked in the header", "[hal][gpio]") {
  FakeLines lines;
  TimedFrames frames({1, 2, 3, 4});
  hal::GpioSyncedSource source(frames, lines);
  test::HashingCollector sink(4, 2);
  REQUIRE(source.stream_frame(sink) == hal::StreamStatus::frame);
  CHECK(sink.header().ffc == fw::FfcState::none);
  lines.imminent = true;
  REQUIRE(source.stream_frame(sink) == hal::StreamStatus::frame);
  CHECK(source.last_marks().ffc_imminent);
  CHECK(sink.header().ffc == fw::FfcState::imminent);  // into the header, as a core's telemetry would put it
  CHECK(source.request_shutter());
  lines.imminent = false;
  REQUIRE(source.stream_frame(sink) == hal::StreamStatus::frame);
  CHECK(sink.header().ffc == fw::FfcState::completed);
  CHECK(source.last_marks().after_shutter);
  lines.shutter_ok = false;
  CHECK_FALSE(source.request_shutter());
  REQUIRE(source.stream_frame(sink) == hal::StreamStatus::frame);
  CHECK(sink.header().ffc == fw::FfcState::none);  // a failed pulse marks nothing
  CHECK(source.imminent_frames() == 1);
  CHECK(lines.pulses == 2);
}

// SeekFrameParser and SeekSource against a scripted Seek device: start-up sequence, frame types,
// dead-pixel map from the start-up frame, shutter frames as FFC events, faults counted.

#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "../firmware/frame_collector.hpp"
#include "bolo/hal/seek_source.hpp"
#include "seek_device.hpp"

using namespace bolo;
using hal::SeekFrameKind;

TEST_CASE("seek parser: frame types, counter, dead pixels for both models", "[hal][seek]") {
  for (const hal::SeekModel& m : {hal::kSeekCompact, hal::kSeekCompactPro}) {
    INFO(m.name);
    hal::SeekFrameParser p(m);
    const auto startup = test::make_seek_frame(m, 4, 7, 2000, {0, 5, 999, m.width * m.image_height() - 1});
    hal::SeekFrameInfo info;
    REQUIRE(p.parse(startup, info));
    CHECK(info.kind == SeekFrameKind::startup);
    CHECK(info.counter == 7);
    CHECK(info.dead_pixels == 4);
    CHECK(p.dead_map_count() == 4);
    CHECK(p.dead_map()[5] == 1);
    CHECK(p.dead_map()[6] == 0);
    CHECK(p.dead_map().back() == 1);
    // An image frame counts its dead pixels but leaves the map alone.
    REQUIRE(p.parse(test::make_seek_frame(m, 3, 8, 2000, {1}), info));
    CHECK(info.kind == SeekFrameKind::image);
    CHECK(info.dead_pixels == 1);
    CHECK(p.dead_map_count() == 4);
    CHECK(p.image_row(0).size() == m.width);
    CHECK_FALSE(p.parse(std::span<const std::uint8_t>(startup).first(startup.size() - 2), info));
  }
  CHECK(hal::seek_frame_kind(1) == SeekFrameKind::shutter);
  CHECK(hal::seek_frame_kind(6) == SeekFrameKind::before_calibration);
  CHECK(hal::seek_frame_kind(20) == SeekFrameKind::after_calibration);
  CHECK(hal::seek_frame_kind(8) == SeekFrameKind::startup_calibration);
  CHECK(hal::seek_frame_kind(7) == SeekFrameKind::startup_calibration);
  CHECK(hal::seek_frame_kind(25) == SeekFrameKind::other);
  for (std::uint16_t t : {1, 3, 4, 6, 7, 8, 9, 14, 20, 25, 26, 27, 28}) CHECK(hal::seek_frame_type_known(t));
  for (std::uint16_t t : {0, 2, 5, 10, 29, 1003, 8000, 0xFFFF}) CHECK_FALSE(hal::seek_frame_type_known(t));
}

TEST_CASE("seek parser: chunks assemble a frame, a zero-length or overlong read gives it up", "[hal][seek]") {
  const hal::SeekModel m = hal::kSeekCompact;
  hal::SeekFrameParser p(m);
  const auto frame = test::make_seek_frame(m, 3, 1);
  p.begin();
  CHECK(p.add_chunk({frame.data(), 16224}) == hal::SeekChunk::need_more);
  CHECK(p.add_chunk({frame.data() + 16224, 16224 * 3}) == hal::SeekChunk::complete);
  hal::SeekFrameInfo info;
  CHECK(p.parse_received(info));
  p.begin();
  CHECK(p.add_chunk({}) == hal::SeekChunk::aborted);
  CHECK(p.add_chunk({frame.data(), 16224}) == hal::SeekChunk::need_more);
  std::vector<std::uint8_t> big(frame.size(), 0);
  CHECK(p.add_chunk(big) == hal::SeekChunk::overflow);
  CHECK(p.received() == 0);
}

TEST_CASE("seek source: boot frames consumed, dead map taken, shutter frames mark the next image", "[hal][seek]") {
  for (const hal::SeekModel& m : {hal::kSeekCompact, hal::kSeekCompactPro}) {
    INFO(m.name);
    test::FakeSeek cam(m);
    for (std::uint16_t t : {4, 9, 14, 25, 26, 27, 28, 8, 7, 6, 1, 20, 3, 3, 6, 1, 20, 3})
      cam.plan.push_back({t});
    cam.dead_in_startup = {3, 11, 20};  // clear of the Compact's metadata words 10 and 40
    {
      hal::SeekSource source(cam, m);
      CHECK(source.format().width == m.width);
      CHECK(source.format().height == m.image_height());
      test::HashingCollector sink(m.width, m.image_height());
      std::vector<fw::FfcState> ffc;
      for (int i = 0; i < 4; ++i) {
        REQUIRE(source.stream_frame(sink) == hal::StreamStatus::frame);
        ffc.push_back(sink.header().ffc);
        CHECK(sink.header().sequence == static_cast<std::uint64_t>(i));
        CHECK(sink.lines() == m.image_height());
      }
      CHECK(ffc == std::vector<fw::FfcState>{fw::FfcState::completed, fw::FfcState::none,
                                            fw::FfcState::completed, fw::FfcState::none});
      CHECK(source.counters().shutter_frames == 2);
      CHECK(source.counters().startup_frames == 1);
      CHECK(source.dead_pixels() == 3);
      CHECK(source.dead_map()[11] == 1);
      CHECK(cam.requested_pixels == m.pixels());
      CHECK(source.stats().frames_delivered == 4);
      // Start-up sequence as the facts doc orders it.
      const std::vector<std::uint8_t> start(cam.log.begin(), cam.log.begin() + 6);
      CHECK(start == std::vector<std::uint8_t>{84, 60, 78, 54, 62, 60});
    }
    CHECK(cam.log.back() == hal::seek::kSetOperationMode);  // closed on destruction
  }
}

TEST_CASE("seek source: a failed first write is retried after a close", "[hal][seek]") {
  test::FakeSeek cam(hal::kSeekCompact);
  cam.fail_first_write = true;
  hal::SeekSource source(cam, hal::kSeekCompact);
  test::HashingCollector sink(208, 156);
  CHECK(source.stream_frame(sink) == hal::StreamStatus::frame);
  const std::vector<std::uint8_t> start(cam.log.begin(), cam.log.begin() + 3);
  CHECK(start == std::vector<std::uint8_t>{84, 60, 84});
}

TEST_CASE("seek source: zero-length reads, timeouts, errors and an unplug are counted and survived", "[hal][seek]") {
  using F = test::FakeSeek::Fault;
  const hal::SeekModel m = hal::kSeekCompact;
  test::FakeSeek cam(m);
  cam.plan = {{3}, {3, F::zero_length}, {3}, {3, F::timeout}, {3, F::error}, {3}, {3, F::unplug}, {3}, {3}};
  hal::SeekSource source(cam, m);
  test::HashingCollector sink(m.width, m.height);
  using S = hal::StreamStatus;
  std::vector<S> statuses;
  std::vector<std::uint64_t> seq;
  for (int i = 0; i < 10; ++i) {
    statuses.push_back(source.stream_frame(sink));
    if (statuses.back() == S::frame) seq.push_back(sink.header().sequence);
  }
  // The abandoned frame (F::timeout: silent until asked again) is awaited over two timeouts,
  // then given up: two faults.
  CHECK(statuses == std::vector<S>{S::frame, S::fault, S::frame, S::fault, S::fault, S::fault, S::frame,
                                   S::fault, S::frame, S::frame});
  CHECK(seq == std::vector<std::uint64_t>{0, 2, 5, 7, 8});
  const hal::SourceStats st = source.stats();
  CHECK(st.short_transfers == 2);  // the zero-length read, and the frame abandoned after its first chunk
  CHECK(st.timeouts == 2);
  CHECK(st.corrupt_transfers == 1);
  CHECK(st.disconnects == 1);
  CHECK(st.reconnects == 1);
  CHECK(st.frames_delivered == 5);
  // The lost frames' counters were skipped: one gap after the zero-length read, one of two after
  // the timeout and the error; the unplug restarts the count.
  CHECK(st.dropped == 3);
  CHECK(source.counters().counter_jumps == 2);
  CHECK(st.duplicates == 0);
  // After the replug the start-up sequence ran again.
  CHECK(std::count(cam.log.begin(), cam.log.end(), std::uint8_t{84}) == 2);
}

TEST_CASE("seek source: a pause mid-frame is a counted timeout, not a lost frame", "[hal][seek]") {
  using F = test::FakeSeek::Fault;
  using S = hal::StreamStatus;
  const hal::SeekModel m = hal::kSeekCompact;
  test::FakeSeek cam(m);
  cam.plan = {{3}, {3, F::pause}, {3}};  // frame 2 stops after its first chunk, then goes on
  hal::SeekSource source(cam, m);
  test::HashingCollector sink(m.width, m.height);
  std::vector<S> statuses;
  std::vector<std::uint64_t> seq;
  for (int i = 0; i < 4; ++i) {
    statuses.push_back(source.stream_frame(sink));
    if (statuses.back() != S::frame) continue;
    seq.push_back(sink.header().sequence);
    // Each frame whole and its own: pixel i = 1000 + counter + i % 1000 (test::FakeSeek).
    const std::uint16_t base = static_cast<std::uint16_t>(1000 + seq.size());
    CHECK(sink.frame()[1] == base + 1);
    CHECK(sink.frame().back() == base + (m.pixels() - 1) % 1000);
  }
  CHECK(statuses == std::vector<S>{S::frame, S::fault, S::frame, S::frame});
  CHECK(seq == std::vector<std::uint64_t>{0, 1, 2});  // nothing was lost: no gap
  const hal::SourceStats st = source.stats();
  CHECK(st.timeouts == 1);
  CHECK(st.short_transfers == 0);
  CHECK(st.dropped == 0);
  CHECK(source.counters().counter_jumps == 0);
  // The paused frame was read on, not asked for again.
  CHECK(std::count(cam.log.begin(), cam.log.end(), std::uint8_t{hal::seek::kStartGetImageTransfer}) == 3);
}

TEST_CASE("seek source: a request the camera never answers costs timeouts, not a short frame", "[hal][seek]") {
  using S = hal::StreamStatus;
  test::FakeSeek cam(hal::kSeekCompact);
  cam.unanswered_requests = 1;  // e.g. still booting
  hal::SeekSource source(cam, hal::kSeekCompact);
  test::HashingCollector sink(208, 156);
  std::vector<S> statuses;
  for (int i = 0; i < 3; ++i) statuses.push_back(source.stream_frame(sink));
  CHECK(statuses == std::vector<S>{S::fault, S::fault, S::frame});
  CHECK(source.stats().timeouts == 2);
  CHECK(source.stats().short_transfers == 0);
  CHECK(sink.header().sequence == 1);  // the unanswered request leaves a gap all the same
}

TEST_CASE("seek source: the rest of a frame given up on is never delivered as part of the next", "[hal][seek]") {
  using F = test::FakeSeek::Fault;
  using S = hal::StreamStatus;
  const hal::SeekModel m = hal::kSeekCompact;
  test::FakeSeek cam(m);
  cam.pause_timeouts = 3;  // longer than the source waits (2 timeouts): frame 2 is given up...
  cam.plan = {{3}, {3, F::pause}, {3}, {3}, {3}};  // ...and its rest then comes before frame 3
  hal::SeekSource source(cam, m);
  test::HashingCollector sink(m.width, m.height);
  std::vector<S> statuses;
  std::vector<std::uint16_t> counters;  // of the frames delivered, from their pixels
  for (int i = 0; i < 7; ++i) {
    statuses.push_back(source.stream_frame(sink));
    if (statuses.back() != S::frame) continue;
    const auto counter = static_cast<std::uint16_t>(sink.frame()[1] - 1001);
    counters.push_back(counter);
    CHECK(sink.frame().back() == 1000 + counter + (m.pixels() - 1) % 1000);  // whole, not mixed
  }
  // Frame 2's rest + frame 3's first chunk begin mid-frame (pixels where the type word is): that
  // "frame" is refused, frame 3's rest drained, and frame 4 asked for afresh.
  CHECK(statuses == std::vector<S>{S::frame, S::fault, S::fault, S::fault, S::fault, S::frame, S::frame});
  CHECK(counters == std::vector<std::uint16_t>{1, 4, 5});
  const hal::SourceStats st = source.stats();
  CHECK(st.timeouts == 3);
  CHECK(st.short_transfers == 1);    // frame 2, given up
  CHECK(st.corrupt_transfers == 1);  // the stale chunks with frame 3's start
  CHECK(source.counters().calibration_frames == 0);  // not taken for some other frame type
}

TEST_CASE("seek source: a camera that never sends an image gives faults, not a hang", "[hal][seek]") {
  test::FakeSeek cam(hal::kSeekCompact);
  for (int i = 0; i < 200; ++i) cam.plan.push_back({6});
  hal::SeekSource source(cam, hal::kSeekCompact, {.max_frames_without_image = 16});
  test::HashingCollector sink(208, 156);
  CHECK(source.stream_frame(sink) == hal::StreamStatus::fault);
  CHECK(source.counters().calibration_frames == 16);
}

TEST_CASE("seek source: a refused start-up is a counted fault, an unplugged camera a disconnect", "[hal][seek]") {
  test::FakeSeek cam(hal::kSeekCompact);
  cam.unplugged = true;
  cam.replug = false;
  hal::SeekSource source(cam, hal::kSeekCompact);
  test::HashingCollector sink(208, 156);
  CHECK(source.stream_frame(sink) == hal::StreamStatus::fault);
  CHECK(source.stats().disconnects == 1);
  CHECK(cam.reconnects == 1);
  cam.unplugged = false;
  cam.fail_first_write = true;  // fails once: the retry inside start() succeeds
  CHECK(source.stream_frame(sink) == hal::StreamStatus::frame);
  CHECK(source.counters().start_failures == 1);
}

TEST_CASE("seek source: the frame counter shows duplicates, gaps and surprises", "[hal][seek]") {
  const hal::SeekModel m = hal::kSeekCompact;
  test::FakeSeek cam(m);
  // Image counters 1, 2, 2 (a duplicate), 5 (two lost), 1005 (a surprise), 1006; then a shutter
  // cycle whose frames count too, and an image right after it.
  cam.plan = {{3}, {3}, {3, {}, 0}, {3, {}, 3}, {3, {}, 1000}, {3}, {6}, {1}, {20}, {3}};
  hal::SeekSource source(cam, m);
  test::HashingCollector sink(m.width, m.height);
  std::vector<std::uint64_t> seq;
  for (int i = 0; i < 7; ++i) {
    REQUIRE(source.stream_frame(sink) == hal::StreamStatus::frame);
    seq.push_back(sink.header().sequence);
  }
  CHECK(seq == std::vector<std::uint64_t>{0, 1, 2, 3, 4, 5, 6});  // duplicates are delivered
  const hal::SourceStats st = source.stats();
  CHECK(st.duplicates == 1);
  CHECK(st.dropped == 2);  // the surprise of 999 is not counted as losses
  CHECK(source.counters().counter_jumps == 2);
  CHECK(source.counters().shutter_frames == 1);
  // The same counters by name, as `bolo capture` reports them.
  const hal::ExtraCounters extra = source.extra_counters();
  std::vector<std::string> names;
  for (const hal::NamedCounter& c : extra.items()) names.emplace_back(c.name);
  CHECK(names == std::vector<std::string>{"shutter_frames", "calibration_frames", "startup_frames",
                                          "start_failures", "counter_jumps"});
  CHECK(extra.find("counter_jumps")->value == 2);
  CHECK(extra.find("shutter_frames")->value == 1);
}

// SeekFrameParser, SeekImageCorrector and SeekSource against a scripted Seek device that demands
// the public driver's start-up sequence: the sequence for both models, frame types, the shutter
// subtraction checked against images computed here from the raw frames sent, the crop, the
// dead-pixel rule, shutter frames as FFC events, faults counted.

#include <catch2/catch.hpp>

#include <algorithm>
#include <string>
#include <vector>

#include "../firmware/frame_collector.hpp"
#include "bolo/hal/seek_source.hpp"
#include "seek_device.hpp"

using namespace bolo;
using hal::SeekFrameKind;

TEST_CASE("seek parser: frame types and counter for both models", "[hal][seek]") {
  for (const hal::SeekModel& m : {hal::kSeekCompact, hal::kSeekCompactPro}) {
    INFO(m.name);
    hal::SeekFrameParser p(m);
    const auto startup = test::make_seek_frame(m, 4, 7);
    hal::SeekFrameInfo info;
    REQUIRE(p.parse(startup, info));
    CHECK(info.kind == SeekFrameKind::startup);
    CHECK(info.counter == 7);
    REQUIRE(p.parse(test::make_seek_frame(m, 3, 8), info));
    CHECK(info.kind == SeekFrameKind::image);
    CHECK(p.words().size() == m.pixels());
    CHECK(p.words()[m.type_word] == 3);
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

namespace {

// The first `n` images a source delivers, each as its pixels (row by row).
std::vector<std::vector<fw::Pixel>> stream_images(hal::SeekSource& source, std::size_t n) {
  const hal::SourceFormat f = source.format();
  test::HashingCollector sink(f.width, f.height);
  std::vector<std::vector<fw::Pixel>> out;
  for (std::size_t calls = 0; out.size() < n && calls < 4 * n + 8; ++calls)
    if (source.stream_frame(sink) == hal::StreamStatus::frame) out.push_back(sink.frame());
  return out;
}

// How many delivered images equal clamp(0x4000 + image - shutter) of the raw frames the device
// sent (the latest shutter frame before each image), computed here.
std::size_t images_matching_subtraction(const test::FakeSeek& cam, const std::vector<std::vector<fw::Pixel>>& got) {
  const auto sent = cam.images_with_shutter();
  std::size_t matching = 0;
  for (std::size_t i = 0; i < got.size() && i < sent.size(); ++i) {
    if (sent[i].second == nullptr) continue;
    const auto want = test::expected_seek_image(cam.model, sent[i].first->words, sent[i].second->words);
    matching += std::equal(want.begin(), want.end(), got[i].begin(), got[i].end()) ? 1 : 0;
  }
  return matching;
}

// The counter of the image sent whose subtraction equals `frame`; -1 for none.
int sent_image_counter(const test::FakeSeek& cam, const std::vector<fw::Pixel>& frame) {
  for (const auto& [image, shutter] : cam.images_with_shutter()) {
    if (shutter == nullptr) continue;
    const auto want = test::expected_seek_image(cam.model, image->words, shutter->words);
    if (std::equal(want.begin(), want.end(), frame.begin(), frame.end())) return image->words[cam.model.counter_word];
  }
  return -1;
}

}  // namespace

TEST_CASE("seek source: sends the public driver's start-up sequence, exactly, for both models", "[hal][seek]") {
  for (const hal::SeekModel& m : {hal::kSeekCompact, hal::kSeekCompactPro}) {
    INFO(m.name);
    test::FakeSeek cam(m);
    {
      hal::SeekSource source(cam, m);
      test::HashingCollector sink(source.format().width, source.format().height);
      REQUIRE(source.stream_frame(sink) == hal::StreamStatus::frame);
      CHECK(cam.refused == 0);
      // Every request before the first frame request, in order, is the device's list.
      const auto first_frame = std::find(cam.log.begin(), cam.log.end(), std::uint8_t{83});
      std::vector<std::uint8_t> want;
      for (const test::ExpectedRequest& r : cam.startup) want.push_back(r.request);
      CHECK(std::vector<std::uint8_t>(cam.log.begin(), first_frame) == want);
      CHECK(want.size() == (m.product_id == 0x0010 ? 17u : 176u));
      CHECK(source.counters().startup_frames == 1);
      CHECK(cam.requested_pixels == m.pixels());
      cam.log.clear();
    }
    // Closed on destruction: SET_OPERATION_MODE [00 00] three times.
    CHECK(cam.log == std::vector<std::uint8_t>{60, 60, 60});
    CHECK(cam.refused == 0);
  }
}

TEST_CASE("seek device: a start-up out of order or with a wrong payload is refused and counted", "[hal][seek]") {
  const hal::SeekModel m = hal::kSeekCompact;
  using S = hal::TransferStatus;
  const std::uint8_t platform[] = {1}, idle[] = {0, 0}, count[] = {0xC0, 0x7E, 0, 0};
  std::uint8_t reply[12] = {};
  test::FakeSeek cam(m);
  CHECK(cam.control_out(83, count).status == S::error);  // a frame before the sequence
  CHECK(cam.control_out(84, platform).status == S::ok);
  CHECK(cam.control_out(60, idle).status == S::ok);
  CHECK(cam.control_in(54, reply).status == S::error);  // READ_CHIP_ID before GET_FIRMWARE_INFO
  CHECK(cam.control_in(78, std::span<std::uint8_t>(reply, 4)).status == S::ok);
  CHECK(cam.control_in(54, reply).status == S::ok);
  const std::uint8_t wrong[] = {0x20, 0x00, 0x31, 0x00, 0x00, 0x00};
  CHECK(cam.control_out(86, wrong).status == S::error);  // a wrong factory-settings address
  CHECK(cam.refused == 3);
  CHECK_FALSE(cam.running);
}

TEST_CASE("seek source: a device with another sequence refuses the source's start-up", "[hal][seek]") {
  test::FakeSeek cam(hal::kSeekCompact);
  cam.startup = test::expected_seek_startup(hal::kSeekCompactPro);  // the Pro's list for a Compact
  hal::SeekSource source(cam, hal::kSeekCompact);
  test::HashingCollector sink(207, 154);
  CHECK(source.stream_frame(sink) == hal::StreamStatus::fault);
  CHECK(cam.refused == 1);
  CHECK(source.counters().start_failures == 1);
  CHECK(source.stats().corrupt_transfers == 1);
}

TEST_CASE("seek source: delivers the active area minus the latest shutter frame, for both models", "[hal][seek]") {
  for (const hal::SeekModel& m : {hal::kSeekCompact, hal::kSeekCompactPro}) {
    INFO(m.name);
    test::FakeSeek cam(m);
    cam.plan = {{3}, {3}, {3}, {6}, {1}, {20}, {3}, {3}, {6}, {1}, {20}, {3}};
    hal::SeekSource source(cam, m);
    // The crop, as the test writes it down.
    const test::TestCrop crop = test::test_crop(m);
    CHECK(source.format().width == crop.width);
    CHECK(source.format().height == crop.height);
    const auto got = stream_images(source, 8);
    REQUIRE(got.size() == 8);
    CHECK(got[0].size() == std::size_t{crop.width} * crop.height);
    CHECK(images_matching_subtraction(cam, got) == 8);
    CHECK(source.counters().shutter_frames == 3);
    CHECK(source.dead_pixels() == 0);
    CHECK(cam.refused == 0);
  }
}

TEST_CASE("seek source: without the subtraction the delivered images fail that check", "[hal][seek]") {
  // The check above has teeth: the raw active area (the offset pattern left in) matches nothing.
  for (const hal::SeekModel& m : {hal::kSeekCompact, hal::kSeekCompactPro}) {
    INFO(m.name);
    test::FakeSeek cam(m);
    cam.plan = {{3}, {3}, {6}, {1}, {20}, {3}, {3}};
    hal::SeekSource source(cam, m, {.subtract_shutter = false});
    const auto got = stream_images(source, 4);
    REQUIRE(got.size() == 4);
    CHECK(images_matching_subtraction(cam, got) == 0);
    // What it delivers is the raw active area: the metadata row is not part of it.
    const test::TestCrop c = test::test_crop(m);
    const auto& raw = cam.images_with_shutter()[0].first->words;
    CHECK(got[0][0] == raw[c.y * m.width + c.x]);
    CHECK(got[0].back() == raw[(c.y + c.height - 1) * m.width + c.x + c.width - 1]);
  }
}

TEST_CASE("seek source: images before the first shutter frame are consumed, not delivered", "[hal][seek]") {
  test::FakeSeek cam(hal::kSeekCompact);
  cam.boot = {4};
  cam.plan = {{3}, {3}, {1}, {3}};
  hal::SeekSource source(cam, hal::kSeekCompact);
  const auto got = stream_images(source, 1);
  REQUIRE(got.size() == 1);
  CHECK(source.counters().images_before_shutter == 2);
  CHECK(images_matching_subtraction(cam, got) == 0);  // the first image sent had no shutter frame...
  const auto sent = cam.images_with_shutter();
  const auto want = test::expected_seek_image(cam.model, sent[2].first->words, sent[2].second->words);
  CHECK(std::equal(want.begin(), want.end(), got[0].begin()));  // ...the third is the one delivered
}

TEST_CASE("seek source: the start-up frame must come first, a lost one runs the sequence again", "[hal][seek]") {
  SECTION("another frame first: the open fails") {
    test::FakeSeek cam(hal::kSeekCompact);
    cam.boot = {3};
    hal::SeekSource source(cam, hal::kSeekCompact);
    test::HashingCollector sink(207, 154);
    CHECK(source.stream_frame(sink) == hal::StreamStatus::fault);
    CHECK(source.counters().start_failures == 1);
    CHECK(source.stats().corrupt_transfers == 1);
  }
  SECTION("the first frame request unanswered: the sequence again, then the start-up frame") {
    test::FakeSeek cam(hal::kSeekCompact);
    cam.unanswered_requests = 1;
    hal::SeekSource source(cam, hal::kSeekCompact);
    test::HashingCollector sink(207, 154);
    CHECK(source.stream_frame(sink) == hal::StreamStatus::frame);
    CHECK(std::count(cam.log.begin(), cam.log.end(), std::uint8_t{84}) == 2);
    CHECK(source.stats().timeouts == 2);  // a request never answered costs timeouts, not a short frame
    CHECK(source.stats().short_transfers == 0);
    CHECK(source.counters().start_failures == 0);
    CHECK(cam.refused == 0);
  }
  SECTION("three attempts without a frame: a fault, counted once") {
    test::FakeSeek cam(hal::kSeekCompact);
    cam.unanswered_requests = 3;
    hal::SeekSource source(cam, hal::kSeekCompact);
    test::HashingCollector sink(207, 154);
    CHECK(source.stream_frame(sink) == hal::StreamStatus::fault);
    CHECK(std::count(cam.log.begin(), cam.log.end(), std::uint8_t{84}) == 3);
    CHECK(source.counters().start_failures == 1);
    CHECK(source.stats().corrupt_transfers == 0);
    CHECK(source.stream_frame(sink) == hal::StreamStatus::frame);  // the next call opens anew
  }
}

TEST_CASE("seek image: dead pixels by the driver's histogram rule, filled from known neighbours", "[hal][seek]") {
  const hal::SeekModel m = hal::kSeekCompact;  // active area: columns 0..206, rows 1..154
  const auto at = [&](std::uint32_t x, std::uint32_t y) { return std::size_t{y + 1} * m.width + x; };
  std::vector<std::uint16_t> startup(m.pixels(), 8000);
  // Most pixels 8000 (m), one 8010 (M): threshold 8000 - 10 = 7990.
  for (std::uint32_t x = 0; x < 50; ++x) startup[at(x, 100)] = static_cast<std::uint16_t>(8001 + x % 9);
  startup[at(60, 100)] = 8010;
  startup[at(10, 10)] = 7990;  // dead (<= threshold)
  startup[at(11, 10)] = 0;     // dead (bin 0 is ignored in the histogram, not in the rule)
  startup[at(30, 30)] = 7991;  // alive
  startup[at(0, 0)] = 5;       // dead, in the corner
  for (std::uint32_t y = 150; y < 154; ++y)
    for (std::uint32_t x = 203; x < 207; ++x) startup[at(x, y)] = 1000;  // a dead 4x4 block, bottom right
  startup[0] = 0xFFFF;  // outside the active area: no part of the rule
  hal::SeekImageCorrector c(m);
  c.take_startup(startup);
  CHECK(c.dead_pixels() == 3 + 16);
  CHECK(c.unfillable_pixels() == 0);
  const auto dead = [&](std::uint32_t x, std::uint32_t y) { return c.dead_map()[std::size_t{y} * 207 + x]; };
  CHECK(dead(10, 10) == 1);
  CHECK(dead(11, 10) == 1);
  CHECK(dead(30, 30) == 0);
  CHECK(dead(0, 0) == 1);
  CHECK(dead(206, 153) == 1);
  CHECK(dead(202, 153) == 0);

  // An image whose neighbours of the dead pixels are known values (no shutter: raw).
  std::vector<std::uint16_t> image(m.pixels(), 3000);
  image[at(9, 10)] = 100;
  image[at(10, 9)] = 200;
  image[at(10, 11)] = 300;
  image[at(12, 10)] = 400;
  image[at(11, 9)] = 500;
  image[at(11, 11)] = 601;
  image[at(1, 0)] = 10;
  image[at(0, 1)] = 21;
  c.correct(image, false);
  const auto out = [&](std::uint32_t x, std::uint32_t y) { return c.image()[std::size_t{y} * 207 + x]; };
  // Row order: (10,10) first, from left, up, down (its right is dead): 600 / 3; then (11,10)
  // with the filled (10,10) as its left: (200 + 400 + 500 + 601) / 4.
  CHECK(out(10, 10) == 200);
  CHECK(out(11, 10) == 425);
  CHECK(out(0, 0) == 15);  // (10 + 21) / 2, integer division
  CHECK(out(206, 153) == 3000);  // the block's far corner, reached over filled pixels
  CHECK(out(30, 30) == 3000);

  SECTION("a maximum above the histogram's range lowers the threshold below every pixel") {
    startup[at(100, 100)] = 0x7000;  // M = 0x7000: threshold = 8000 - (0x7000 - 8000) < 0
    c.take_startup(startup);
    CHECK(c.dead_pixels() == 0);
  }
  SECTION("an all-equal area is all dead, and none can be filled") {
    c.take_startup(std::vector<std::uint16_t>(m.pixels(), 8000));
    CHECK(c.dead_pixels() == 207u * 154u);
    CHECK(c.unfillable_pixels() == 207u * 154u);
  }
}

TEST_CASE("seek source: dead pixels from the start-up frame, filled in every image", "[hal][seek]") {
  for (const hal::SeekModel& m : {hal::kSeekCompact, hal::kSeekCompactPro}) {
    INFO(m.name);
    const test::TestCrop crop = test::test_crop(m);
    test::FakeSeek cam(m);
    // Isolated dead pixels (0 and 100 in a flat 6000..6004 start-up frame), one on the border.
    const std::vector<std::uint32_t> dead = {3 + 5 * crop.width, 77 + 40 * crop.width, 150 + 100 * crop.width,
                                             crop.width - 1};
    cam.dead_in_startup = dead;
    hal::SeekSource source(cam, m);
    const auto got = stream_images(source, 2);
    REQUIRE(got.size() == 2);
    CHECK(source.dead_pixels() == dead.size());
    for (std::uint32_t d : dead) CHECK(source.dead_map()[d] == 1);
    const auto sent = cam.images_with_shutter();
    for (std::size_t f = 0; f < got.size(); ++f) {
      const auto want = test::expected_seek_image(m, sent[f].first->words, sent[f].second->words);
      for (std::size_t i = 0; i < want.size(); ++i) {
        if (std::find(dead.begin(), dead.end(), i) != dead.end()) continue;
        if (got[f][i] != want[i]) FAIL("image " << f << " pixel " << i);
      }
      for (std::uint32_t d : dead) {  // the mean of its neighbours inside the area
        const std::uint32_t x = d % crop.width, y = d / crop.width;
        std::uint32_t sum = 0, n = 0;
        if (x > 0) sum += want[d - 1], ++n;
        if (x + 1 < crop.width) sum += want[d + 1], ++n;
        if (y > 0) sum += want[d - crop.width], ++n;
        if (y + 1 < crop.height) sum += want[d + crop.width], ++n;
        CHECK(got[f][d] == sum / n);
      }
    }
  }
}

TEST_CASE("seek source: boot frames consumed, shutter frames mark the next image", "[hal][seek]") {
  for (const hal::SeekModel& m : {hal::kSeekCompact, hal::kSeekCompactPro}) {
    INFO(m.name);
    test::FakeSeek cam(m);
    cam.boot = {4, 9, 14, 25, 26, 27, 28, 8, 7, 6, 1, 20};  // as the camera boots
    for (std::uint16_t t : {3, 3, 6, 1, 20, 3}) cam.plan.push_back({t});
    hal::SeekSource source(cam, m);
    test::HashingCollector sink(source.format().width, source.format().height);
    std::vector<fw::FfcState> ffc;
    for (int i = 0; i < 4; ++i) {
      REQUIRE(source.stream_frame(sink) == hal::StreamStatus::frame);
      ffc.push_back(sink.header().ffc);
      CHECK(sink.header().sequence == static_cast<std::uint64_t>(i));
      CHECK(sink.header().width == test::test_crop(m).width);
      CHECK(sink.header().height == test::test_crop(m).height);
      CHECK(sink.lines() == test::test_crop(m).height);
    }
    CHECK(ffc == std::vector<fw::FfcState>{fw::FfcState::completed, fw::FfcState::none,
                                          fw::FfcState::completed, fw::FfcState::none});
    CHECK(source.counters().shutter_frames == 2);
    CHECK(source.counters().startup_frames == 1);
    CHECK(source.counters().calibration_frames == 8 + 2 + 2);
    CHECK(source.stats().frames_delivered == 4);
  }
}

TEST_CASE("seek source: a failed first write is retried after the close sequence", "[hal][seek]") {
  test::FakeSeek cam(hal::kSeekCompact);
  cam.fail_first_write = true;
  hal::SeekSource source(cam, hal::kSeekCompact);
  test::HashingCollector sink(207, 154);
  CHECK(source.stream_frame(sink) == hal::StreamStatus::frame);
  const std::vector<std::uint8_t> start(cam.log.begin(), cam.log.begin() + 6);
  CHECK(start == std::vector<std::uint8_t>{84, 60, 60, 60, 84, 60});
  CHECK(cam.refused == 0);
}

TEST_CASE("seek source: zero-length reads, timeouts, errors and an unplug are counted and survived", "[hal][seek]") {
  using F = test::FakeSeek::Fault;
  const hal::SeekModel m = hal::kSeekCompact;
  test::FakeSeek cam(m);
  cam.plan = {{3}, {3, F::zero_length}, {3}, {3, F::timeout}, {3, F::error}, {3}, {3, F::unplug}, {3}, {3}};
  hal::SeekSource source(cam, m);
  test::HashingCollector sink(207, 154);
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
  test::HashingCollector sink(207, 154);
  std::vector<S> statuses;
  std::vector<std::uint64_t> seq;
  std::vector<int> counters;  // of the images delivered, found by their pixels
  for (int i = 0; i < 4; ++i) {
    statuses.push_back(source.stream_frame(sink));
    if (statuses.back() != S::frame) continue;
    seq.push_back(sink.header().sequence);
    counters.push_back(sent_image_counter(cam, sink.frame()));
  }
  CHECK(counters == std::vector<int>{5, 6, 7});  // each whole and its own (after 4, 6, 1, 20)
  CHECK(statuses == std::vector<S>{S::frame, S::fault, S::frame, S::frame});
  CHECK(seq == std::vector<std::uint64_t>{0, 1, 2});  // nothing was lost: no gap
  const hal::SourceStats st = source.stats();
  CHECK(st.timeouts == 1);
  CHECK(st.short_transfers == 0);
  CHECK(st.dropped == 0);
  CHECK(source.counters().counter_jumps == 0);
  // The paused frame was read on, not asked for again: the boot's 4 frames and 3 images.
  CHECK(std::count(cam.log.begin(), cam.log.end(), std::uint8_t{hal::seek::kStartGetImageTransfer}) == 7);
}

TEST_CASE("seek source: the rest of a frame given up on is never delivered as part of the next", "[hal][seek]") {
  using F = test::FakeSeek::Fault;
  using S = hal::StreamStatus;
  const hal::SeekModel m = hal::kSeekCompact;
  test::FakeSeek cam(m);
  cam.pause_timeouts = 3;  // longer than the source waits (2 timeouts): frame 2 is given up...
  cam.plan = {{3}, {3, F::pause}, {3}, {3}, {3}};  // ...and its rest then comes before frame 3
  hal::SeekSource source(cam, m);
  test::HashingCollector sink(207, 154);
  std::vector<S> statuses;
  std::vector<int> counters;  // of the images delivered, found by their pixels: whole, not mixed
  for (int i = 0; i < 7; ++i) {
    statuses.push_back(source.stream_frame(sink));
    if (statuses.back() == S::frame) counters.push_back(sent_image_counter(cam, sink.frame()));
  }
  // Frame 2's rest + frame 3's first chunk begin mid-frame (pixels where the type word is): that
  // "frame" is refused, frame 3's rest drained, and frame 4 asked for afresh.
  CHECK(statuses == std::vector<S>{S::frame, S::fault, S::fault, S::fault, S::fault, S::frame, S::frame});
  CHECK(counters == std::vector<int>{5, 8, 9});  // after the boot's 4, 6, 1, 20
  const hal::SourceStats st = source.stats();
  CHECK(st.timeouts == 3);
  CHECK(st.short_transfers == 1);    // frame 2, given up
  CHECK(st.corrupt_transfers == 1);  // the stale chunks with frame 3's start
  CHECK(source.counters().calibration_frames == 2);  // the boot's 6 and 20: nothing taken for another type
}

TEST_CASE("seek source: a camera that never sends an image gives faults, not a hang", "[hal][seek]") {
  test::FakeSeek cam(hal::kSeekCompact);
  cam.boot = {4};
  for (int i = 0; i < 200; ++i) cam.plan.push_back({6});
  hal::SeekSource source(cam, hal::kSeekCompact, {.max_frames_without_image = 16});
  test::HashingCollector sink(207, 154);
  CHECK(source.stream_frame(sink) == hal::StreamStatus::fault);
  CHECK(source.counters().calibration_frames == 16);
}

TEST_CASE("seek source: a refused start-up is a counted fault, an unplugged camera a disconnect", "[hal][seek]") {
  test::FakeSeek cam(hal::kSeekCompact);
  cam.unplugged = true;
  cam.replug = false;
  hal::SeekSource source(cam, hal::kSeekCompact);
  test::HashingCollector sink(207, 154);
  CHECK(source.stream_frame(sink) == hal::StreamStatus::fault);
  CHECK(source.stats().disconnects == 1);
  CHECK(cam.reconnects == 1);
  cam.unplugged = false;
  cam.fail_first_write = true;  // fails once: the retry inside start() succeeds
  CHECK(source.stream_frame(sink) == hal::StreamStatus::frame);
  CHECK(source.counters().start_failures == 0);  // the unplug is a disconnect, not a failed open
}

TEST_CASE("seek source: the frame counter shows duplicates, gaps and surprises", "[hal][seek]") {
  const hal::SeekModel m = hal::kSeekCompact;
  test::FakeSeek cam(m);
  // Image counters 1, 2, 2 (a duplicate), 5 (two lost), 1005 (a surprise), 1006; then a shutter
  // cycle whose frames count too, and an image right after it.
  cam.plan = {{3}, {3}, {3, {}, 0}, {3, {}, 3}, {3, {}, 1000}, {3}, {6}, {1}, {20}, {3}};
  hal::SeekSource source(cam, m);
  test::HashingCollector sink(207, 154);
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
  CHECK(source.counters().shutter_frames == 2);  // the boot's and the cycle's
  // The same counters by name, as `bolo capture` reports them.
  const hal::ExtraCounters extra = source.extra_counters();
  std::vector<std::string> names;
  for (const hal::NamedCounter& c : extra.items()) names.emplace_back(c.name);
  CHECK(names == std::vector<std::string>{"shutter_frames", "calibration_frames", "startup_frames",
                                          "start_failures", "images_before_shutter", "counter_jumps",
                                          "dead_pixels"});
  CHECK(extra.find("counter_jumps")->value == 2);
  CHECK(extra.find("shutter_frames")->value == 2);
}

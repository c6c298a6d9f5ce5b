// Y16 frames as V4L2 hands them over (padding, telemetry rows, short buffers), and the V4L2
// source's refusals of nodes that are not Y16 cameras.

#include <catch2/catch.hpp>

#include <vector>

#include "../firmware/frame_collector.hpp"
#include "bolo/firmware/two_frame_corrector.hpp"
#include "bolo/hal/v4l2_source.hpp"
#include "bolo/hal/y16_frame.hpp"
#include "v4l2_buffers.hpp"

using namespace bolo::hal;
using bolo::test::filled;

namespace {

// A 160x122 PureThermal frame: pixel (x, y) = 100 * y + x, row A telemetry in row 120,
// each row padded to `stride` bytes.
std::vector<std::uint8_t> lepton_buffer(std::uint32_t stride, std::uint32_t last_ffc_ms,
                                        std::uint32_t frame_counter = 77) {
  std::vector<std::uint8_t> b(std::size_t{stride} * 122, 0xEE);
  auto put = [&](std::uint32_t row, std::uint32_t x, std::uint16_t v) {
    b[std::size_t{row} * stride + 2 * x] = static_cast<std::uint8_t>(v & 0xFF);
    b[std::size_t{row} * stride + 2 * x + 1] = static_cast<std::uint8_t>(v >> 8);
  };
  for (std::uint32_t y = 0; y < 120; ++y)
    for (std::uint32_t x = 0; x < 160; ++x) put(y, x, static_cast<std::uint16_t>(100 * y + x));
  for (std::uint32_t x = 0; x < 160; ++x) {
    put(120, x, 0);
    put(121, x, 0);
  }
  put(120, 3, 3u << 4);  // FFC complete
  put(120, 20, static_cast<std::uint16_t>(frame_counter & 0xFFFF));
  put(120, 21, static_cast<std::uint16_t>(frame_counter >> 16));
  put(120, 24, 30615);
  put(120, 26, 30500);
  put(120, 30, static_cast<std::uint16_t>(last_ffc_ms & 0xFFFF));
  put(120, 31, static_cast<std::uint16_t>(last_ffc_ms >> 16));
  return b;
}

}  // namespace

TEST_CASE("y16: padded rows, telemetry row A decoded from the first telemetry row", "[hal][v4l2]") {
  for (std::uint32_t stride : {320u, 384u}) {
    INFO("stride " << stride);
    const auto buf = lepton_buffer(stride, 123456);
    const Y16Layout layout{160, 120, 2, stride};
    REQUIRE(Y16Frame::check(buf, layout) == Y16Check::ok);
    const Y16Frame f(buf, layout);
    std::vector<std::uint16_t> row(160);
    f.image_row(119, row);
    CHECK(row[0] == 11900);
    CHECK(row[159] == 12059);
    LeptonTelemetry t;
    REQUIRE(f.telemetry(t));
    CHECK(t.ffc_state == LeptonFfcState::complete);
    CHECK(t.frame_counter == 77);
    CHECK(t.fpa_temp_ck == 30615);
    CHECK(t.housing_temp_ck == 30500);
    CHECK(t.time_at_last_ffc_ms == 123456);
  }
}

TEST_CASE("y16: short buffers and impossible layouts are refused, no telemetry without its rows", "[hal][v4l2]") {
  const auto buf = lepton_buffer(320, 0);
  // The last row needs no padding after it.
  CHECK(Y16Frame::check({buf.data(), 121 * 384 + 320}, Y16Layout{160, 120, 2, 384}) == Y16Check::ok);
  CHECK(Y16Frame::check({buf.data(), 121 * 384 + 319}, Y16Layout{160, 120, 2, 384}) == Y16Check::short_frame);
  CHECK(Y16Frame::check({buf.data(), buf.size() - 1}, Y16Layout{160, 120, 2, 320}) == Y16Check::short_frame);
  CHECK(Y16Frame::check(buf, Y16Layout{160, 120, 2, 100}) == Y16Check::bad_layout);
  CHECK(Y16Frame::check(buf, Y16Layout{0, 120, 2, 0}) == Y16Check::bad_layout);
  CHECK(Y16Frame::check(buf, Y16Layout{160, 0, 2, 0}) == Y16Check::bad_layout);
  const Y16Layout plain{160, 120, 0, 0};
  REQUIRE(Y16Frame::check(buf, plain) == Y16Check::ok);
  LeptonTelemetry t;
  CHECK_FALSE(Y16Frame(buf, plain).telemetry(t));
  const Y16Layout narrow{40, 30, 2, 0};  // a telemetry row narrower than 80 words
  REQUIRE(Y16Frame::check(buf, narrow) == Y16Check::ok);
  CHECK_FALSE(Y16Frame(buf, narrow).telemetry(t));
}

TEST_CASE("v4l2: nodes that are not Y16 capture devices are refused by name", "[hal][v4l2]") {
  auto refused = [](const std::string& path) {
    try {
      V4l2Source source(V4l2Config{.path = path});
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  CHECK(refused("/dev/null") == "/dev/null: not a V4L2 device");
  CHECK(refused("/nonexistent/video9").rfind("/nonexistent/video9: cannot open: ", 0) == 0);
}

TEST_CASE("v4l2: the Y16 size asked for among what the driver offers", "[hal][v4l2]") {
  using Sizes = std::vector<std::pair<std::uint32_t, std::uint32_t>>;
  using Size = std::pair<std::uint32_t, std::uint32_t>;
  const Sizes lepton{{160, 120}, {160, 122}};
  CHECK(choose_frame_size(lepton, {}) == Size{160, 122});  // telemetry rows when offered
  CHECK(choose_frame_size(lepton, {.telemetry = TelemetryRows::off}) == Size{160, 120});
  CHECK(choose_frame_size(lepton, {.width = 160, .height = 120}) == Size{160, 122});
  CHECK(choose_frame_size(lepton, {.width = 160, .height = 120, .telemetry = TelemetryRows::off}) == Size{160, 120});
  const Sizes boson{{320, 256}, {640, 512}};
  CHECK(choose_frame_size(boson, {}) == Size{640, 512});
  CHECK_FALSE(choose_frame_size(boson, {.telemetry = TelemetryRows::on}).has_value());
  CHECK_FALSE(choose_frame_size(boson, {.width = 160, .height = 120}).has_value());
  // A test pattern generator's huge modes: the largest one up to the limit, unless asked for.
  const Sizes vivid{{16384, 8640}, {3840, 2160}, {640, 480}, {1280, 720}};
  CHECK(choose_frame_size(vivid, {}) == Size{1280, 720});
  CHECK(choose_frame_size(vivid, {.width = 3840, .height = 2160}) == Size{3840, 2160});
  CHECK(choose_frame_size(Sizes{{16384, 8640}, {3840, 2160}}, {}) == Size{3840, 2160});  // none fits: smallest
  CHECK_FALSE(choose_frame_size(Sizes{}, {}).has_value());
}

TEST_CASE("v4l2: sequence gaps count frames never delivered, late frames are taken back", "[hal][v4l2]") {
  SequenceGaps in_order;
  for (std::uint32_t s : {7u, 8u, 9u}) CHECK(in_order.add(s));
  CHECK(in_order.missing() == 0);
  CHECK(in_order.out_of_order() == 0);

  SequenceGaps gap;  // 11 and 12 never come
  for (std::uint32_t s : {9u, 10u, 13u, 14u}) CHECK(gap.add(s));
  CHECK(gap.missing() == 2);

  // uvcvideo completed 129 after 130 (seen in the HIL VM): nothing is missing in the end, and
  // the swap does not wrap into ~4e9 "drops" as a plain difference would.
  SequenceGaps swapped;
  CHECK(swapped.add(128));
  CHECK(swapped.add(130));
  CHECK(swapped.missing() == 1);
  CHECK_FALSE(swapped.add(129));
  CHECK(swapped.add(131));
  CHECK(swapped.missing() == 0);
  CHECK(swapped.out_of_order() == 1);

  SequenceGaps wrap;  // the 32-bit counter wrapping is a step of 1
  CHECK(wrap.add(0xFFFFFFFFu));
  CHECK(wrap.add(0));
  CHECK(wrap.missing() == 0);

  SequenceGaps reopened;  // a reopened device starts at 0 again: no gap, nothing late
  CHECK(reopened.add(500));
  reopened.restart();
  CHECK(reopened.add(0));
  CHECK(reopened.missing() == 0);
  CHECK(reopened.out_of_order() == 0);
}

TEST_CASE("v4l2 buffers: synthetic Y16 buffers become frames, with gaps, FFC, refusals and a reopen counted", "[hal][v4l2]") {
  using S = StreamStatus;
  V4l2BufferStream stream(Y16Layout{160, 120, 2, 384});
  SourceStats st;
  bolo::test::HashingCollector sink(160, 120);
  const auto before_ffc = lepton_buffer(384, 100, 1), after_ffc = lepton_buffer(384, 5000, 4);
  REQUIRE(stream.deliver(filled(before_ffc, 10), sink, st) == S::frame);
  CHECK(sink.header().sequence == 10);
  CHECK(sink.header().timestamp_valid);
  CHECK(sink.header().timestamp_ns == 1'110'000'000);
  CHECK(sink.header().ffc == bolo::fw::FfcState::none);  // the first stamp is no event
  CHECK(sink.header().fpa_temp_mc == 33000);             // 306.15 K
  CHECK(sink.lines() == 120);
  CHECK(sink.frame()[119 * 160 + 159] == 12059);  // image rows only, padding skipped
  REQUIRE(stream.deliver(filled(before_ffc, 11), sink, st) == S::frame);
  CHECK(sink.header().ffc == bolo::fw::FfcState::none);
  REQUIRE(stream.deliver(filled(after_ffc, 13), sink, st) == S::frame);  // 12 never came
  CHECK(sink.header().ffc == bolo::fw::FfcState::completed);
  CHECK(st.dropped == 1);

  V4l2BufferStream::Buffer failed = filled(after_ffc, 14);
  failed.error = true;
  CHECK(stream.deliver(failed, sink, st) == S::fault);
  const std::vector<std::uint8_t> cut(after_ffc.begin(), after_ffc.end() - 64 - 2);  // into the last row
  CHECK(stream.deliver(filled(cut, 15), sink, st) == S::fault);
  CHECK(st.corrupt_transfers == 1);
  CHECK(st.short_transfers == 1);
  CHECK(st.dropped == 1);  // numbered and handed over, if broken: not dropped

  stream.reopened(Y16Layout{160, 120, 2, 320});  // the driver numbers from 0 again
  REQUIRE(stream.deliver(filled(lepton_buffer(320, 5000, 9), 0), sink, st) == S::frame);
  CHECK(sink.header().sequence == 17);  // after 15, with a gap for the unplug
  CHECK(sink.header().ffc == bolo::fw::FfcState::none);
  CHECK(st.frames_delivered == 4);
  CHECK(stream.out_of_order() == 0);
}

TEST_CASE("v4l2 buffers: the telemetry frame counter shows frames skipped in the camera and sent twice", "[hal][v4l2]") {
  V4l2BufferStream stream(Y16Layout{160, 120, 2, 320});
  SourceStats st;
  bolo::test::HashingCollector sink(160, 120);
  // (telemetry frame counter, the driver's sequence number) of each buffer, in the order dequeued;
  // the delivered header's sequence of each.
  auto stream_frames = [&](std::initializer_list<std::pair<std::uint32_t, std::uint32_t>> frames) {
    std::vector<std::uint64_t> delivered;
    for (auto [counter, sequence] : frames) {
      const auto bytes = lepton_buffer(320, 100, counter);
      REQUIRE(stream.deliver(filled(bytes, sequence), sink, st) == StreamStatus::frame);
      delivered.push_back(sink.header().sequence);
    }
    return delivered;
  };
  // 1003 never left the camera: no gap in the driver's numbers, but one in the delivered sequence.
  CHECK(stream_frames({{1001, 0}, {1002, 1}, {1004, 2}}) == std::vector<std::uint64_t>{0, 1, 3});
  CHECK(stream.skipped_in_camera() == 1);
  CHECK(st.dropped == 0);
  // 1005 had the driver's number 3, which it dropped: not the camera's, the driver's gap is the gap.
  CHECK(stream_frames({{1006, 4}}) == std::vector<std::uint64_t>{5});
  CHECK(stream.skipped_in_camera() == 1);
  CHECK(st.dropped == 1);
  CHECK(stream_frames({{1006, 5}}) == std::vector<std::uint64_t>{6});  // sent twice: delivered, no gap
  CHECK(st.duplicates == 1);
  // uvcvideo swapped two: nothing lost, nothing twice, no gap beyond the swap's own.
  CHECK(stream_frames({{1008, 7}, {1007, 6}, {1009, 8}}) == std::vector<std::uint64_t>{8, 7, 9});
  CHECK(stream.out_of_order() == 1);
  CHECK(st.dropped == 1);
  CHECK(stream.skipped_in_camera() == 1);
  CHECK(st.duplicates == 1);
  // 1010, 1011 skipped (1012 comes 3 after 1009); 1012 again after 1013.
  CHECK(stream_frames({{1012, 9}, {1013, 10}, {1012, 11}}) == std::vector<std::uint64_t>{12, 13, 14});
  CHECK(stream.skipped_in_camera() == 3);
  CHECK(st.duplicates == 2);
  // The core counts from the start again: a jump, no losses, no gap.
  CHECK(stream_frames({{7, 12}, {8, 13}}) == std::vector<std::uint64_t>{15, 16});
  CHECK(stream.counter_jumps() == 1);
  CHECK(stream.skipped_in_camera() == 3);
  CHECK(st.duplicates == 2);
  stream.reopened(Y16Layout{160, 120, 2, 320});  // a replugged camera counts anew
  CHECK(stream_frames({{500, 0}, {501, 1}}) == std::vector<std::uint64_t>{18, 19});  // after 16, with a gap
  CHECK(stream.skipped_in_camera() == 3);
  CHECK(stream.counter_jumps() == 1);
  CHECK(st.frames_delivered == 15);
}

TEST_CASE("v4l2 buffers: the frame after frames the camera skipped is not corrected against the one before", "[hal][v4l2]") {
  // Counter 3 never left the camera. The driver's numbers and time stamps run on evenly (it never
  // saw the frame), so only the sequence can tell the corrector that 4 has no predecessor.
  V4l2BufferStream stream(Y16Layout{160, 120, 2, 320});
  SourceStats st;
  bolo::test::HashingCollector out(160, 120);
  const bolo::fw::CorrectorConfig config = bolo::test::lepton_corrector_config(160, 120);
  std::vector<bolo::fw::Pixel> storage(bolo::fw::TwoFrameCorrector::storage_pixels(160, 120));
  bolo::fw::TwoFrameCorrector corrector(config, storage, out);
  std::vector<std::uint64_t> sequence;
  std::vector<bolo::fw::CarryOver> carry_over;
  std::uint32_t driver_sequence = 0;
  for (std::uint32_t counter : {1u, 2u, 4u, 5u}) {
    const auto bytes = lepton_buffer(320, 100, counter);
    REQUIRE(stream.deliver(filled(bytes, driver_sequence++), corrector, st) == StreamStatus::frame);
    sequence.push_back(out.header().sequence);
    carry_over.push_back(corrector.last_frame().carry_over);
  }
  using bolo::fw::CarryOver;
  CHECK(sequence == std::vector<std::uint64_t>{0, 1, 3, 4});  // one frame skipped: a step of 2
  CHECK(carry_over == std::vector<CarryOver>{CarryOver::first_frame, CarryOver::applied, CarryOver::sequence_gap,
                                             CarryOver::applied});
  CHECK(stream.skipped_in_camera() == 1);
  CHECK(st.dropped == 0);  // the driver's count stays the driver's
}

TEST_CASE("v4l2 buffers: a camera exporting every third core frame steps its counter by 3", "[hal][v4l2]") {
  V4l2BufferStream stream(Y16Layout{160, 120, 2, 320});
  SourceStats st;
  bolo::test::HashingCollector sink(160, 120);
  std::uint32_t sequence = 0;
  std::vector<std::uint64_t> delivered;
  for (std::uint32_t counter : {30u, 33u, 36u, 42u, 42u, 45u}) {  // 39 skipped, 42 sent twice
    const auto bytes = lepton_buffer(320, 100, counter);
    REQUIRE(stream.deliver(filled(bytes, sequence++), sink, st) == StreamStatus::frame);
    delivered.push_back(sink.header().sequence);
  }
  CHECK(delivered == std::vector<std::uint64_t>{0, 1, 2, 4, 5, 6});
  CHECK(stream.skipped_in_camera() == 1);
  CHECK(st.duplicates == 1);
  CHECK(stream.counter_jumps() == 0);
}

TEST_CASE("v4l2 buffers: without telemetry rows nothing is counted from them", "[hal][v4l2]") {
  V4l2BufferStream stream(Y16Layout{160, 120, 0, 320});
  SourceStats st;
  bolo::test::HashingCollector sink(160, 120);
  for (std::uint32_t sequence : {0u, 1u, 2u}) {
    const auto bytes = lepton_buffer(320, 100, sequence * 5);  // row 120 is not read
    REQUIRE(stream.deliver(filled(bytes, sequence), sink, st) == StreamStatus::frame);
    CHECK(sink.header().sequence == sequence);  // the driver's numbers, no gaps from the image
  }
  CHECK(stream.skipped_in_camera() == 0);
  CHECK(st.duplicates == 0);
}

// The V4L2 formats beside Y16 (GREY, YUYV, UYVY: the 8-bit luma, marked tone-mapped), the Lepton
// 2.x telemetry size 80x63, the FFC states from telemetry into FrameHeader (and what the corrector
// and a recording make of them), and the source spec's options.

#include <catch2/catch.hpp>

#include <stdexcept>
#include <vector>

#include "../firmware/frame_collector.hpp"
#include "bolo/firmware/two_frame_corrector.hpp"
#include "bolo/hal/device_spec.hpp"
#include "bolo/hal/v4l2_source.hpp"
#include "bolo/hal/y16_frame.hpp"
#include "v4l2_buffers.hpp"
#include "bolo/recording/frame_row_header.hpp"

using namespace bolo::hal;
using bolo::test::filled;
using bolo::fw::FfcState;

namespace {

// An 8-bit frame as a driver fills it: pixel (x, y) has luma 7 * x + 11 * y (mod 256), chroma
// bytes 0x80 (YUYV: Y U Y V, UYVY: U Y V Y), rows padded to `stride` with 0xEE.
std::vector<std::uint8_t> luma_buffer(V4l2Pixels pixels, std::uint32_t w, std::uint32_t h, std::uint32_t stride) {
  std::vector<std::uint8_t> b(std::size_t{stride} * h, 0xEE);
  for (std::uint32_t y = 0; y < h; ++y)
    for (std::uint32_t x = 0; x < w; ++x) {
      const auto luma = static_cast<std::uint8_t>((7 * x + 11 * y) & 0xFF);
      std::uint8_t* row = b.data() + std::size_t{y} * stride;
      switch (pixels) {
        case V4l2Pixels::grey: row[x] = luma; break;
        case V4l2Pixels::yuyv: row[2 * x] = luma, row[2 * x + 1] = 0x80; break;
        case V4l2Pixels::uyvy: row[2 * x] = 0x80, row[2 * x + 1] = luma; break;
        case V4l2Pixels::y16: break;
      }
    }
  return b;
}

struct Telemetry {
  LeptonFfcState ffc = LeptonFfcState::complete;
  std::uint32_t last_ffc_ms = 100;
  std::uint32_t frame_counter = 1;
};

// A Y16 frame `width` x `image_rows` (pixel = 100 * y + x) with `telemetry_rows` rows after it,
// row A in the first of them, unpadded.
std::vector<std::uint8_t> y16_buffer(std::uint32_t width, std::uint32_t image_rows, std::uint32_t telemetry_rows,
                                     const Telemetry& t) {
  const std::uint32_t stride = width * 2;
  std::vector<std::uint8_t> b(std::size_t{stride} * (image_rows + telemetry_rows), 0);
  auto put = [&](std::uint32_t row, std::uint32_t x, std::uint32_t v) {
    b[std::size_t{row} * stride + 2 * x] = static_cast<std::uint8_t>(v & 0xFF);
    b[std::size_t{row} * stride + 2 * x + 1] = static_cast<std::uint8_t>((v >> 8) & 0xFF);
  };
  for (std::uint32_t y = 0; y < image_rows; ++y)
    for (std::uint32_t x = 0; x < width; ++x) put(y, x, 100 * y + x);
  const std::uint32_t a = image_rows;
  put(a, 3, static_cast<std::uint32_t>(t.ffc) << 4);
  put(a, 20, t.frame_counter & 0xFFFF);
  put(a, 21, t.frame_counter >> 16);
  put(a, 24, 30615);  // 33.0 C
  put(a, 26, 30500);
  put(a, 30, t.last_ffc_ms & 0xFFFF);
  put(a, 31, t.last_ffc_ms >> 16);
  for (std::uint32_t r = a + 1; r < a + telemetry_rows; ++r)  // rows B, C: not row A's fields
    for (std::uint32_t x = 0; x < width; ++x) put(r, x, 0xBBBB);
  return b;
}

}  // namespace

TEST_CASE("v4l2 formats: GREY, YUYV and UYVY rows give the luma, padding skipped", "[hal][v4l2]") {
  for (const V4l2Pixels pixels : {V4l2Pixels::grey, V4l2Pixels::yuyv, V4l2Pixels::uyvy}) {
    INFO(v4l2_pixels_name(pixels));
    const std::uint32_t w = 80, h = 60, row = w * bytes_per_pixel(pixels);
    for (const std::uint32_t stride : {row, row + 32}) {
      const auto buf = luma_buffer(pixels, w, h, stride);
      const Y16Layout layout{w, h, 0, stride, pixels};
      REQUIRE(Y16Frame::check(buf, layout) == Y16Check::ok);
      std::vector<std::uint16_t> line(w);
      for (const std::uint32_t y : {0u, 37u, 59u}) {
        Y16Frame(buf, layout).image_row(y, line);
        for (std::uint32_t x = 0; x < w; ++x) REQUIRE(line[x] == ((7 * x + 11 * y) & 0xFF));
      }
      // The last row needs no padding after it; one byte less is short.
      const std::size_t whole = std::size_t{h - 1} * stride + row;
      CHECK(Y16Frame::check({buf.data(), whole}, layout) == Y16Check::ok);
      CHECK(Y16Frame::check({buf.data(), whole - 1}, layout) == Y16Check::short_frame);
    }
    // A stride that does not hold a row (GREY: 80 bytes, the 4:2:2 modes: 160).
    CHECK(Y16Frame::check(luma_buffer(pixels, 80, 60, 160), Y16Layout{80, 60, 0, 79, pixels}) == Y16Check::bad_layout);
    CHECK(tone_mapped(pixels));
    // Telemetry rows come only with Y16.
    CHECK(Y16Frame::check(std::vector<std::uint8_t>(80 * 2 * 63), Y16Layout{80, 60, 3, 0, pixels}) ==
          Y16Check::bad_layout);
  }
  CHECK_FALSE(tone_mapped(V4l2Pixels::y16));
  CHECK(bytes_per_pixel(V4l2Pixels::grey) == 1);
  CHECK(bytes_per_pixel(V4l2Pixels::yuyv) == 2);
}

TEST_CASE("v4l2 formats: names, fourccs and the order they are tried in", "[hal][v4l2]") {
  CHECK(kV4l2PixelOrder[0] == V4l2Pixels::y16);  // the counts first, then the 8-bit modes
  CHECK(kV4l2PixelOrder[1] == V4l2Pixels::grey);
  CHECK(v4l2_pixels_named("grey") == V4l2Pixels::grey);
  CHECK(v4l2_pixels_named("YUYV") == V4l2Pixels::yuyv);
  CHECK(v4l2_pixels_named("Uyvy") == V4l2Pixels::uyvy);
  CHECK(v4l2_pixels_named("Y16") == V4l2Pixels::y16);
  CHECK_FALSE(v4l2_pixels_named("RGB3").has_value());
  CHECK_FALSE(v4l2_pixels_named("GRE").has_value());
  CHECK(v4l2_pixels_fourcc(V4l2Pixels::grey) == 0x59455247u);  // 'G' 'R' 'E' 'Y'
  CHECK(v4l2_pixels_fourcc(V4l2Pixels::yuyv) == 0x56595559u);  // 'Y' 'U' 'Y' 'V'
  CHECK(v4l2_pixels_fourcc(V4l2Pixels::uyvy) == 0x59565955u);  // 'U' 'Y' 'V' 'Y'
  CHECK(v4l2_pixels_fourcc(V4l2Pixels::y16) == 0x20363159u);   // 'Y' '1' '6' ' '
}

TEST_CASE("v4l2 buffers: a GREY stream delivers the luma, with no telemetry and no FFC knowledge", "[hal][v4l2]") {
  V4l2BufferStream stream(Y16Layout{80, 60, 0, 0, V4l2Pixels::grey});
  SourceStats st;
  bolo::test::HashingCollector sink(80, 60);
  const auto buf = luma_buffer(V4l2Pixels::grey, 80, 60, 80);
  REQUIRE(stream.deliver(filled(buf, 4), sink, st) == StreamStatus::frame);
  CHECK(sink.frame()[59 * 80 + 79] == ((7 * 79 + 11 * 59) & 0xFF));
  CHECK(sink.header().ffc == FfcState::unknown);
  CHECK(sink.header().fpa_temp_mc == bolo::fw::kUnknownTemperature);
  CHECK(st.frames_delivered == 1);
}

TEST_CASE("lepton 2.x: 80x63 is recognised as 60 image rows and 3 telemetry rows", "[hal][v4l2][telemetry]") {
  CHECK(lepton_telemetry_rows(80, 63) == 3);
  CHECK(lepton_telemetry_rows(160, 122) == 2);
  CHECK(lepton_telemetry_rows(80, 60) == 0);
  CHECK(lepton_telemetry_rows(160, 120) == 0);
  CHECK(lepton_telemetry_rows(80, 62) == 0);

  using Sizes = V4l2Sizes;
  using Size = std::pair<std::uint32_t, std::uint32_t>;
  const Sizes lepton2{{80, 60}, {80, 63}};  // what a PureThermal with a Lepton 2.x offers in Y16
  CHECK(choose_frame_size(lepton2, {}) == Size{80, 63});
  CHECK(choose_frame_size(lepton2, {.telemetry = TelemetryRows::off}) == Size{80, 60});
  CHECK(choose_frame_size(lepton2, {.width = 80, .height = 60}) == Size{80, 63});
  CHECK(choose_frame_size(lepton2, {.telemetry = TelemetryRows::on}) == Size{80, 63});
  // The same sizes in an 8-bit mode carry no telemetry: 80x63 would be 63 image rows.
  CHECK_FALSE(choose_frame_size(lepton2, {.telemetry = TelemetryRows::on}, V4l2Pixels::grey).has_value());
  CHECK(choose_frame_size(lepton2, {.width = 80, .height = 60}, V4l2Pixels::grey) == Size{80, 60});

  // Row A is row 60; rows B and C (61, 62) are not image.
  V4l2BufferStream stream(Y16Layout{80, 60, 3, 0});
  SourceStats st;
  bolo::test::HashingCollector sink(80, 60);
  for (std::uint32_t i = 0; i < 3; ++i) {
    const auto buf = y16_buffer(80, 60, 3, {.ffc = LeptonFfcState::complete, .last_ffc_ms = i < 2 ? 100u : 900u,
                                           .frame_counter = 10 + i});
    REQUIRE(stream.deliver(filled(buf, i), sink, st) == StreamStatus::frame);
    CHECK(sink.lines() == 60);
    CHECK(sink.frame()[59 * 80 + 79] == 5979);
    CHECK(sink.header().fpa_temp_mc == 33000);
    CHECK(sink.header().housing_temp_mc == 31850);
    CHECK(stream.last_telemetry().frame_counter == 10 + i);
  }
  CHECK(sink.header().ffc == FfcState::completed);  // the stamp changed at the third frame
  CHECK(stream.skipped_in_camera() == 0);
  CHECK(stream.counter_jumps() == 0);
}

TEST_CASE("lepton FFC states: imminent and in progress reach the header, and the frame after is completed",
          "[hal][telemetry]") {
  LeptonFfcTracker ffc;
  const auto at = [](LeptonFfcState state, std::uint32_t stamp) {
    LeptonTelemetry t;
    t.ffc_state = state;
    t.time_at_last_ffc_ms = stamp;
    return t;
  };
  using L = LeptonFfcState;
  CHECK(ffc.next(at(L::never, 0)) == FfcState::none);
  CHECK(ffc.next(at(L::imminent, 0)) == FfcState::imminent);
  CHECK(ffc.next(at(L::in_progress, 0)) == FfcState::in_progress);
  CHECK(ffc.next(at(L::in_progress, 0)) == FfcState::in_progress);
  // A core that stamps the FFC as it completes, and one that stamped it as it began: the first
  // frame after it is `completed` either way.
  CHECK(ffc.next(at(L::complete, 5000)) == FfcState::completed);
  CHECK(ffc.next(at(L::complete, 5000)) == FfcState::none);
  CHECK(ffc.next(at(L::in_progress, 9000)) == FfcState::in_progress);
  CHECK(ffc.next(at(L::complete, 9000)) == FfcState::completed);
  CHECK(ffc.next(at(L::complete, 9000)) == FfcState::none);
  // A new stamp without a frame in progress (the export paused during the FFC).
  CHECK(ffc.next(at(L::complete, 12000)) == FfcState::completed);
  ffc.restart();
  CHECK(ffc.next(at(L::complete, 15000)) == FfcState::none);  // no predecessor to differ from

  CHECK(bolo::fw::shutter_event(FfcState::completed));
  CHECK(bolo::fw::shutter_event(FfcState::in_progress));
  CHECK_FALSE(bolo::fw::shutter_event(FfcState::imminent));
  CHECK_FALSE(bolo::fw::shutter_event(FfcState::none));
  CHECK_FALSE(bolo::fw::shutter_event(FfcState::unknown));
}

TEST_CASE("lepton FFC states through a V4L2 stream: the corrector breaks the carry-over, frames.csv says ffc 1",
          "[hal][v4l2][telemetry]") {
  V4l2BufferStream stream(Y16Layout{80, 60, 3, 0});
  SourceStats st;
  bolo::test::HashingCollector out(80, 60);
  const bolo::fw::CorrectorConfig config = bolo::test::lepton_corrector_config(80, 60);
  std::vector<bolo::fw::Pixel> storage(bolo::fw::TwoFrameCorrector::storage_pixels(80, 60));
  bolo::fw::TwoFrameCorrector corrector(config, storage, out);
  using L = LeptonFfcState;
  const std::vector<Telemetry> frames = {
      {L::complete, 100, 1}, {L::imminent, 100, 2}, {L::in_progress, 100, 3},
      {L::in_progress, 100, 4}, {L::complete, 700, 5}, {L::complete, 700, 6}};
  std::vector<FfcState> ffc;
  std::vector<bolo::fw::CarryOver> carry_over;
  std::vector<std::optional<bool>> csv;
  for (std::uint32_t i = 0; i < frames.size(); ++i) {
    const auto buf = y16_buffer(80, 60, 3, frames[i]);
    REQUIRE(stream.deliver(filled(buf, i), corrector, st) == StreamStatus::frame);
    ffc.push_back(out.header().ffc);
    carry_over.push_back(corrector.last_frame().carry_over);
    csv.push_back(bolo::rec::row_from_header(out.header(), i, 0).ffc);
  }
  CHECK(ffc == std::vector<FfcState>{FfcState::none, FfcState::imminent, FfcState::in_progress, FfcState::in_progress,
                                     FfcState::completed, FfcState::none});
  using bolo::fw::CarryOver;
  CHECK(carry_over == std::vector<CarryOver>{CarryOver::first_frame, CarryOver::applied, CarryOver::ffc_event,
                                             CarryOver::ffc_event, CarryOver::ffc_event, CarryOver::applied});
  CHECK(csv == std::vector<std::optional<bool>>{false, false, true, true, true, false});
}

TEST_CASE("source spec options: KEY=VALUE lists, one parser for --gpio and v4l2:NODE?format=", "[hal][v4l2]") {
  const auto options = parse_spec_options("format=GREY,x=1,flag");
  REQUIRE(options.size() == 3);
  CHECK(options[0].key == "format");
  CHECK(options[0].value == "GREY");
  CHECK(options[2].key == "flag");
  CHECK(options[2].value.empty());
  CHECK(parse_spec_options("").empty());
  CHECK_THROWS_WITH(parse_spec_options("=3"), "'=3': expected KEY=VALUE");
  CHECK_THROWS_WITH(parse_spec_options("a=1,,b=2"), "'': expected KEY=VALUE");
  CHECK(parse_gpio_spec("gpiochip0:sync=3,shutter=4").shutter_line == 4);
}

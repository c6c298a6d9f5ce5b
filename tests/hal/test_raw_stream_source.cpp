// RawStreamSource: whole frames from a file descriptor, a short tail counted, never crashed on.

#include <catch2/catch.hpp>

#include <fcntl.h>
#include <unistd.h>

#include <fstream>
#include <vector>

#include "../firmware/frame_collector.hpp"
#include "../test_support.hpp"
#include "bolo/hal/raw_stream_source.hpp"

using namespace bolo;

TEST_CASE("raw Y16 frames stream line by line, a cut-off frame is counted", "[hal][raw]") {
  bolo::test::TempDir tmp;
  const auto file = tmp / "in.y16";
  constexpr std::uint32_t W = 5, H = 3;
  {
    std::ofstream out(file, std::ios::binary);
    for (int f = 0; f < 3; ++f)
      for (std::uint32_t i = 0; i < W * H; ++i) {
        const std::uint16_t v = static_cast<std::uint16_t>(1000 * f + i + 0x0100);
        out.put(static_cast<char>(v & 0xFF));
        out.put(static_cast<char>(v >> 8));
      }
    out.write("\x01\x02\x03", 3);  // a frame cut short
  }
  const int fd = ::open(file.c_str(), O_RDONLY);
  REQUIRE(fd >= 0);
  hal::RawStreamConfig cfg{W, H, 14, 33'333'333, 8'000'000, 25'000'000};
  hal::RawStreamSource source(fd, cfg);
  bolo::test::HashingCollector sink(W, H);
  int frames = 0;
  while (source.stream_frame(sink) == hal::StreamStatus::frame) {
    CHECK(sink.frame()[0] == 1000 * frames + 0x0100);
    CHECK(sink.frame()[W * H - 1] == 1000 * frames + W * H - 1 + 0x0100);
    CHECK(sink.header().sequence == static_cast<std::uint64_t>(frames));
    CHECK(sink.header().exposure_ns == 8'000'000);
    CHECK(sink.header().timestamp_ns == 33'333'333LL * frames);
    ++frames;
  }
  CHECK(frames == 3);
  CHECK(source.stats().frames_delivered == 3);
  CHECK(source.stats().short_transfers == 1);
  CHECK(source.stream_frame(sink) == hal::StreamStatus::end_of_stream);  // stays ended
  ::close(fd);
}

TEST_CASE("a bad file descriptor is a counted fault, not a crash", "[hal][raw]") {
  hal::RawStreamSource source(-1, {4, 4, 16, 0, 0, 0});
  bolo::test::HashingCollector sink(4, 4);
  CHECK(source.stream_frame(sink) == hal::StreamStatus::end_of_stream);
  CHECK(source.stats().corrupt_transfers == 1);
  CHECK(sink.frames() == 0);
}

TEST_CASE("raw Y16 frames stream from the caller's storage, which must hold a frame and a line",
          "[hal][raw]") {
  bolo::test::TempDir tmp;
  const auto file = tmp / "in.y16";
  constexpr std::uint32_t W = 4, H = 2;
  {
    std::ofstream out(file, std::ios::binary);
    for (std::uint32_t i = 0; i < 2 * W * H; ++i) {
      out.put(static_cast<char>(i));
      out.put(static_cast<char>(0x30));
    }
  }
  const hal::RawStreamConfig cfg{W, H, 16, 0, 0, 0};
  REQUIRE(hal::RawStreamSource::frame_bytes(cfg) == W * H * 2);
  std::vector<std::uint8_t> frame(W * H * 2);
  std::vector<fw::Pixel> line(W);
  for (const bool enough : {true, false}) {
    const int fd = ::open(file.c_str(), O_RDONLY);
    REQUIRE(fd >= 0);
    hal::RawStreamSource source(fd, cfg, std::span(frame).first(enough ? frame.size() : frame.size() - 1),
                                line);
    bolo::test::HashingCollector sink(W, H);
    int frames = 0;
    while (source.stream_frame(sink) == hal::StreamStatus::frame) {
      CHECK(sink.frame()[W * H - 1] == 0x3000 + W * H * (frames + 1) - 1);
      ++frames;
    }
    CHECK(frames == (enough ? 2 : 0));
    ::close(fd);
  }
}

// A minimal board program: raw Y16 frames in on stdin (a HAL source), the firmware pipeline
// (bad pixels + two-frame corrector), corrected Y16 frames out on stdout. What a camera board's
// main loop looks like; also what the size report measures.
//
//   correct_stream WIDTH HEIGHT TAU_H_US TAU_C_US EXPOSURE_US READOUT_US [PERIOD_US] < in.y16 > out.y16
//
// Built like the firmware: no exceptions, no RTTI, and no heap: the pipeline's arena, the raw
// frame and the output line are static buffers sized at compile time for frames up to
// BOLO_MAX_WIDTH x BOLO_MAX_HEIGHT (default 640 x 512); larger frames are refused.

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include <unistd.h>

#include "bolo/firmware/pipeline.hpp"
#include "bolo/hal/raw_stream_source.hpp"

#ifndef BOLO_MAX_WIDTH
#define BOLO_MAX_WIDTH 640
#endif
#ifndef BOLO_MAX_HEIGHT
#define BOLO_MAX_HEIGHT 512
#endif

namespace {

using namespace bolo;

constexpr std::uint32_t kMaxWidth = BOLO_MAX_WIDTH;
constexpr std::uint32_t kMaxHeight = BOLO_MAX_HEIGHT;
// What the pipeline below (bad pixels + corrector) needs at the largest frame, with room for a
// smaller frame whose bad-pixel ring takes more lines (checked against arena_pixels at run time).
constexpr std::size_t kArenaPixels =
    fw::TwoFrameCorrector::storage_pixels(kMaxWidth, kMaxHeight) +
    fw::BadPixelStage::storage_pixels(kMaxWidth, kMaxHeight) + 64 * std::size_t{kMaxWidth};
fw::Pixel g_arena[kArenaPixels];
std::uint8_t g_frame_bytes[std::size_t{kMaxWidth} * kMaxHeight * 2];
fw::Pixel g_in_line[kMaxWidth];
std::uint8_t g_out_bytes[std::size_t{kMaxWidth} * 2];

// Writes each corrected line to a file descriptor as little-endian uint16.
class FdSink final : public fw::LineSink {
 public:
  explicit FdSink(int fd) : fd_(fd) {}
  void begin_frame(const fw::FrameHeader&) override {}
  void push_line(std::uint32_t, fw::LineView line) override {
    for (std::size_t x = 0; x < line.size(); ++x) {
      bytes_[2 * x] = static_cast<std::uint8_t>(line[x] & 0xFF);
      bytes_[2 * x + 1] = static_cast<std::uint8_t>(line[x] >> 8);
    }
    std::size_t done = 0;
    while (done < line.size() * 2 && ok) {
      const ssize_t n = ::write(fd_, bytes_ + done, line.size() * 2 - done);
      if (n > 0) done += static_cast<std::size_t>(n);
      else if (errno != EINTR) ok = false;
    }
  }
  void end_frame() override {}
  bool ok = true;

 private:
  int fd_;
  std::uint8_t* bytes_ = g_out_bytes;  // a line, at most kMaxWidth pixels
};

bool parse(const char* text, std::uint32_t& out) {
  char* end = nullptr;
  errno = 0;
  const unsigned long v = std::strtoul(text, &end, 10);
  if (errno != 0 || end == text || *end != '\0' || v > 0xFFFFFFFFul) return false;
  out = static_cast<std::uint32_t>(v);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::uint32_t v[7] = {0, 0, 0, 0, 0, 0, 0};
  const char* names[7] = {"WIDTH", "HEIGHT", "TAU_H_US", "TAU_C_US", "EXPOSURE_US", "READOUT_US", "PERIOD_US"};
  if (argc < 7 || argc > 8) {
    std::fprintf(stderr,
                 "usage: %s WIDTH HEIGHT TAU_H_US TAU_C_US EXPOSURE_US READOUT_US [PERIOD_US] < in.y16 > out.y16\n",
                 argv[0]);
    return 2;
  }
  for (int i = 1; i < argc; ++i)
    if (!parse(argv[i], v[i - 1]) || (i <= 6 && v[i - 1] == 0) || v[i - 1] > 4'000'000) {
      std::fprintf(stderr, "correct_stream: %s: expected a positive whole number up to 4000000, got '%s'\n",
                   names[i - 1], argv[i]);
      return 2;
    }
  const std::uint32_t width = v[0], height = v[1];
  if (width > kMaxWidth || height > kMaxHeight) {
    std::fprintf(stderr, "correct_stream: WIDTH/HEIGHT: at most %u x %u (this build's BOLO_MAX_WIDTH/HEIGHT)\n",
                 kMaxWidth, kMaxHeight);
    return 2;
  }

  fw::PipelineConfig cfg;
  cfg.corrector.width = width;
  cfg.corrector.height = height;
  cfg.corrector.tau = {v[2] * 1000u, v[3] * 1000u};
  cfg.use_bad_pixels = true;
  hal::RawStreamConfig raw{width, height, 16, v[6] * 1000u, v[4] * 1000u, v[5] * 1000u};

  const std::size_t arena_pixels = fw::Pipeline::arena_pixels(cfg);
  if (arena_pixels > kArenaPixels) {
    std::fprintf(stderr, "correct_stream: %u x %u needs %zu arena pixels, this build has %zu\n", width,
                 height, arena_pixels, kArenaPixels);
    return 2;
  }
  FdSink sink(STDOUT_FILENO);
  fw::Pipeline pipeline(cfg, std::span(g_arena, arena_pixels), sink);
  hal::RawStreamSource source(STDIN_FILENO, raw, g_frame_bytes, g_in_line);

  while (sink.ok && source.stream_frame(pipeline.input()) == hal::StreamStatus::frame) {
  }
  const fw::CorrectorTotals& t = pipeline.corrector().totals();
  const hal::SourceStats s = source.stats();
  std::fprintf(stderr, "correct_stream: %llu frames, %llu with carry-over, %llu short transfers\n",
               static_cast<unsigned long long>(t.frames),
               static_cast<unsigned long long>(t.by_reason[static_cast<int>(fw::CarryOver::applied)]),
               static_cast<unsigned long long>(s.short_transfers));
  if (!sink.ok) {
    std::fprintf(stderr, "correct_stream: writing to stdout failed\n");
    return 1;
  }
  return 0;
}

// HIL reader of `bolo run --sink v4l2:`: the v4l2loopback node's capture side through the
// project's V4l2Source. Every frame read must equal, bit for bit, a frame of the expected
// recording (`bolo correct` of what the camera sent), in the recording's order: frames the reader
// came too late for are skipped (counted), none may be changed or reordered.
//
//   hil_loopback_reader --device /dev/videoN --expected REC --min-frames N [--idle-ms MS]
//
// Reads until no frame came for --idle-ms (3000) after the first one; passes when at least N
// frames were read and every one matched.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "bolo/core/frame_collector.hpp"
#include "bolo/hal/v4l2_source.hpp"
#include "bolo/recording/recording.hpp"

namespace {

using Clock = std::chrono::steady_clock;

struct Options {
  std::string device, expected;
  std::uint64_t min_frames = 1;
  int idle_ms = 3000;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) throw std::runtime_error(a + ": needs a value");
    const std::string v = argv[++i];
    if (a == "--device") o.device = v;
    else if (a == "--expected") o.expected = v;
    else if (a == "--min-frames") o.min_frames = std::stoull(v);
    else if (a == "--idle-ms") o.idle_ms = std::stoi(v);
    else throw std::runtime_error(a + ": unknown option");
  }
  if (o.device.empty() || o.expected.empty()) throw std::runtime_error("--device and --expected are required");
  return o;
}

// The capture side offers a format only once the writer has set one: retried for 20 s.
std::unique_ptr<bolo::hal::V4l2Source> open_capture(const Options& o, std::uint32_t width, std::uint32_t height) {
  const auto until = Clock::now() + std::chrono::seconds(20);
  for (;;) {
    try {
      return std::make_unique<bolo::hal::V4l2Source>(bolo::hal::V4l2Config{
          .path = o.device, .width = width, .height = height, .telemetry = bolo::hal::TelemetryRows::off});
    } catch (const std::exception& e) {
      if (Clock::now() > until) throw;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    bolo::rec::Recording expected(o.expected);
    const std::uint32_t width = expected.width(), height = expected.height();
    std::vector<std::vector<std::uint16_t>> frames(expected.frame_count());
    for (std::uint64_t i = 0; i < frames.size(); ++i) {
      frames[i].resize(std::size_t{width} * height);
      expected.read_frame(i, frames[i]);
    }
    const std::unique_ptr<bolo::hal::V4l2Source> source = open_capture(o, width, height);
    std::vector<std::uint16_t> storage(bolo::fw::FrameCollector::storage_pixels(width, height));
    bolo::fw::FrameCollector got(width, height, storage);
    std::uint64_t read = 0, next = 0, skipped = 0, repeated = 0, faults = 0, first = 0;
    Clock::time_point last = Clock::now();
    while (Clock::now() - last < std::chrono::milliseconds(read == 0 ? 30000 : o.idle_ms)) {
      const bolo::hal::StreamStatus s = source->stream_frame(got);
      if (s == bolo::hal::StreamStatus::end_of_stream) break;
      if (s != bolo::hal::StreamStatus::frame || !got.complete()) {
        ++faults;
        continue;
      }
      last = Clock::now();
      const auto pixels = got.pixels().first(frames.front().size());
      const auto equal = [&](std::uint64_t k) { return std::equal(pixels.begin(), pixels.end(), frames[k].begin()); };
      if (next > 0 && equal(next - 1)) {  // the same frame handed out again
        ++repeated;
        continue;
      }
      std::uint64_t k = next;
      while (k < frames.size() && !equal(k)) ++k;
      if (k == frames.size()) {
        std::printf("loopback: frame %llu read (after expected frame %llu) equals no later expected frame\n",
                    static_cast<unsigned long long>(read), static_cast<unsigned long long>(next));
        return 1;
      }
      if (read == 0)
        first = k;
      else
        skipped += k - next;
      next = k + 1;
      ++read;
    }
    std::printf("loopback: %llu frames read, each equal to the expected frame (expected %llu..%llu, %llu skipped "
                "between, %llu repeats, %llu faults)\n",
                static_cast<unsigned long long>(read), static_cast<unsigned long long>(first),
                static_cast<unsigned long long>(next == 0 ? 0 : next - 1), static_cast<unsigned long long>(skipped),
                static_cast<unsigned long long>(repeated), static_cast<unsigned long long>(faults));
    return read >= o.min_frames ? 0 : 1;
  } catch (const std::exception& e) {
    std::printf("hil_loopback_reader: %s\n", e.what());
    return 2;
  }
}

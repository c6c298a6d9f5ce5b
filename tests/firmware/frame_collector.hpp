#pragma once
// Test sinks: collect the lines a pipeline emits into whole frames, and note the order of events.

#include <cstdint>
#include <vector>

#include "bolo/core/frame_collector.hpp"
#include "bolo/core/line_sink.hpp"

namespace bolo::test {

// The core's FrameCollector with storage of its own, and a running FNV-1a hash of every pixel of
// every line pushed (up to the collector's width; rows past the frame are only hashed).
class HashingCollector final : public fw::LineSink {
 public:
  HashingCollector(std::uint32_t width, std::uint32_t height)
      : width_(width),
        frame_(fw::FrameCollector::storage_pixels(width, height)),
        collector_(width, height, frame_) {}
  void begin_frame(const fw::FrameHeader& header) override { collector_.begin_frame(header); }
  void push_line(std::uint32_t row, fw::LineView line) override {
    for (std::size_t x = 0; x < line.size() && x < width_; ++x) hash_pixel(line[x]);
    collector_.push_line(row, line);
  }
  void end_frame() override { collector_.end_frame(); }

  const std::vector<fw::Pixel>& frame() const { return frame_; }
  const fw::FrameHeader& header() const { return collector_.header(); }
  std::uint64_t frames() const { return collector_.frames(); }
  std::uint32_t lines() const { return collector_.lines(); }
  std::uint32_t last_row() const { return collector_.last_row(); }
  std::uint64_t hash() const { return hash_; }

 private:
  void hash_pixel(fw::Pixel v) {
    for (int byte = 0; byte < 2; ++byte) {  // little-endian bytes, whatever the host
      hash_ ^= static_cast<std::uint8_t>(v >> (8 * byte));
      hash_ *= 0x100000001b3ull;
    }
  }
  std::uint32_t width_;
  std::vector<fw::Pixel> frame_;
  fw::FrameCollector collector_;
  std::uint64_t hash_ = 0xcbf29ce484222325ull;
};

// splitmix64: a tiny deterministic generator, identical on every target.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  std::uint32_t below(std::uint32_t n) { return static_cast<std::uint32_t>(next() % n); }

 private:
  std::uint64_t state_;
};

// Pushes a whole frame held in memory into a sink, line by line.
inline void push_frame(fw::LineSink& sink, const fw::FrameHeader& header,
                       const std::vector<fw::Pixel>& pixels) {
  sink.begin_frame(header);
  for (std::uint32_t row = 0; row < header.height; ++row)
    sink.push_line(row, fw::LineView(pixels.data() + std::size_t{row} * header.width, header.width));
  sink.end_frame();
}

}  // namespace bolo::test

#pragma once
// The one frame-collecting sink: keeps the last frame pushed into it, with its header, in
// caller-provided storage, for whatever comes after the pipeline (a writer, the VO, a test).
// Board-safe: nothing allocates.

#include <cstddef>
#include <cstdint>
#include <span>

#include "bolo/core/line_sink.hpp"

namespace bolo::fw {

class FrameCollector final : public LineSink {
 public:
  static constexpr std::size_t storage_pixels(std::uint32_t width, std::uint32_t height) {
    return std::size_t{width} * height;
  }
  // `storage` must hold storage_pixels(width, height) pixels and outlive the collector.
  FrameCollector(std::uint32_t width, std::uint32_t height, std::span<Pixel> storage);

  void begin_frame(const FrameHeader& header) override;
  // Keeps a line's first `width` pixels at its row; a row past the frame is only counted.
  void push_line(std::uint32_t row, LineView line) override;
  void end_frame() override { ++frames_; }

  // The last frame had this size and brought rows 0..height-1 once each, in order, `width` wide.
  bool complete() const { return intact_ && lines_ == height_; }
  std::span<const Pixel> pixels() const { return storage_; }
  const FrameHeader& header() const { return header_; }
  std::uint64_t frames() const { return frames_; }      // end_frame calls so far
  std::uint32_t lines() const { return lines_; }        // lines of the last frame
  std::uint32_t last_row() const { return last_row_; }  // row of the last line

 private:
  std::uint32_t width_, height_;
  std::span<Pixel> storage_;
  FrameHeader header_{};
  std::uint32_t lines_ = 0;
  std::uint32_t last_row_ = 0;
  std::uint64_t frames_ = 0;
  bool intact_ = false;
};

}  // namespace bolo::fw

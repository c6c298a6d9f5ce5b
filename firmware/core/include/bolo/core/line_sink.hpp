#pragma once
// The one interface data flows through: a frame is begin_frame, `height` lines in row order,
// end_frame. Sources push into the first stage; every stage pushes into the next.

#include <cstddef>
#include <cstdint>
#include <span>

#include "bolo/core/frame_header.hpp"

namespace bolo::fw {

using Pixel = std::uint16_t;
using LineView = std::span<const Pixel>;

class LineSink {
 public:
  virtual void begin_frame(const FrameHeader& header) = 0;
  // `line.size()` equals the frame's width; rows arrive as 0, 1, ..., height-1.
  virtual void push_line(std::uint32_t row, LineView line) = 0;
  // Rows first_row, first_row + 1, ..., first_row + count - 1 at once, row i at
  // pixels + i * stride, each `width` pixels: by definition the same as that many push_line calls
  // in order, which is all this default does. A source holding a whole frame pushes runs so a
  // stage that overrides this pays its per-call costs once per run instead of once per line.
  virtual void push_lines(std::uint32_t first_row, std::uint32_t count, const Pixel* pixels,
                          std::size_t width, std::size_t stride) {
    for (std::uint32_t i = 0; i < count; ++i)
      push_line(first_row + i, LineView(pixels + i * stride, width));
  }
  virtual void end_frame() = 0;

 protected:
  ~LineSink() = default;
};

}  // namespace bolo::fw

#pragma once
// The one interface data flows through: a frame is begin_frame, `height` lines in row order,
// end_frame. Sources push into the first stage; every stage pushes into the next.

#include <cstdint>
#include <span>

#include "bolo/firmware/frame_header.hpp"

namespace bolo::fw {

using Pixel = std::uint16_t;
using LineView = std::span<const Pixel>;

class LineSink {
 public:
  virtual void begin_frame(const FrameHeader& header) = 0;
  // `line.size()` equals the frame's width; rows arrive as 0, 1, ..., height-1.
  virtual void push_line(std::uint32_t row, LineView line) = 0;
  virtual void end_frame() = 0;

 protected:
  ~LineSink() = default;
};

}  // namespace bolo::fw

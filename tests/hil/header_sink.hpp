#pragma once
// A sink that keeps only the last frame's header (the HIL programs that check marks, not pixels).

#include "bolo/core/frame_source.hpp"

namespace bolo::hil {

class HeaderSink final : public fw::LineSink {
 public:
  void begin_frame(const fw::FrameHeader& h) override { header = h; }
  void push_line(std::uint32_t, fw::LineView) override {}
  void end_frame() override {}
  fw::FrameHeader header;
};

}  // namespace bolo::hil
